#pragma once
// From what photo analysis measured (FeatherLayout, docs/layout-format.md) to what
// the procedural generator builds from (FeatherParams), and on to a Feather that
// sits where the analysed feather lies in feather coordinates: the curves follow
// the photo's shaft, vane widths, barb angles and spacing (DESIGN §8, issue 6).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "plumage/common/feather.h"
#include "plumage/common/image.h"
#include "plumage/layout/layout.h"
#include "plumage/layout/rules.h"
#include "plumage/generator/feather_params.h"

namespace plumage {

class FileBatch;

struct LayoutParams {
  FeatherParams params;
  // In-plane rotation (degrees, counter-clockwise about +Z) that brings the
  // generated shaft's chord onto the analysed one (+Y): the bent arc the builder
  // makes leans its chord by about half the bend.
  double chord_rotation_deg = 0;
  // Values replaced because analysis was unsure of them, for a person to read.
  std::vector<std::string> warnings;
};

// How fast a barb angle may fall along the shaft in a layout's feather: cot(theta
// at the barb's end) rises by at most kMaxFan ds / W over ds of shaft, W the
// vane's widest width, so neighbouring barbs' tips are at most about twice as far
// apart as their roots; an angle that falls faster is raised (docs/cli.md, "From a
// photo").
inline constexpr double kMaxFan = 1.0;

// A profile along the shaft from per-station readings that may include some
// that are something else (docs/analysis.md, "Barb angles along the shaft"): at
// each station a weighted local-linear regression over station position `x`
// (tricube kernel whose half-width is at least `bandwidth`, wide enough to hold
// `min_weight` of reading weight and, between readings, to reach the nearest one
// on either side), started from a weighted median over twice that window (no kernel)
// and refitted `iterations` times with Tukey's bisquare robustness weights
// B(r / (6 s)), s the weighted median |residual| but at least `min_scale`
// (Cleveland 1979, J. Am. Stat. Assoc. 74:829), so readings far off the curve
// drop out. A fitted value never leaves the range of the readings it is fitted
// from. A station without a reading (weight 0, or a non-finite position, value
// or weight) takes its neighbours' value: across a gap the line between its
// sides, past the last reading that reading's fitted value. With no weighted
// reading at all every station takes `prior` (one value per station).
struct AlongShaftOptions {
  double bandwidth = 0.12;  // in units of x (stations_t: fraction of the shaft)
  double min_weight = 1.5;
  double min_scale = 2.0;   // in units of the values
  int iterations = 3;
};
struct AlongShaftFit {
  std::vector<double> value;  // one per station
  std::vector<bool> outlier;  // a weighted reading the robust fit rejected (bisquare weight 0)
  bool from_prior = false;    // no reading had weight
};
AlongShaftFit smooth_along_shaft(const std::vector<double>& x, const std::vector<double>& value,
                                 const std::vector<double>& weight, const std::vector<double>& prior,
                                 const AlongShaftOptions& options = {});

// One vane's barb angles for the generator from analysis readings (degrees, 0..180,
// and confidences): readings under kLayoutMinConfidence, pointing back toward the
// calamus (> 90 degrees), or under kMinBarbAngleDeg away from the tip (the last
// tenth of the vane, from `calamus_t` on) are not barbs; the rest, weighted by
// confidence, go through smooth_along_shaft with the default feather's angle
// profile over the vane as the prior.
inline constexpr double kMinBarbAngleDeg = 15.0;
struct BarbAngleFit {
  std::vector<double> angle_deg;  // one per station, smoothed
  int confident = 0;              // readings with confidence >= kLayoutMinConfidence
  int backward = 0, flat = 0;     // of those: > 90 degrees, < kMinBarbAngleDeg away from the tip
  int outliers = 0;               // of the rest: rejected against their neighbours
  bool from_prior = false;
};
BarbAngleFit barb_angles_along_shaft(const std::vector<double>& t, const std::vector<double>& angle_deg,
                                     const std::vector<double>& confidence, double calamus_t);

// The gap between neighbouring barbs of one vane of a built feather: for each
// barb, the distance from the middle of its control polygon to the next barb's,
// and of those the kBarbGapQuantile quantile (mm; 0 with fewer than two barbs).
inline constexpr double kBarbGapQuantile = 0.75;
double barb_gap_mm(const Feather& feather, VaneSide side);

// Makes one vane of a built feather an intact (closed) pennaceous vane, where
// each barb's distal barbules lie over the next barb's proximal ones
// (docs/analysis.md, "Barbules"): the ribbon width W is kBarbOverlap times the
// barb gap (the ramus radius at most W / 4), and the barbules per side close
// the longest barb (closing_barbule_count). layout_to_feather does this.
inline constexpr double kBarbOverlap = 1.3;
void close_vane(Feather& feather, VaneSide side);

// Barbules per side that cover a barb of `longest_barb_mm` across the whole ribbon
// (DESIGN §5: covered when 2 r_b N / (L sin theta_b) >= 1), with kBarbuleClosure to spare.
inline constexpr double kBarbuleClosure = 1.1;
int closing_barbule_count(double longest_barb_mm, const SubstructureParams& s);

// Throws plumage::Error naming `source` (the layout file) and the bad value when
// the layout cannot describe a feather (no shaft length, stations out of order,
// profiles of the wrong length, non-finite numbers).
LayoutParams layout_to_params(const FeatherLayout& layout, const std::string& source = "layout");

// The feather with id `id`, or the first when none is given; plumage::Error
// listing the ids there are when it is not in the layout.
const FeatherLayout& pick_feather(const Layout& layout, std::optional<int> id, const std::string& source = "layout");

// Builds the feather of `layout`, rotated so its chord follows the analysed shaft,
// with the analysis albedo texture mapped by its rectangle. `albedo_dir` is the
// folder of layout.json (where the albedo PNG is) and `fcurves_dir` the folder the
// curve file will be written to: the texture path is stored relative to it.
Feather layout_to_feather(const FeatherLayout& layout, std::uint64_t seed, const std::filesystem::path& albedo_dir,
                          const std::filesystem::path& fcurves_dir, const std::string& source = "layout",
                          std::vector<std::string>* warnings = nullptr);

// The analysis albedo (RGBA, alpha = the photo's mask) made usable for rendering:
// generated barbs reach texels outside the mask, which hold the background, so
// those get the mean colour under the mask (RGB result). `mean` receives it.
Image albedo_for_render(const Image& analysis_albedo, glm::vec3* mean = nullptr);

// The mean colour of an analysis albedo under the photo's mask: texels weighted by
// their alpha (RGBA; every texel alike without alpha), in double; nothing when no
// texel is inside the mask. albedo_for_render fills with it; `plumage wing --layout`
// and a .fscene's layout feathers colour a feather by it (times the texture's scale).
std::optional<glm::dvec3> albedo_mean(const Image& analysis_albedo);

// layout_to_feather, then the filled albedo written as `texture_path` (atomically,
// or staged in `outputs` with the command's other files when given) and
// referenced by the feather relative to `fcurves_dir`, its mean as the feather's
// constant colour. What `generate --layout` and photo-to-feather use.
Feather layout_to_feather_with_albedo(const FeatherLayout& layout, std::uint64_t seed,
                                      const std::filesystem::path& albedo_dir,
                                      const std::filesystem::path& fcurves_dir,
                                      const std::filesystem::path& texture_path, const std::string& source,
                                      std::vector<std::string>* warnings = nullptr,
                                      FileBatch* outputs = nullptr);

}  // namespace plumage
