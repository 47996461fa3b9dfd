#pragma once
// Rows of faint feathers (grey down on a grey card): patches that clear the
// threshold joined into the region they lie in, cut along its row into feathers
// or reported as several (rows.cpp says how and where the levels were set). One
// stage of photo analysis, private to analysis/src; working pixels.
#include <opencv2/core.hpp>
#include <vector>

#include "segmentation.h"
#include "thresholds.h"

namespace plumage::analysis {

// How a row is read: the profile's smoothing (a share of the square root of the
// region's area), the least aspect of each piece, and how far a cut may lean
// (thresholds.h says where each was measured).
struct RowReading {
  double smooth = thresholds::segmentation::kRowSmooth;
  double min_aspect = thresholds::segmentation::kMinPlumeAspect;
  double max_tilt_deg = 0;  // a cut may lean this far off straight across the row
};

// A region of feathers side by side in a row (faint plumes on a band, white
// plumes on their bases) cut straight across the row between them, each piece
// with its base end when the row shows one; empty when the row cannot be told
// (rows.cpp says how). `own`: the region's pixels that stand out (bbox-sized,
// 0/255), `dist` the photo's colour distance to the card.
std::vector<Component> split_faint_row(const Component& region, const cv::Mat& own, const cv::Mat& dist,
                                       const cv::Size& image, double min_area, const RowReading& reading = {});

void join_faint_pieces(std::vector<Component>& feathers, const cv::Mat& dist, double threshold,
                       double half_level, const cv::Mat& open_k, const cv::Size& image, double min_area);

}  // namespace plumage::analysis
