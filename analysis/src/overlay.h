#pragma once
// The overlay a person checks the analysis with (overlay.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <vector>

#include "plumage/common/bspline.h"
#include "plumage/layout/layout.h"
#include "grid_scale.h"
#include "vane.h"

namespace plumage::analysis {

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
