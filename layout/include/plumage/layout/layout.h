#pragma once
// FeatherLayout: what photo analysis found about each feather, in the units the
// generator builds from (DESIGN §3, §8). Stored as layout.json; the format is
// documented in docs/layout-format.md. This header has no OpenCV in it.
#include <cstddef>
#include <array>
#include <filesystem>
#include <optional>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "plumage/common/bspline.h"

namespace plumage {

// Where the millimetres-per-pixel figure came from.
enum class ScaleSource { Given, Grid, Default };
const char* to_string(ScaleSource s);

struct LayoutScale {
  double mm_per_px = 0.1;  // in the photo's own (full-resolution) pixels
  ScaleSource source = ScaleSource::Default;
  double confidence = 0.0;    // 0..1
  double grid_period_px = 0;  // detected grid line period, 0 when none
  double grid_mm = 0;         // the physical grid spacing assumed for it
};

// A profile sampled at stations along the shaft: t is the fraction of shaft arc
// length from the calamus (0) to the tip (1).
struct VaneProfile {
  std::vector<double> width_mm, width_confidence;
  // Angle between the barb (pointing away from the shaft) and the shaft tangent
  // toward the tip, in degrees (0..180; typical feathers 20..70).
  std::vector<double> barb_angle_deg, barb_angle_confidence;
  // Distance between neighbouring barb roots measured along the shaft.
  std::vector<double> barb_spacing_mm, barb_spacing_confidence;
  // The side's downy base (docs/analysis.md, "Downy base"): below this shaft
  // fraction its barbs are loose and fluffy (plumulaceous), not an interlocked
  // vane; 0 when there is none. Its barb angles and spacing are not the vane's.
  double afterfeather_to_t = 0;
  // The share of the side's vane where the card shows between its barbs
  // (docs/analysis.md, "Plumes: an open vane"); both sides open make the feather a
  // plume, downy from base to tip (afterfeather_to_t 1).
  double open_share = 0;
  // 1 at a station where the side's edge is another feather of its shingled row
  // (hidden under it, or cut from it along the quills), else 0; empty when the
  // feather is no row's. There the width is what shows, a lower bound, and its
  // confidence is 0, so the generator's prior builds it (docs/analysis.md,
  // "Shingled rows").
  std::vector<double> width_hidden;
};

struct AlbedoTexture {
  std::string file;  // PNG next to layout.json (relative name)
  int width_px = 0, height_px = 0;
  glm::dvec2 origin_mm{0.0};  // feather coordinates of the texture's top-left corner
  double mm_per_texel = 0.0;  // texel (i,j) centre: origin + ((i+.5)s, -(j+.5)s)
  // A texel times `scale` is the albedo: above 1 where a feather on a light backdrop
  // is paler than the paper (the texture stores [0, 1]); in [1, kMaxAlbedoScale].
  double scale = 1.0;
  // The rachis's own colour (linear RGB, over the paper as the texture is; each in
  // [0, kMaxAlbedoScale]), read before the shaft is painted out of the texture: at
  // evenly spaced stations along the shaft from its base (Albedo::shaft), or one
  // colour for the whole shaft; empty when too few texels show it.
  std::vector<glm::dvec3> shaft_rgb;
};

// The most stations one feather's layout may have (the reader refuses more).
inline constexpr std::size_t kMaxLayoutStations = 4096;

// The rachis a layout's feather is built with narrows from shaft_width_mm at the
// calamus to this fraction of it at the tip (layout_to_params); the albedo texture
// paints out the same band.
inline constexpr double kShaftTipRadiusFraction = 0.15;
// The built rachis's width at shaft parameter t (0 at the calamus, 1 at the tip) as a
// fraction of its width at the calamus: it narrows linearly (builder.cpp).
inline double rachis_width_fraction(double t) { return 1.0 - (1.0 - kShaftTipRadiusFraction) * t; }

struct FeatherLayout {
  int id = 1;                          // 1-based, as labelled on the overlay
  std::array<int, 4> bbox_px{};        // mask bounding box x, y, w, h (photo pixels)
  std::vector<glm::dvec2> outline_px;  // closed polygon, photo pixels
  // Feather coordinates (mm, DESIGN §3: calamus at the origin, tip along +Y,
  // dorsal side toward the viewer) from photo pixels: f = A * (u, v, 1).
  glm::dmat3x2 feather_from_image{1.0};  // glm: 3 columns of 2 rows
  glm::dmat3x2 image_from_feather{1.0};
  BSpline2 shaft_mm;            // calamus (t=0) to tip (t=1), feather coords
  double length_mm = 0.0;       // shaft arc length
  double shaft_width_mm = 0.0;  // at the calamus
  double shaft_confidence = 0.0;
  // Share of the shaft's length that the analysis saw as a ridge (the rachis
  // itself); the rest was inferred (the barbs' chevron, the smoothness prior).
  double shaft_seen = 0.0;
  std::vector<double> stations_t;  // shared by both sides
  VaneProfile left, right;         // seen from the dorsal side, tip up
  AlbedoTexture albedo;
  bool touches_border = false;
  // One of a shingled row of `row.feathers` feathers that the analysis found as
  // one region (id `row.region`, listed under skipped as "split_row") and cut
  // into one feather per quill; 0 and 0 for a feather of its own.
  struct Row {
    int region = 0, feathers = 0;
  } row;
  std::vector<std::string> warnings;
};

// A region of the photo that was found but not analysed: a feather touching the
// border (it may be cut off) or a blob of feathers that touch or overlap and
// could not be told apart. It keeps its id, so the numbering on the overlay and
// for --feather is the same with or without it.
struct SkippedRegion {
  int id = 1;
  std::array<int, 4> bbox_px{};  // x, y, w, h (photo pixels)
  std::string reason;            // "touches_border", "unseparated" or "split_row"
  std::string message;           // for a person: what was seen and what to do
};

struct Layout {
  std::string source_image;               // the photo's path as given
  int image_width = 0, image_height = 0;  // full resolution
  double analysis_downscale = 1.0;        // working pixels per photo pixel (<= 1)
  std::string background;                 // "light" or "dark"
  LayoutScale scale;
  std::vector<FeatherLayout> feathers;
  std::vector<SkippedRegion> skipped;  // in id order
};

// How far a shaft bends in an S: the largest distance of the curve from the
// parabola fitted to it by least squares (in the frame of its chord, calamus to
// tip, 513 points evenly spaced in t), as a fraction of its arc length. A straight
// shaft or a simple arc gives about 0; docs/analysis.md, "The rachis".
double shaft_s_ness(const BSpline2& shaft);

// Maps a point with a 2x3 affine matrix.
inline glm::dvec2 apply(const glm::dmat3x2& A, const glm::dvec2& p) {
  return A * glm::dvec3(p, 1.0);
}

// JSON text of a layout (pretty-printed), and back. `parse_layout` validates
// strictly and throws plumage::Error naming `source` and, for syntax errors,
// line:column; for content errors the JSON path (e.g. /feathers/0/shaft).
std::string layout_to_json(const Layout& layout);
Layout parse_layout(const std::string& text, const std::string& source);
Layout read_layout(const std::filesystem::path& path);
// Writes atomically (plumage::write_file_atomic).
void write_layout(const std::filesystem::path& path, const Layout& layout);

}  // namespace plumage
