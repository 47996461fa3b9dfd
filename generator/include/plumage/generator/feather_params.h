#pragma once
// Everything the procedural generator needs to build one feather, read from JSON
// (docs/generator.md lists every key, its unit and its allowed range). Lengths
// are millimetres, angles degrees; "position" means the fraction of the vane's
// length along the shaft, 0 at the end of the calamus and 1 at the tip.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "plumage/common/feather.h"
#include "plumage/generator/profile.h"
#include "plumage/layout/rules.h"  // kMinShaftLengthMm, kMaxShaftLengthMm

namespace plumage {

struct ShaftParams {
  double length = 100;          // calamus base to tip, along the shaft
  double calamus_length = 15;   // bare base without barbs
  double bend_deg = 0;          // in-plane turn of the tangent from base to tip (+ bends toward +X)
  double arch_deg = 0;          // out-of-plane turn from base to tip (+ bends the tip ventrally, -Z)
  double radius_base = 0.8;
  double radius_tip = 0.1;
  int control_points = 16;      // before the two phantom ends
  bool operator==(const ShaftParams&) const = default;
};

struct VaneParams {
  int barbs = 150;              // barbs on this side; used when barb_density is 0
  double barb_density = 0;      // barbs per mm of vane length; overrides barbs when > 0
  Profile width;                // half-width (mm, shaft to vane edge) by position
  Profile angle_deg;            // barb-shaft angle at the root by position
  double barb_bend_deg = 10;    // how far a barb turns toward the tip from root to tip
  SubstructureParams substructure;
  bool operator==(const VaneParams&) const = default;
};

struct BarbParams {
  double radius_root = 0.05;
  double radius_tip = 0.02;
  int control_points = 8;       // samples on the vane surface, before the phantom ends
  bool operator==(const BarbParams&) const = default;
};

struct SurfaceParams {
  double cupping = 0;           // vane edge depth below the shaft, as a fraction of the local width (+ = dorsally convex)
  double twist_deg = 0;         // rotation of the vane about the shaft, from vane base to tip
  int cage_columns = 24;        // Catmull-Clark control cage: columns along the shaft
  int cage_rows = 5;            //   and rows from the shaft to the vane edge
  bool operator==(const SurfaceParams&) const = default;
};

// The thinnest down barb (afterfeather.radius's lower bound, mm).
inline constexpr double kMinDownRadiusMm = 0.001;

// Loose, fluffy (plumulaceous) barbs near the base of the vane, built as down
// barbs (CurveKind::Down): round tubes of `radius` their fibres fill to `cover`, no
// ribbon, no closed vane. A fraction of 1 makes the whole feather downy (a plume).
struct AfterfeatherParams {
  bool enabled = false;
  double fraction = 0.15;       // basal fraction of the vane whose barbs are loose
  double wave = 1.0;            // in-vane waviness amplitude at the base (mm)
  double lift = 1.0;            // out-of-vane lift amplitude at the base (mm)
  double waves = 2.0;           // oscillations along a loose barb
  double radius = 0.25;         // a down barb's radius (mm): the reach of its barbules around the ramus
  double cover = 0.8;           // the share of that tube its ramus and barbules fill (Feather::down_cover)
  bool operator==(const AfterfeatherParams&) const = default;
};

// Splits: places where neighbouring barbs separate and open a gap from the edge in.
struct SplitParams {
  int count = 0;                        // splits per vane
  std::optional<std::uint64_t> seed;    // their own seed; derived from the feather seed when absent
  double gap = 1.0;                     // gap width at the vane edge (mm)
  double depth = 0.6;                   // how far in from the edge the gap reaches (fraction of width)
  bool operator==(const SplitParams&) const = default;
};

struct JitterParams {
  double angle_deg = 0;         // uniform random barb-angle offset, +-angle_deg
  double spacing = 0;           // random root offset as a fraction of the barb spacing (+-spacing/2)
  bool operator==(const JitterParams&) const = default;
};

struct FeatherParams {
  std::string name;
  std::string description;
  ShaftParams shaft;
  VaneParams left, right;
  BarbParams barb;
  SurfaceParams surface;
  AfterfeatherParams afterfeather;
  SplitParams splits;
  JitterParams jitter;
  glm::vec3 albedo{0.3f, 0.25f, 0.2f};  // linear RGB

  const VaneParams& vane(VaneSide s) const { return s == VaneSide::Right ? right : left; }
  VaneParams& vane(VaneSide s) { return s == VaneSide::Right ? right : left; }
  double vane_length() const { return shaft.length - shaft.calamus_length; }
  // Barbs on one side (barb_density resolved against the vane length).
  int barb_count(VaneSide s) const;
  bool operator==(const FeatherParams&) const = default;
};

// A plain feather that passes validate(): the defaults documented in docs/generator.md.
FeatherParams default_feather_params();

// Throws plumage::Error naming the first bad parameter, its value and its allowed
// range; `source` (a file name) is put in front when given.
void validate(const FeatherParams& p, const std::string& source = "");

// JSON <-> params. Missing keys keep default_feather_params()'s value; unknown
// keys and wrong types are errors. The result is validated.
FeatherParams params_from_json(const nlohmann::json& j, const std::string& source = "");
nlohmann::json params_to_json(const FeatherParams& p);
// Parses JSON text (syntax errors reported at FILE:LINE:COL).
FeatherParams parse_params(const std::string& text, const std::string& source = "<memory>");
FeatherParams read_params(const std::filesystem::path& path);

}  // namespace plumage
