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
#include "plumage/generator/analysis/layout.h"
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

// Measurements with confidence below this are not trusted (docs/layout-format.md).
inline constexpr double kLayoutMinConfidence = 0.5;

// Barb spacing along the rachis (mm, each side) assumed for a feather of this
// shaft length when the photo does not resolve its barbs (docs/analysis.md,
// "Barb density": 0.25 mm + 0.2 % of the length, within [0.25, 0.75] mm).
double barb_spacing_prior_mm(double length_mm);

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
