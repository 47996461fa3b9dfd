#pragma once
// How closely a render reproduces the photographed feather it was made from,
// measured on panels that overlay pixel for pixel (photo_view.h): silhouette IoU
// and colour difference (CIE ΔE 2000), for the whole feather and per vane.
// Every metric is defined in docs/analysis.md, "Fidelity".
#include <functional>
#include <optional>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "plumage/common/image.h"

namespace plumage {

struct FidelitySettings {
  float blur_sigma_px = 1.0f;  // Gaussian blur of every panel before anything is measured
  float mask_de = 10.0f;       // a pixel is feather where it is farther than this (ΔE 2000) from its backdrop
};

// Which pixels are compared, and on which side of the shaft they lie:
// 0 = not compared (outside the picked feather's outline, dilated), 1 = left vane, 2 = right vane.
struct PanelRegions {
  int width = 0, height = 0;
  std::vector<unsigned char> side;
  unsigned char at(int x, int y) const { return side[std::size_t(y) * width + x]; }
};

// CIELAB (D65 white, reference white = linear RGB 1) of a linear sRGB colour.
glm::vec3 linear_rgb_to_lab(const glm::vec3& rgb);
// CIE ΔE 2000 (Sharma, Wu & Dalal 2005) between two CIELAB colours.
double ciede2000(const glm::vec3& lab1, const glm::vec3& lab2);
// The same between two linear sRGB colours.
double ciede2000_linear_rgb(const glm::vec3& rgb1, const glm::vec3& rgb2);

// Per-channel median of the image's outermost `depth` rings of pixels, over those
// for which keep(x, y, colour) holds; nothing when fewer than `min_count` do.
std::optional<glm::vec3> ring_median(const Image& img,
                                     const std::function<bool(int x, int y, const glm::vec3& c)>& keep,
                                     std::size_t min_count = 1, int depth = 1);

// Separable Gaussian of standard deviation `sigma` pixels (edges clamped); RGB out.
Image gaussian_blur(const Image& img, float sigma);

// One panel, ready to compare: blurred, its backdrop colour and its feather mask.
struct MeasuredPanel {
  Image blurred;                // linear RGB
  glm::vec3 backdrop{0};        // the given one, or the per-channel median of the outermost pixel ring (compared pixels left out)
  std::vector<char> feather;    // 1 = feather (only where the region is compared), holes filled
};
MeasuredPanel measure_panel(const Image& panel, const PanelRegions& regions, const FidelitySettings& settings,
                            std::optional<glm::vec3> backdrop = std::nullopt);

// The mean of `img` (linear RGB) over the pixels where `mask` is 1 (0 when none
// is): VaneFidelity's photo_mean and render_mean, summed the same way.
glm::vec3 mean_over_mask(const Image& img, const std::vector<char>& mask);

struct VaneFidelity {
  double iou = 0;                  // |photo ∩ render| / |photo ∪ render| over the feather masks
  int photo_pixels = 0, render_pixels = 0;
  glm::vec3 photo_mean{0}, render_mean{0};  // mean linear RGB inside the photo's feather mask
  double mean_colour_de2000 = 0;   // ΔE 2000 between those two means
  double pixel_de2000 = 0;         // mean over the photo's mask of the pixel-by-pixel ΔE 2000
  // Pearson correlation of the photo's and the render's luminance over the photo's
  // mask shrunk by 3 pixels (its blurred rim left out): the pattern (bars, the shaft,
  // light and shade) whatever the overall colour; 0 where the mask has no inside.
  double luminance_correlation = 0;
};

struct RenderFidelity {
  VaneFidelity feather, left, right;
  double backdrop_de2000 = 0;  // between the render's backdrop colour and the photo's
  // The render's feather-mask perimeter over the photo's: mask pixels with a
  // 4-neighbour outside the mask (or the compared region), counted in each. 1 for
  // an outline as smooth as the photo's; a saw-tooth edge raises it.
  double perimeter_ratio = 0;
};

// The pixels of `mask` (compared ones only) with a 4-neighbour outside it.
long mask_perimeter(const std::vector<char>& mask, const PanelRegions& regions);

// `render` against `photo` (both measured with the same settings and regions).
RenderFidelity compare_panels(const MeasuredPanel& photo, const MeasuredPanel& render, const PanelRegions& regions);

// The masks (white both, red photo only, cyan render only, dark neither, darker
// not compared) and the pixel ΔE 2000 (black 0 → red → yellow → white at 20 and above).
Image mask_picture(const MeasuredPanel& photo, const MeasuredPanel& render, const PanelRegions& regions);
Image difference_picture(const MeasuredPanel& photo, const MeasuredPanel& render, const PanelRegions& regions);

nlohmann::json to_json(const RenderFidelity& f);
nlohmann::json to_json(const FidelitySettings& s);

}  // namespace plumage
