#pragma once
// The vanes: widths, barb angles and spacing along the shaft, the downy base (vane.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <vector>

#include "plumage/common/bspline.h"
#include "segmentation.h"
#include "thresholds.h"

namespace plumage::analysis {

using thresholds::vane::kDownyTexture;
using thresholds::vane::kPlumeOpenShare;

struct SideMeasure {
  std::vector<double> width_px, width_conf;
  std::vector<double> angle_deg, angle_conf;
  std::vector<double> spacing_px, spacing_conf;
  // Fine texture: the RMS of the photo's grey minus its blur at the barb scale
  // over the pixels the barb angle is read from, and how many there are.
  std::vector<double> texture;
  std::vector<int> texture_px;
  // The downy base (find_downy_base): where it ends along the shaft, 0 when there
  // is none, and which stations' texture says down.
  double afterfeather_to_t = 0;
  std::vector<char> downy;
};
struct VaneMeasure {
  std::vector<double> t;
  SideMeasure left, right;  // left: the -X side in feather coordinates
};
// `shaft_px` runs calamus to tip in working pixels.
VaneMeasure measure_vanes(const cv::Mat& bgr, const Component& feather, const BSpline2& shaft_px,
                          double shaft_width_px, int stations);
// A side's downy base (docs/analysis.md, "Downy base"), for a photo that resolves
// barbs `period_px` apart: the run of stations from the base whose fine texture
// is under kDownyTexture of the vane's; sets side.downy and side.afterfeather_to_t.
void find_downy_base(SideMeasure& side, const std::vector<double>& t, double period_px);
// How open a side's vane is (docs/analysis.md, "Plumes: an open vane"): the share
// of its pixels, from kOpenFromWidth to kOpenToWidth of the measured width at each
// station, whose colour is the card's (no channel farther from `card_bgr` than
// kOpenCardSigmas x `card_sigma`, or kOpenMinLevels): the card seen between loose
// barbs. A closed vane lets it through only at splits. `side` is -1 for the left
// (-X) side, +1 for the right; 0 when the side has no width to read.
double vane_open_share(const cv::Mat& bgr, const cv::Vec3d& card_bgr, double card_sigma, const BSpline2& shaft_px,
                       const std::vector<double>& t, const SideMeasure& measure, int side);

}  // namespace plumage::analysis
