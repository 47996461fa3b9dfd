#pragma once
// Feathers told from the card: the regions, touching ones separated, rows split (segmentation.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace plumage::analysis {

struct Component {
  cv::Rect bbox;                   // in the working image
  cv::Mat mask;                    // CV_8U 0/255, bbox-sized
  std::vector<cv::Point> contour;  // working image coordinates
  double area = 0;
  bool touches_border = false;
  // Two or more feathers that touch or overlap and were not told apart (the
  // blob's distance-transform core falls apart into several pieces).
  bool unseparated = false;
  int cores = 1;        // pieces of the distance-transform core
  double solidity = 1;  // area / convex hull area
  // > 0: this feather was cut out of a blob of that many touching feathers
  // (segmentation.cpp, separate); its vane may be clipped where they overlapped.
  int separated_from = 0;
  // > 0: faint pieces (patches of grey down above the threshold) that join
  // below it, reported as several feathers (segmentation.cpp, join_faint_pieces).
  int faint_pieces = 0;
  // Where this feather's base lies (working image coordinates), when the cut
  // that made it says so: feathers in a row join at their bases
  // (segmentation.cpp, split_faint_row). The shaft tracer then takes the end
  // nearer it for the calamus.
  std::optional<cv::Point2d> base_px;
  // Where its calamus is (a white plume cut from its row, rows.cpp): the shaft
  // tracer straightens it along the line from there to the mask's farthest
  // point, the plume's own axis, instead of along its principal axis (fluff
  // spread to one side tilts that).
  std::optional<cv::Point2d> quill_px;
  // > 0: this feather is one of a shingled row of that many, cut out of its
  // region along the quills (quills.cpp, split_by_quills); `row_rest` (bbox-sized,
  // 0/255) marks the row's other feathers' pixels in this box: where they meet
  // this one, its vane is hidden under them or cut from them.
  int row_feathers = 0;
  int row_region = 0;  // the id of the region it was cut from (set by analyze_photo)
  cv::Mat row_rest;
};
struct Segmentation {
  bool dark_background = false;
  cv::Vec3d background_bgr;         // median border colour
  double threshold = 0;             // on the colour distance to the background
  double card_sigma = 0;            // the card's grain: MAD sigma of the border frame's luma
  cv::Mat foreground;               // CV_8U, everything above threshold (before filtering)
  std::vector<Component> feathers;  // sorted left to right
};
Segmentation segment_feathers(const cv::Mat& bgr);

}  // namespace plumage::analysis
