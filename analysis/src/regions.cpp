// Helpers on feather regions that the segmentation stages share (regions.h).
#include "regions.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "thresholds.h"

namespace plumage::analysis {
using namespace thresholds::segmentation;

// The outer boundary of a binary mask's largest region, in image coordinates
// (`offset`: where the mask's top-left pixel lies); empty for an empty mask.
std::vector<cv::Point> largest_contour(const cv::Mat& mask, cv::Point offset) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, offset);
  if (contours.empty()) return {};
  return std::move(*std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  }));
}

// The region inside `contour` (image coordinates), filled, as a mask over `box`.
cv::Mat filled(const std::vector<cv::Point>& contour, const cv::Rect& box) {
  cv::Mat m = cv::Mat::zeros(box.size(), CV_8U);
  cv::drawContours(m, std::vector<std::vector<cv::Point>>{contour}, 0, cv::Scalar(255), cv::FILLED, cv::LINE_8,
                   cv::noArray(), 0, -box.tl());
  return m;
}

// Where barbs end at the vane's edge the background reaches in between their
// tips, a few pixels wide and far deep where they meet the edge at a slant. The
// vane is one surface, so those notches are closed: a closing whose disc is
// 0.9 % of the feather's length (wide splits stay open), then the outline and
// area are taken again. A convex disc never grows the mask past its convex hull,
// so the bounding box stays.
void close_barb_gaps(Component& comp) {
  const cv::RotatedRect rr = cv::minAreaRect(comp.contour);
  const int k = 2 * int(std::lround(kBarbGapHalfDisc * std::max(rr.size.width, rr.size.height))) + 1;
  if (k < 3) return;
  cv::Mat padded;
  cv::copyMakeBorder(comp.mask, padded, k, k, k, k, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::morphologyEx(padded, padded, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)), cv::Point(-1, -1), 1,
                   cv::BORDER_CONSTANT, cv::Scalar(0));
  std::vector<cv::Point> outline = largest_contour(padded, comp.bbox.tl() - cv::Point(k, k));
  if (outline.empty()) return;
  comp.contour = std::move(outline);
  comp.area = cv::contourArea(comp.contour);
  comp.mask = filled(comp.contour, comp.bbox);
}

// A component's hull solidity and border flag, from its contour and box.
void measure_shape(Component& comp, const cv::Size& image) {
  std::vector<cv::Point> hull;
  cv::convexHull(comp.contour, hull);
  comp.solidity = comp.area / std::max(1.0, cv::contourArea(hull));
  comp.touches_border = comp.bbox.x <= 1 || comp.bbox.y <= 1 || comp.bbox.br().x >= image.width - 1 ||
                        comp.bbox.br().y >= image.height - 1;
}

}  // namespace plumage::analysis
