#pragma once
// Rows of faint feathers (grey down on a grey card): patches that clear the
// threshold joined into the region they lie in, cut along its row into feathers
// or reported as several (rows.cpp says how and where the levels were set). One
// stage of photo analysis, private to analysis/src; working pixels.
#include <opencv2/core.hpp>
#include <vector>

#include "segmentation.h"

namespace plumage::analysis {

void join_faint_pieces(std::vector<Component>& feathers, const cv::Mat& dist, double threshold,
                       double half_level, const cv::Mat& open_k, const cv::Size& image, double min_area);

}  // namespace plumage::analysis
