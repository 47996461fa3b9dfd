#pragma once
// The shaft: the rachis traced from the calamus, seen and inferred (shaft.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "plumage/common/bspline.h"
#include "segmentation.h"
#include "thresholds.h"

namespace plumage::analysis {

// A region at least kMinAcrossAspect times as long as it is wide whose coarse
// lines run along its length by a share under kMaxLinesAlong (weighted mean
// cos^2; an isotropic texture gives 1/2), both at 1 px and with the picture
// blurred by kAlongBlur of its widest row, and then under kMaxRimAlong along its
// rim, is a row of feathers side by side (shaft.cpp, share_along_axis; the
// numbers are in thresholds.h, namespace thresholds::shaft).
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
  bool lines_across() const {
    return lines_along < thresholds::shaft::kMaxLinesAlong && rim_along < thresholds::shaft::kMaxRimAlong;
  }
  // Two quills, a row's tips or lines, or a fan: the region holds several feathers, and
  // why, for its warning ("is several feathers that lie side by side ..."); empty for one.
  bool several_feathers() const {
    return quills > 1 || tips >= thresholds::shaft::kMinRowTips || fan_deg > 0 || lines_across();
  }
  std::string several_feathers_why() const;
};
Shaft trace_shaft(const cv::Mat& bgr, const Component& feather);
// Least-squares uniform cubic B-spline through ordered points, ends clamped.
BSpline2 fit_spline(const std::vector<glm::dvec2>& points, int num_control_points);
double spline_length(const BSpline2& c);

}  // namespace plumage::analysis
