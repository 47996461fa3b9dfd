#pragma once
// Quills first: the calami that leave a region's vane, and a shingled row (feathers
// over each other like roof tiles, every quill bare at the base) cut into one
// feather per quill (quills.cpp; docs/analysis.md, "Shingled rows"). One stage of
// photo analysis, private to analysis/src; working pixels.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "segmentation.h"

namespace plumage::analysis {

// A stem that leaves the vane: what a disc a quarter of the region's widest
// inscribed radius across cannot enter, long, narrow, straight and of even width.
struct Quill {
  cv::Point2d free_end;  // the calamus end
  cv::Point2d base;      // where the stem enters the vane
  double length_px = 0, width_px = 0;
  cv::Point2d dir() const;  // unit, from the free end toward the vane
};
// The region's quills, in no particular order.
std::vector<Quill> find_quills(const Component& region);
// The largest set of quills that point the same way (each within
// kMaxRowSpread of their mean direction): the quills of a row; a stem at the
// other end (a rachis poking out past the tip) is not another feather's quill.
std::vector<Quill> quills_of_a_row(const std::vector<Quill>& quills);

// A region holding a row of quills, cut into one piece per quill: each pixel
// goes to the quill whose line (the quill and its continuation into the vane) is
// nearest, so each piece is the strip of the row around its own rachis; its
// base_px is the quill's free end, and `row_rest` marks where it meets the
// others (its vane is hidden there). Empty pieces and a reason in `why` when
// the row cannot be followed (a piece too small, or cut in two).
struct RowSplit {
  std::vector<Component> pieces;  // in the order of the quills along the row
  std::string why;
};
RowSplit split_by_quills(const Component& region, std::vector<Quill> quills, const cv::Size& image);

}  // namespace plumage::analysis
