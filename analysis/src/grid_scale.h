#pragma once
// The scale from a regular grid or ruler in the photo (grid_scale.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>

namespace plumage::analysis {

struct GridScale {
  bool found = false;
  double period_px = 0;  // working pixels between grid lines
  double confidence = 0;
};
GridScale detect_grid(const cv::Mat& bgr, const cv::Mat& feather_mask);

}  // namespace plumage::analysis
