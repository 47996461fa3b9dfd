#pragma once
// Peaks of a profile and their prominence (peaks.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <vector>

namespace plumage::analysis {

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

}  // namespace plumage::analysis
