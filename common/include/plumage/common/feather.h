#pragma once
// The Feather model: what the generator builds, the curve file stores and the
// renderer draws. World units are millimetres; the feather lies in the XY plane,
// shaft from the calamus (y = 0) toward the tip (+Y), dorsal side toward +Z
// (DESIGN §3). Every curve is a uniform cubic B-spline (bspline.h).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace plumage {

// Shaft: the rachis and calamus. Barb: a pennaceous barb, drawn as a ribbon of the
// vane's width (its barbules close the vane). Down: a plumulaceous barb (down, a
// downy base, a plume): loose, thin and curling, its barbules sparse and unhooked,
// so no closed vane; drawn in every shading mode as a round tube of its own radius
// that its fibres fill to Feather::down_cover (docs/curve-format.md, "Down").
enum class CurveKind { Shaft, Barb, Down };
// The vane a barb belongs to. Seen from the dorsal side (+Z) with the tip up,
// Left barbs lie at x < 0 of the shaft and Right barbs at x > 0.
enum class VaneSide { None, Left, Right };

const char* to_string(CurveKind k);
const char* to_string(VaneSide s);

// One control point: position and radius (mm), and the vane-surface normal
// (unit; dorsal). For the shaft the normal is the dorsal direction too.
struct ControlPoint {
  glm::vec3 p{0};
  float radius = 0;
  glm::vec3 n{0, 0, 1};
  bool operator==(const ControlPoint&) const = default;
};

struct Curve {
  CurveKind kind = CurveKind::Barb;
  VaneSide side = VaneSide::None;       // None for the shaft
  float root = 0;                        // barbs: root position along the shaft, arc-length fraction in [0,1]
  std::vector<ControlPoint> points;      // >= 4 (uniform cubic B-spline)
  bool operator==(const Curve&) const = default;
};

// The substructure parameters of one vane (DESIGN §5, paper §5.3).
struct SubstructureParams {
  int barbules_per_side = 0;       // N: barbules per side of a barb, along its whole length
  float ramus_radius = 0;          // r_r (mm)
  float barbule_radius = 0;        // r_b (mm)
  float elevation_deg = 45;        // theta_b: barbule angle from the barb tangent, in the vane plane
  float azimuth_deg = 0;           // phi_b: lift of the barbule out of the vane, about b
  float hooked_fraction = 0;       // fraction of a distal barbule's length that bends (pennulum hooks)
  float ribbon_width = 0;          // W (mm): full width of the barb ribbon
  bool operator==(const SubstructureParams&) const = default;
};

// The one range check of SubstructureParams, used by the generator's validate(),
// the curve file reader and writer and the renderer: the first value out of range,
// named by its key in the curve file's substructure record (docs/curve-format.md:
// barbules, ramus_radius, barbule_radius, elevation, azimuth, hooked_fraction,
// ribbon_width), or nothing. Callers add where the value came from; only the CLI
// names its flags.
struct SubstructureProblem {
  std::string setting;  // curve-format key
  std::string problem;  // "value 0 is outside [1, 90] degrees: ..."
};
std::optional<SubstructureProblem> substructure_problem(const SubstructureParams& p);
// Below this barbule elevation (theta_b) a barbule lies along the ramus and its
// period across the ribbon vanishes.
inline constexpr float kMinBarbuleElevationDeg = 1.0f;

// The palest a feather's albedo texture may be over the paper it was photographed
// on: Albedo::scale and the layout's AlbedoTexture::scale lie in [1, this].
inline constexpr double kMaxAlbedoScale = 8.0;
// The most shaft colours one feather may have (Albedo::shaft; the reader refuses more).
inline constexpr std::size_t kMaxShaftColours = 256;
// The shaft's colour at `fraction` of its length from the root (0) to the tip (1):
// station k of n lies at (k + 1/2) / n, linear in between, the end stations' colours
// beyond them. `shaft` must not be empty.
glm::vec3 shaft_colour_at(const std::vector<glm::vec3>& shaft, float fraction);

// Where the albedo comes from: a constant linear RGB colour, or a texture image
// mapped onto the feather's XY plane by an axis-aligned rectangle (mm).
struct Albedo {
  glm::vec3 color{0.5f};                 // used when texture is empty, and as fallback
  std::string texture;                   // path, relative to the curve file's folder
  glm::vec2 rect_min{0}, rect_max{0};    // texture (0,0) at rect_min (x, y) ... (1,1) at rect_max
  float scale = 1.0f;                    // a texel times scale is the albedo (> 1: paler than the paper)
  // The shaft's own colour (rachis and calamus): one colour for the whole shaft, or
  // its colours at evenly spaced stations along its length from the root
  // (shaft_colour_at); empty: the shaft takes the texture's (or the colour).
  std::vector<glm::vec3> shaft;
  bool operator==(const Albedo&) const = default;
};

// The fibres' medulla (docs/hair-bcsdf.md, "The medulla"): a scattering core of
// radius `ratio` (fibre radii, [0, 1); 0 for none) with scattering and absorption
// coefficients per unit radius (each >= 0). The renderer's HairParams take it.
struct Medulla {
  float ratio = 0.0f;
  glm::vec3 sigma_s{0.0f}, sigma_a{0.0f};
  bool operator==(const Medulla&) const = default;
};

struct Provenance {
  std::string source;                    // "preset:osprey-covert", "photo:path.jpg", ...
  std::optional<std::uint64_t> seed;
  bool operator==(const Provenance&) const = default;
};

struct Feather {
  std::string units = "mm";
  Provenance provenance;
  Albedo albedo;
  Medulla medulla;
  SubstructureParams left, right;        // per vane
  // Down barbs (CurveKind::Down): the share of a down barb's tube (its radius the
  // reach of its barbules) that its ramus and barbules fill, in (0, 1]: a ray
  // crossing the tube's surface meets a fibre there with this probability
  // (docs/curve-format.md, "Down"). 1: an opaque fibre.
  float down_cover = 1.0f;
  std::vector<Curve> curves;             // the shaft (if any) first, then barbs

  const SubstructureParams& substructure(VaneSide s) const { return s == VaneSide::Right ? right : left; }
  SubstructureParams& substructure(VaneSide s) { return s == VaneSide::Right ? right : left; }
  const Curve* shaft() const;
  std::size_t count(CurveKind k) const;
  std::size_t count(VaneSide s) const;
  std::size_t num_control_points() const;
  bool operator==(const Feather&) const = default;
};

// The fraction of a barb's length (its control polygon's) over which its drawn
// width tapers to the barb's own radius at the tip: distal barbules shorten toward
// the barb's tip, so a vane's edge is the smooth line of the tips, not a staircase of
// square ribbon ends.
inline constexpr float kBarbTipTaper = 0.2f;

// The radius each control point of `curve` is drawn with in hair and substructure
// modes (DESIGN §4): a barb takes half its vane's ribbon width W, the same width in
// both modes (the paper: "the same curve width parameter was used for the hair and
// substructure versions"), tapering over the last kBarbTipTaper of its length
// (smoothstep in the control polygon's arc length) to its own radius; a barb of one
// B-spline segment (4 points) has no room to taper without narrowing its middle and
// stays at W/2, as does one whose polygon length is 0 or not finite. The shaft, and a barb whose vane has no W, keep their own radii. The
// renderer and the exporters draw with it.
std::vector<float> render_radii(const Feather& feather, const Curve& curve);

}  // namespace plumage
