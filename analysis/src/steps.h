#pragma once
// The stages of photo analysis, private to analysis/src (OpenCV types).
// All pixel figures here are in working pixels (the photo after any downscale).
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "plumage/common/bspline.h"
#include "plumage/layout/layout.h"

namespace plumage::analysis {

// Rec. 601 luma of an sRGB-encoded BGR pixel (0-255 for 8 bit): OpenCV's grey,
// on encoded values, which the analysis thresholds are set in.
template <typename Pixel>
double luma_bgr(const Pixel& p) {
  return 0.114 * p[0] + 0.587 * p[1] + 0.299 * p[2];
}

// photo.cpp -------------------------------------------------------------------
struct Photo {
  cv::Mat bgr;  // 8-bit BGR, working resolution
  int full_width = 0, full_height = 0;
  double downscale = 1.0;  // working pixels per photo pixel
  std::vector<std::string> notes;
};
// Reads PNG/JPEG/TIFF/PNM..., 8 or 16 bit, grey, grey+alpha, RGB, RGBA.
Photo load_photo(const std::filesystem::path& path, double max_megapixels,
                 double refuse_megapixels);
// Width and height from a PNG or JPEG header without decoding; {0,0} if unknown.
cv::Size peek_image_size(const std::filesystem::path& path);

// peaks.cpp -------------------------------------------------------------------
// A local maximum of a profile (v[i] >= v[i-1] and v[i] > v[i+1]) and its
// prominence: how far it stands above the higher of the lowest points reached on
// either side before the profile rises above it again (the ends count as such;
// going back, a maximum of equal height counts as higher, so tied maxima on a
// rippled plateau make one peak).
struct Peak {
  int at;
  double prominence;
};
std::vector<Peak> profile_peaks(const std::vector<double>& v);

// segmentation.cpp ------------------------------------------------------------
struct Component {
  cv::Rect bbox;                   // in the working image
  cv::Mat mask;                    // CV_8U 0/255, bbox-sized
  std::vector<cv::Point> contour;  // working image coordinates
  double area = 0;
  bool touches_border = false;
  // Two or more feathers that touch or overlap and were not told apart (the
  // blob's distance-transform core falls apart into several pieces).
  bool unseparated = false;
  int cores = 1;        // pieces of the distance-transform core
  double solidity = 1;  // area / convex hull area
  // > 0: this feather was cut out of a blob of that many touching feathers
  // (segmentation.cpp, separate); its vane may be clipped where they overlapped.
  int separated_from = 0;
  // > 0: faint pieces (patches of grey down above the threshold) that join
  // below it, reported as several feathers (segmentation.cpp, join_faint_pieces).
  int faint_pieces = 0;
  // Where this feather's base lies (working image coordinates), when the cut
  // that made it says so: feathers in a row join at their bases
  // (segmentation.cpp, split_faint_row). The shaft tracer then takes the end
  // nearer it for the calamus.
  std::optional<cv::Point2d> base_px;
};
struct Segmentation {
  bool dark_background = false;
  cv::Vec3d background_bgr;         // median border colour
  double threshold = 0;             // on the colour distance to the background
  cv::Mat foreground;               // CV_8U, everything above threshold (before filtering)
  std::vector<Component> feathers;  // sorted left to right
};
Segmentation segment_feathers(const cv::Mat& bgr);

// grid_scale.cpp --------------------------------------------------------------
struct GridScale {
  bool found = false;
  double period_px = 0;  // working pixels between grid lines
  double confidence = 0;
};
GridScale detect_grid(const cv::Mat& bgr, const cv::Mat& feather_mask);

// shaft.cpp -------------------------------------------------------------------
inline constexpr int kMinRowTips = 6;
// A region at least kMinAcrossAspect times as long as it is wide whose coarse
// lines run along its length by a share under kMaxLinesAlong (weighted mean
// cos^2; an isotropic texture gives 1/2), both at 1 px and with the picture
// blurred by kAlongBlur of its widest row, and then under kMaxRimAlong along its
// rim, is a row of feathers side by side (shaft.cpp, share_along_axis).
inline constexpr double kMinAcrossAspect = 1.3, kAlongBlur = 0.02, kMaxLinesAlong = 0.33, kMaxRimAlong = 0.6;
struct Shaft {
  std::vector<cv::Point2d> path;  // calamus to tip, working pixels
  double width_px = 0;            // at the calamus
  double confidence = 0;
  double seen = 0;  // share of the path's rows where the rachis was seen as a ridge
  // 2: two quills leave the calamus end side by side (two feathers with
  // overlapping vanes, one blob); then nothing else is traced.
  int quills = 1;
  // Tips standing out along the mask's more lobed side (1-4 on the photos'
  // feathers); kMinRowTips or more: a row of feathers side by side on a string,
  // one blob; then nothing else is traced either.
  int tips = 1;
  // > 0: the region's lines fan out from one point over this many degrees (a
  // spread wing or tail, one blob); then nothing else is traced either.
  double fan_deg = 0;
  // How much of the region's coarse lines (edges, rachises, colour bands) run
  // along its long axis: at 1 px over the region, and where that is under
  // kMaxLinesAlong, at kAlongBlur over the region and along its rim; 1 for a
  // region not kMinAcrossAspect times as long as wide. Under kMaxLinesAlong and
  // kMaxRimAlong: a row of feathers side by side whose tips do not stand out
  // (downy plumes on a string, each across the string), one blob; then nothing
  // else is traced either.
  double lines_along = 1, rim_along = 1;
  bool lines_across() const { return lines_along < kMaxLinesAlong && rim_along < kMaxRimAlong; }
  // Two quills, a row's tips or lines, or a fan: the region holds several feathers, and
  // why, for its warning ("is several feathers that lie side by side ..."); empty for one.
  bool several_feathers() const {
    return quills > 1 || tips >= kMinRowTips || fan_deg > 0 || lines_across();
  }
  std::string several_feathers_why() const;
};
Shaft trace_shaft(const cv::Mat& bgr, const Component& feather);
// Least-squares uniform cubic B-spline through ordered points, ends clamped.
BSpline2 fit_spline(const std::vector<glm::dvec2>& points, int num_control_points);
double spline_length(const BSpline2& c);

// vane.cpp --------------------------------------------------------------------
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
inline constexpr double kDownyTexture = 0.5;
void find_downy_base(SideMeasure& side, const std::vector<double>& t, double period_px);

// albedo.cpp ------------------------------------------------------------------
// Texture in feather coordinates, shaft painted out; linear RGBA.
struct AlbedoResult {
  cv::Mat rgba;  // CV_32FC4 linear, alpha = mask; times `scale` the albedo
  glm::dvec2 origin_mm{0.0};
  double mm_per_texel = 0;
  double scale = 1.0;  // > 1 where the feather is paler than the paper (AlbedoTexture::scale)
  std::vector<glm::dvec3> shaft_rgb;  // the rachis's own colour along it (AlbedoTexture::shaft_rgb)
};
AlbedoResult extract_albedo(const cv::Mat& bgr, const Component& feather,
                            const glm::dmat3x2& image_from_feather_work, const BSpline2& shaft_mm,
                            double shaft_width_mm, double mm_per_work_px, bool light_background,
                            const cv::Vec3d& background_bgr);

// overlay.cpp -----------------------------------------------------------------
struct OverlayFeather {
  int id = 1;
  std::vector<cv::Point> contour;
  BSpline2 shaft_px;  // working pixels
  VaneMeasure vanes;
  double length_mm = 0;
  bool touches_border = false;
};
// A region found but not analysed (SkippedRegion): outlined and labelled with why.
struct OverlaySkipped {
  int id = 1;
  std::vector<cv::Point> contour;
  bool touches_border = false;  // else: feathers that could not be separated
};
cv::Mat draw_overlay(const cv::Mat& bgr, const std::vector<OverlayFeather>& feathers,
                     const std::vector<OverlaySkipped>& skipped, double mm_per_work_px,
                     const LayoutScale& scale, const GridScale& grid, const cv::Mat& busy);

}  // namespace plumage::analysis
