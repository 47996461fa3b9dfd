#pragma once
// Touching feathers told apart: a blob's core pieces, and the cut between them
// where two feathers barely touch (separate.cpp says how and where the levels were
// set). One stage of photo analysis, private to analysis/src; working pixels.
#include <opencv2/core.hpp>
#include <vector>

#include "segmentation.h"

namespace plumage::analysis {

// A blob's mask with a one-pixel frame of background, its distance transform and
// its core pieces (core_markers), found once and used both to count the feathers
// in the blob and to separate them.
struct Cores {
  cv::Mat mask, dt, markers;
  int n = 1;
};
Cores find_cores(const cv::Mat& blob_mask);

// The blob cut into its feathers where they barely touch, each a Component; empty
// when it is one feather or the cut would not be clean. `cores` is the blob's
// (find_cores); its markers are flooded in place.
std::vector<Component> separate(const Component& blob, Cores& cores, const cv::Size& image, double min_area);

}  // namespace plumage::analysis
