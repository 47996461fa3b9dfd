// Quills first (quills.h): the stems a disc cannot enter, and a row cut along them.
#include "quills.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "regions.h"
#include "thresholds.h"

namespace plumage::analysis {
using namespace thresholds::quills;

cv::Point2d Quill::dir() const {
  const cv::Point2d d = base - free_end;
  const double n = std::hypot(d.x, d.y);
  return n > 0 ? d / n : cv::Point2d(0, -1);
}

std::vector<Quill> find_quills(const Component& region) {
  // Distance to the card (`depth`: also where a stem's line runs on into the vane),
  // on the mask framed wide enough for the opening; the frame is card.
  cv::Mat framed, dt;
  cv::copyMakeBorder(region.mask, framed, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::distanceTransform(framed, dt, cv::DIST_L2, 3);
  double widest = 0;
  cv::minMaxLoc(dt, nullptr, &widest);
  const int r = std::max(kMinOpenRadiusPx, int(std::lround(kOpenRadius * widest)));
  const int pad = r + 2;
  cv::Mat M, depth;
  cv::copyMakeBorder(region.mask, M, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::copyMakeBorder(dt, depth, pad - 1, pad - 1, pad - 1, pad - 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat opened, residual, touching;
  cv::morphologyEx(M, opened, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  residual = M & ~opened;
  cv::dilate(opened, touching, cv::Mat());
  touching &= residual;
  cv::Mat labels;
  const int n = cv::connectedComponents(residual, labels, 8, CV_32S);
  std::vector<std::vector<cv::Point>> pixels(static_cast<std::size_t>(n)), contact(static_cast<std::size_t>(n));
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    const uchar* t = touching.ptr<uchar>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (l[x] > 0) {
        pixels[std::size_t(l[x])].emplace_back(x, y);
        if (t[x]) contact[std::size_t(l[x])].emplace_back(x, y);
      }
  }
  const cv::Point2d offset = cv::Point2d(region.bbox.tl()) - cv::Point2d(pad, pad);
  std::vector<Quill> out;
  for (int i = 1; i < n; ++i) {
    const auto& P = pixels[std::size_t(i)];
    const auto& C = contact[std::size_t(i)];
    if (C.empty() || P.size() < 4) continue;  // a fragment the vane does not hold
    cv::Point2d base(0, 0);
    for (const cv::Point& p : C) base += cv::Point2d(p);
    base /= double(C.size());
    cv::Point2d free_end = base;
    double far = 0;
    for (const cv::Point& p : P) {
      const double d = std::hypot(p.x - base.x, p.y - base.y);
      if (d > far) far = d, free_end = cv::Point2d(p);
    }
    const double length = far + 1;
    // The stem's outer two thirds: near the base the corners where it meets the
    // vane, which the disc cannot reach either, widen it.
    const cv::Point2d axis = (free_end - base) / std::max(far, 1e-9);
    int middle = 0, outer = 0;
    double bend = 0;
    for (const cv::Point& p : P) {
      const cv::Point2d d = cv::Point2d(p) - base;
      const double s = d.dot(axis) / length;
      if (s < 1.0 / 3) continue;
      ++(s >= 2.0 / 3 ? outer : middle);
      bend = std::max(bend, std::fabs(d.x * axis.y - d.y * axis.x));
    }
    const double width = double(middle + outer) / (2.0 / 3 * length);
    // Its line runs on into the vane with vane on both sides, as a rachis does: a
    // split-off strip of barbs or a curl of down at the vane's edge runs along it.
    std::vector<float> inside;
    for (int j = 0; j <= 4; ++j) {
      const cv::Point2d q = base - (kIntoFrom + (kIntoTo - kIntoFrom) * j / 4.0) * r * axis;
      const int qx = int(std::lround(q.x)), qy = int(std::lround(q.y));
      inside.push_back(qx >= 0 && qy >= 0 && qx < depth.cols && qy < depth.rows ? depth.at<float>(qy, qx) : 0.f);
    }
    const double into = median(std::move(inside)) / r;
    // And a calamus is a tenth or more of its feather: a curl of down at a plume's
    // edge is shorter.
    double lo = 1e300, hi = -1e300;
    for (const cv::Point& c : region.contour) {
      const double a = (cv::Point2d(c) - offset).dot(axis);
      lo = std::min(lo, a), hi = std::max(hi, a);
    }
    const bool quill = length >= kMinLength * 2 * r && length >= kMinShareOfExtent * (hi - lo) && width <= kMaxWidth * 2 * r &&
                       bend <= kMaxBend * width + 1.5 && outer >= kMinEndWidthRatio * middle && into >= kMinInto;
    if (!quill) continue;
    // Its axis from the stem itself (its outer two thirds, a principal axis): the
    // base's corners lean toward whichever side the vane, or a neighbour's vane,
    // comes nearer, and a few degrees off put the line a neighbour's width off at
    // the tip.
    cv::Point2d centre(0, 0);
    std::vector<cv::Point2d> stem;
    for (const cv::Point& p : P)
      if ((cv::Point2d(p) - base).dot(axis) / length >= 1.0 / 3) stem.push_back(cv::Point2d(p)), centre += cv::Point2d(p);
    centre /= double(stem.size());
    double sxx = 0, sxy = 0, syy = 0;
    for (const cv::Point2d& p : stem) {
      const cv::Point2d d = p - centre;
      sxx += d.x * d.x, sxy += d.x * d.y, syy += d.y * d.y;
    }
    const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
    cv::Point2d line(std::cos(angle), std::sin(angle));
    if (line.dot(axis) < 0) line = -line;
    const cv::Point2d tip_end = centre + (free_end - centre).dot(line) * line;
    const cv::Point2d root = centre + (base - centre).dot(line) * line;
    out.push_back({tip_end + offset, root + offset, length, width});
  }
  return out;
}

std::vector<Quill> quills_of_a_row(const std::vector<Quill>& quills) {
  std::vector<Quill> best;
  const double cos_spread = std::cos(kMaxRowSpread * kPi / 180);
  for (const Quill& q : quills) {
    // The quills within the spread of this one, then of their mean.
    std::vector<Quill> group;
    cv::Point2d mean = q.dir();
    for (int round = 0; round < 2; ++round) {
      group.clear();
      cv::Point2d sum(0, 0);
      for (const Quill& o : quills)
        if (o.dir().dot(mean) >= cos_spread) group.push_back(o), sum += o.dir();
      const double len = std::hypot(sum.x, sum.y);
      if (len > 0) mean = sum / len;
    }
    if (group.size() > best.size()) best = group;
  }
  return best;
}

namespace {
// The label in `parts` (CV_32S, the region's box from `tl`) at the quill's free
// end: the first non-zero one in its 3x3 neighbourhood, row by row; 0 for none.
int part_at_free_end(const cv::Mat& parts, const Quill& q, const cv::Point2d& tl) {
  const cv::Point e(int(std::lround(q.free_end.x - tl.x)), int(std::lround(q.free_end.y - tl.y)));
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (const int l = parts.at<int>(std::clamp(e.y + dy, 0, parts.rows - 1), std::clamp(e.x + dx, 0, parts.cols - 1)))
        return l;
  return 0;
}

// Distance from p to the quill's line: the stem, and past its base on along it.
double distance_to(const Quill& q, const cv::Point2d& p) {
  const cv::Point2d d = q.dir();
  const double s = (p - q.free_end).dot(d);
  const cv::Point2d foot = q.free_end + std::max(0.0, s) * d;
  return std::hypot(p.x - foot.x, p.y - foot.y);
}
}  // namespace

RowSplit split_by_quills(const Component& region, std::vector<Quill> quills, const cv::Size& image) {
  RowSplit out;
  if (quills.size() < 2) return out;
  // Along the row: perpendicular to the quills' mean direction.
  cv::Point2d mean(0, 0);
  for (const Quill& q : quills) mean += q.dir();
  mean /= std::max(1e-9, std::hypot(mean.x, mean.y));
  const cv::Point2d across(-mean.y, mean.x);
  std::sort(quills.begin(), quills.end(),
            [&](const Quill& a, const Quill& b) { return a.free_end.dot(across) < b.free_end.dot(across); });
  const int K = int(quills.size());
  // Quills about evenly spaced along the row: a gap far wider than the others is
  // a quill not found there, whose feather the strips beside it would share.
  std::vector<double> gaps;
  for (int k = 1; k < K; ++k)
    gaps.push_back((quills[std::size_t(k)].free_end - quills[std::size_t(k - 1)].free_end).dot(across));
  const double median_gap = median(gaps);
  for (int k = 1; k < K; ++k)
    if (gaps[std::size_t(k - 1)] > kMaxGapRatio * median_gap)
      return {{}, "the gap between quills " + std::to_string(k) + " and " + std::to_string(k + 1) +
                      " is wider than the others, as if a quill there was not seen"};
  cv::Mat label(region.mask.size(), CV_32S, cv::Scalar(0));
  const cv::Point2d tl(region.bbox.tl());
  for (int y = 0; y < label.rows; ++y) {
    const uchar* m = region.mask.ptr<uchar>(y);
    int* l = label.ptr<int>(y);
    for (int x = 0; x < label.cols; ++x) {
      if (!m[x]) continue;
      const cv::Point2d p = tl + cv::Point2d(x, y);
      int best = 0;
      double nearest = 1e300;
      for (int k = 0; k < K; ++k)
        if (const double d = distance_to(quills[std::size_t(k)], p); d < nearest) nearest = d, best = k;
      l[x] = best + 1;
    }
  }
  // Where two quills' lines cross (feathers tilted toward each other), a strip is
  // cut in two past the crossing: a part that does not hold its quill goes to the
  // strip it borders most.
  for (int k = 0; k < K; ++k) {
    cv::Mat parts;
    const int n = cv::connectedComponents(label == k + 1, parts, 8, CV_32S);
    if (n <= 2) continue;
    const int own = part_at_free_end(parts, quills[std::size_t(k)], tl);
    for (int part = 1; part < n; ++part) {
      if (part == own) continue;
      std::vector<int> border(std::size_t(K) + 1, 0);
      for (int y = 0; y < parts.rows; ++y)
        for (int x = 0; x < parts.cols; ++x) {
          if (parts.at<int>(y, x) != part) continue;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int yy = y + dy, xx = x + dx;
              if (yy < 0 || xx < 0 || yy >= label.rows || xx >= label.cols) continue;
              const int l = label.at<int>(yy, xx);
              if (l > 0 && l != k + 1) ++border[std::size_t(l)];
            }
        }
      const int to = int(std::max_element(border.begin(), border.end()) - border.begin());
      if (to > 0 && border[std::size_t(to)] > 0) label.setTo(to, parts == part);
    }
  }
  std::vector<double> area;
  for (int k = 0; k < K; ++k) {
    cv::Mat mine = label == k + 1, parts, stats, centroids;
    // The part holding the quill's free end; a strip cut in two is not followed.
    const int n = cv::connectedComponentsWithStats(mine, parts, stats, centroids, 8, CV_32S);
    const int own = part_at_free_end(parts, quills[std::size_t(k)], tl);
    if (own == 0) return {{}, "a quill's own strip does not reach its calamus"};
    int rest = 0;
    for (int i = 1; i < n; ++i) if (i != own) rest += stats.at<int>(i, cv::CC_STAT_AREA);
    if (rest > kMaxCutOffShare * stats.at<int>(own, cv::CC_STAT_AREA))
      return {{}, "the strip of the row around quill " + std::to_string(k + 1) + " falls into pieces"};
    const cv::Mat piece = parts == own;
    const cv::Rect box = cv::boundingRect(piece);
    Component c;
    c.bbox = box + region.bbox.tl();
    c.mask = piece(box).clone();
    c.contour = largest_contour(c.mask, c.bbox.tl());
    if (c.contour.empty()) return {{}, "a quill's strip is empty"};
    c.area = cv::contourArea(c.contour);
    measure_shape(c, image);
    c.base_px = quills[std::size_t(k)].free_end;
    c.row_rest = (label(box) > 0) & (label(box) != k + 1);
    c.row_feathers = K;
    area.push_back(c.area);
    out.pieces.push_back(std::move(c));
  }
  const double median_area = median(area);
  for (int k = 0; k < K; ++k) {
    if (area[std::size_t(k)] < kMinPieceShare * median_area) {
      out.pieces.clear();
      out.why = "the strip around quill " + std::to_string(k + 1) + " is too small to be a feather";
      return out;
    }
    // An end strip far larger than the others holds a feather whose quill was not seen.
    if (area[std::size_t(k)] > kMaxPieceShare * median_area) {
      out.pieces.clear();
      out.why = "the strip around quill " + std::to_string(k + 1) + " is larger than two feathers' share";
      return out;
    }
  }
  return out;
}

}  // namespace plumage::analysis
