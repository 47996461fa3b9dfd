#pragma once
// Photo analysis (private to analysis/src): the grey its thresholds are set in.

namespace plumage::analysis {

// Rec. 601 luma of an sRGB-encoded BGR pixel (0-255 for 8 bit): OpenCV's grey,
// on encoded values, which the analysis thresholds are set in.
template <typename Pixel>
double luma_bgr(const Pixel& p) {
  return 0.114 * p[0] + 0.587 * p[1] + 0.299 * p[2];
}

}  // namespace plumage::analysis
