#pragma once
// Helpers on feather regions (outline, fill, shape) that the segmentation stages
// share: segmentation, separate and rows. Private to analysis/src; working pixels.
#include <opencv2/core.hpp>
#include <vector>

#include "segmentation.h"

namespace plumage::analysis {

// The outer boundary of a binary mask's largest region, in image coordinates
// (`offset`: where the mask's top-left pixel lies); empty for an empty mask.
std::vector<cv::Point> largest_contour(const cv::Mat& mask, cv::Point offset);
// The region inside `contour` (image coordinates), filled, as a mask over `box`.
cv::Mat filled(const std::vector<cv::Point>& contour, const cv::Rect& box);
// Closes the notches the background makes between barb tips at the vane's edge,
// then takes the outline and area again (regions.cpp says how).
void close_barb_gaps(Component& comp);
// A component's hull solidity and border flag, from its contour and box.
void measure_shape(Component& comp, const cv::Size& image);

}  // namespace plumage::analysis
