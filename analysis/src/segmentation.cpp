// Feather masks: background colour from the border, colour distance to it,
// Otsu threshold, an opening that removes grid lines, and connected components
// filtered by size and thickness so text, labels and rulings are dropped.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <unordered_map>
#include <opencv2/imgproc.hpp>

#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "plumage/analysis/analyze.h"
#include "segmentation.h"
#include "luma.h"
#include "peaks.h"
#include "thresholds.h"

namespace plumage::analysis {
using namespace thresholds::segmentation;
namespace {

// Median colour and luminance spread of a frame of pixels along the border.
void border_statistics(const cv::Mat& bgr, cv::Vec3d& median, double& sigma) {
  const int b = border_frame_px(bgr.cols, bgr.rows);
  std::vector<uchar> ch[3];
  std::vector<double> luma;
  auto take = [&](int x, int y) {
    const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
    for (int c = 0; c < 3; ++c) ch[c].push_back(p[c]);
    luma.push_back(luma_bgr(p));
  };
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x)
      if (y < b || y >= bgr.rows - b || x < b || x >= bgr.cols - b)
        take(x, y);
      else
        x = bgr.cols - b - 1;
  for (int c = 0; c < 3; ++c) median[c] = plumage::median(std::move(ch[c]));
  const double m = plumage::median(luma);
  for (double& v : luma) v = std::fabs(v - m);
  sigma = 1.4826 * plumage::median(std::move(luma));  // MAD to a Gaussian sigma
}

}  // namespace

namespace {

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

// Feathers that touch or overlap make one blob. A feather's vane is one
// ribbon: the part of it at least kCore of its widest half-width away from the
// background is one connected piece along the shaft. Two feathers side by side
// or tip to quill give two such pieces of comparable size (a narrow neck where
// they touch is below the level). Pieces under kMinPiece of the largest are
// noise (a lobe of a split vane), not a second feather. Levels chosen on the
// sheets in ../shared/photos (docs/analysis.md, "Sheets").

// A single feather fills most of its convex hull (0.63-0.99 on those sheets); a
// fan or a row of downy feathers on a string leaves the background between
// them inside it.

// The blob's distance transform and its core pieces (labels 1..n of `markers`,
// CV_32S, mask-sized; 0 elsewhere); returns n (at least 1 for a non-empty mask).
int core_markers(const cv::Mat& mask, cv::Mat& dt, cv::Mat& markers) {
  cv::distanceTransform(mask, dt, cv::DIST_L2, 3);
  markers = cv::Mat::zeros(mask.size(), CV_32S);
  double most = 0;
  cv::minMaxLoc(dt, nullptr, &most);
  if (most < kMinCoreDepthPx) return 1;
  cv::Mat core = dt >= kCore * most, labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(core, labels, stats, centroids, 8, CV_32S);
  int largest = 0;
  for (int i = 1; i < n; ++i) largest = std::max(largest, stats.at<int>(i, cv::CC_STAT_AREA));
  std::vector<int> id(n, 0);
  int pieces = 0;
  for (int i = 1; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) >= kMinPiece * largest) id[i] = ++pieces;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) markers.at<int>(y, x) = id[labels.at<int>(y, x)];
  return std::max(1, pieces);
}

// A blob's mask with a one-pixel frame of background, its distance transform and
// its core pieces (core_markers), found once and used both to count the feathers
// in the blob and to separate them.
struct Cores {
  cv::Mat mask, dt, markers;
  int n = 1;
};
Cores find_cores(const cv::Mat& blob_mask) {
  Cores c;
  cv::copyMakeBorder(blob_mask, c.mask, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  c.n = core_markers(c.mask, c.dt, c.markers);
  return c;
}

// A component's hull solidity and border flag, from its contour and box.
void measure_shape(Component& comp, const cv::Size& image) {
  std::vector<cv::Point> hull;
  cv::convexHull(comp.contour, hull);
  comp.solidity = comp.area / std::max(1.0, cv::contourArea(hull));
  comp.touches_border = comp.bbox.x <= 1 || comp.bbox.y <= 1 || comp.bbox.br().x >= image.width - 1 ||
                        comp.bbox.br().y >= image.height - 1;
}

// Grows the labelled cores (markers > 0) over the rest of the mask, deepest
// pixels (largest distance to the background) first: each pixel joins the label
// that reaches it first (Meyer's flooding). Pixels outside the mask stay 0.
void flood_from_cores(const cv::Mat& mask, const cv::Mat& dt, cv::Mat& markers) {
  struct Item {
    float depth;
    int x, y;
    bool operator<(const Item& o) const { return depth < o.depth; }
  };
  std::priority_queue<Item> queue;
  auto push_neighbours = [&](int x, int y) {
    const int label = markers.at<int>(y, x);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= mask.cols || ny >= mask.rows) continue;
        if (!mask.at<uchar>(ny, nx) || markers.at<int>(ny, nx) != 0) continue;
        markers.at<int>(ny, nx) = label;  // claimed now, grown from in depth order
        queue.push({dt.at<float>(ny, nx), nx, ny});
      }
  };
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (markers.at<int>(y, x) > 0) queue.push({dt.at<float>(y, x), x, y});
  while (!queue.empty()) {
    const Item it = queue.top();
    queue.pop();
    push_neighbours(it.x, it.y);
  }
}

// Touching feathers, told apart: the blob's core pieces (one per feather) grow
// back over the blob by a watershed on the distance transform, so each piece
// takes the pixels nearer its own ridge and the cut runs along the neck where
// two feathers meet. A piece that grows to less than a feather (under `min_area`
// or kMinPiece of the largest piece) is a lobe of its neighbour's vane, not a
// feather: its core is dropped and the rest grow again; when one piece is left,
// the blob is one feather (`cores.n` becomes 1). Each cut, between two pieces
// that meet, is kept only where they barely touch: no longer than kMaxCut of
// the narrower one's width (twice its largest inscribed radius). Feathers that
// overlap, or lie quill on tip, meet over a longer line, and a watershed there
// hands one feather's quill or tip to the other (a feather whose quill is cut
// off is then read backwards), so they stay one region, reported as such.
// Every piece must also fill at least kMinPieceSolidity of its hull, as a
// feather does. Otherwise the result is empty. `cores` is the blob's
// (find_cores); its markers are flooded in place.
std::vector<Component> separate(const Component& blob, Cores& cores, const cv::Size& image, double min_area) {
  const cv::Mat &padded = cores.mask, &dt = cores.dt;
  cv::Mat& markers = cores.markers;
  if (cores.n < 2) return {};
  const cv::Mat seeds = markers.clone();
  std::vector<int> label(std::size_t(cores.n) + 1);  // seed's core -> its piece now (0: dropped)
  for (std::size_t i = 0; i < label.size(); ++i) label[i] = int(i);
  std::vector<int> area;
  for (;;) {
    flood_from_cores(padded, dt, markers);
    area.assign(std::size_t(cores.n) + 1, 0);
    for (int y = 0; y < markers.rows; ++y) {
      const int* m = markers.ptr<int>(y);
      for (int x = 0; x < markers.cols; ++x) ++area[std::size_t(std::max(0, m[x]))];
    }
    const int largest = *std::max_element(area.begin() + 1, area.end());
    std::vector<int> id(std::size_t(cores.n) + 1, 0);
    int kept = 0;
    for (int i = 1; i <= cores.n; ++i)
      if (area[std::size_t(i)] >= std::max(min_area, kMinPiece * largest)) id[std::size_t(i)] = ++kept;
    if (kept == cores.n) break;
    // No piece the size of a feather: small feathers together, reported as such.
    if (kept == 0) return {};
    // Lobes: grow again from the other cores only.
    cores.n = kept;
    for (int& l : label) l = id[std::size_t(l)];
    for (int y = 0; y < markers.rows; ++y) {
      const int* sd = seeds.ptr<int>(y);
      int* m = markers.ptr<int>(y);
      for (int x = 0; x < markers.cols; ++x) m[x] = label[std::size_t(sd[x])];
    }
    if (cores.n < 2) return {};
  }
  const int n = cores.n;
  // The cuts: pixels of one piece with a pixel of another among their 8
  // neighbours, per pair of pieces; a cut's length is the longer side of the
  // smallest box around its pixels.
  std::vector<std::vector<cv::Point>> cut_points(std::size_t(n * n));
  for (int y = 1; y + 1 < markers.rows; ++y)
    for (int x = 1; x + 1 < markers.cols; ++x) {
      const int here = markers.at<int>(y, x);
      if (here < 1) continue;
      int other = 0;
      for (int dy = -1; dy <= 1 && !other; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int l = markers.at<int>(y + dy, x + dx);
          if (l > 0 && l != here) other = l;
        }
      if (other) cut_points[std::size_t((std::min(here, other) - 1) * n + std::max(here, other) - 1)].emplace_back(x, y);
    }
  std::vector<Component> pieces;
  std::vector<double> width(std::size_t(n), 0);
  for (int i = 1; i <= n; ++i) {
    double widest = 0;
    cv::minMaxLoc(dt, nullptr, &widest, nullptr, nullptr, markers == i);
    width[std::size_t(i - 1)] = 2 * widest;
    cv::Mat region = (markers == i) & padded;
    const cv::Rect box = cv::boundingRect(region);
    if (box.empty()) return {};
    Component c;
    c.bbox = box + blob.bbox.tl() - cv::Point(1, 1);
    c.mask = region(box).clone();
    c.contour = largest_contour(c.mask, c.bbox.tl());
    if (c.contour.empty()) return {};
    c.area = cv::contourArea(c.contour);
    measure_shape(c, image);
    c.separated_from = n;
    pieces.push_back(std::move(c));
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const auto& pts = cut_points[std::size_t(i * n + j)];
      if (pts.empty()) continue;
      const cv::Size2f box = cv::minAreaRect(pts).size;
      // Both sides of the cut are counted: half the thickness is one side.
      const double cut = std::max(box.width, box.height) + 1.0;
      if (cut > kMaxCut * std::min(width[std::size_t(i)], width[std::size_t(j)])) return {};
    }
  for (const Component& c : pieces)
    if (c.solidity < kMinPieceSolidity) return {};
  return pieces;
}

// Faint feathers side by side, as glued in a row on a band (the blue-jay
// sheet's grey downy feathers): each plume is denser than the fluff where two
// plumes meet. The colour distance summed across the region, along each of
// kRowAngles directions, is a profile with a peak per plume where the direction
// runs along the row; the direction whose smoothed profile varies most (total
// variation over its maximum) is taken. Peaks standing out by kRowProminence of
// the profile's maximum are plumes, and the region is cut at the lowest point
// between two neighbours, straight across the row. `own`: the region's pixels
// above the level that joined it (its filled holes weigh nothing). Smoothing:
// kRowSmooth of the square root of the region's area. On that sheet the plumes
// stand out by 0.22-0.95 (at 0.75x, 1x and 1.5x, and turned a quarter); each
// drawn plume alone is one peak. Returns the pieces when there are two or
// more, each a feather in size (`min_area`, kMinPiece of the largest) and
// standing across the row, at least kMinPlumeAspect times as long along the cut
// as it is wide across the row (those plumes 2.07-3.20; a plume cut from its
// own downy base, where the direction found runs along one feather, 0.73-1.17;
// tufts on a string 1.36-2.02, a row of them 0.73-2.13); otherwise nothing.
std::vector<Component> split_faint_row(const Component& region, const cv::Mat& own, const cv::Mat& dist,
                                       const cv::Size& image, double min_area) {
  struct Px {
    int x, y;
    double w;  // 0 in the region's holes (filled, but card)
  };
  std::vector<Px> px;
  for (int y = 0; y < region.mask.rows; ++y) {
    const uchar* m = region.mask.ptr<uchar>(y);
    const uchar* o = own.ptr<uchar>(y);
    const uchar* d = dist.ptr<uchar>(y + region.bbox.y) + region.bbox.x;
    for (int x = 0; x < region.mask.cols; ++x)
      if (m[x]) px.push_back({x, y, o[x] ? double(d[x]) : 0.0});
  }
  if (px.empty()) return {};
  const double sigma = std::max(kRowMinSigmaPx, kRowSmooth * std::sqrt(double(cv::countNonZero(own))));
  const int reach = int(std::ceil(kRowKernelSigmas * sigma));
  std::vector<double> kernel(std::size_t(2 * reach + 1));
  for (int k = -reach; k <= reach; ++k) kernel[std::size_t(k + reach)] = std::exp(-0.5 * k * k / (sigma * sigma));
  struct Across {
    double ux = 1, uy = 0, s0 = 0, variation = -1;
    std::vector<double> profile;
  } best;
  for (int a = 0; a < kRowAngles; ++a) {
    const double angle = kPi * a / kRowAngles, ux = std::cos(angle), uy = std::sin(angle);
    double s0 = 1e300, s1 = -1e300;
    for (const Px& p : px) {
      const double s = p.x * ux + p.y * uy;
      s0 = std::min(s0, s), s1 = std::max(s1, s);
    }
    std::vector<double> raw(std::size_t(std::lround(s1 - s0)) + 1, 0.0), smooth(raw.size(), 0.0);
    for (const Px& p : px) raw[std::size_t(std::lround(p.x * ux + p.y * uy - s0))] += p.w;
    for (std::size_t i = 0; i < raw.size(); ++i)
      for (int k = -reach; k <= reach; ++k) {
        const long j = long(i) + k;
        if (j >= 0 && j < long(raw.size())) smooth[i] += kernel[std::size_t(k + reach)] * raw[std::size_t(j)];
      }
    const double most = *std::max_element(smooth.begin(), smooth.end());
    if (most <= 0) continue;
    double variation = 0;
    for (std::size_t i = 1; i < smooth.size(); ++i) variation += std::fabs(smooth[i] - smooth[i - 1]);
    variation /= most;
    if (variation > best.variation) best = {ux, uy, s0, variation, std::move(smooth)};
  }
  if (best.profile.empty()) return {};
  const std::vector<double>& v = best.profile;
  const double most = *std::max_element(v.begin(), v.end());
  std::vector<int> plumes;
  for (const Peak& p : profile_peaks(v))
    if (p.prominence >= kRowProminence * most) plumes.push_back(p.at);
  if (plumes.size() < 2) return {};
  std::vector<double> cuts;  // profile positions between neighbouring plumes
  for (std::size_t i = 0; i + 1 < plumes.size(); ++i)
    cuts.push_back(double(std::min_element(v.begin() + plumes[i], v.begin() + plumes[i + 1]) - v.begin()));
  const std::size_t n = plumes.size();
  std::vector<cv::Mat> masks(n);
  for (cv::Mat& m : masks) m = cv::Mat::zeros(region.mask.size(), CV_8U);
  // Each piece's extent across the row (along u) and along its feathers (t).
  // Feathers in a row join at their bases (a glue band, downy bases): along the
  // cuts, the region's own pixels lie toward that end. When their mean lies
  // kBaseSide of the region's extent along the feathers off its middle, each
  // piece's base is its end on that side (the blue-jay sheet's two groups:
  // 0.20-0.23 and 0.11-0.13 toward their bands at 0.75x, 1x and 1.5x and turned
  // a quarter).
  std::vector<double> lo_u(n, 1e300), hi_u(n, -1e300), lo_v(n, 1e300), hi_v(n, -1e300);
  double t_sum = 0;  // over the region's own pixels within 1 px of a cut
  int t_count = 0;
  for (const Px& p : px) {
    const double s = p.x * best.ux + p.y * best.uy - best.s0, t = -p.x * best.uy + p.y * best.ux;
    const auto piece = std::size_t(std::upper_bound(cuts.begin(), cuts.end(), s) - cuts.begin());
    masks[piece].at<uchar>(p.y, p.x) = 255;
    lo_u[piece] = std::min(lo_u[piece], s), hi_u[piece] = std::max(hi_u[piece], s);
    lo_v[piece] = std::min(lo_v[piece], t), hi_v[piece] = std::max(hi_v[piece], t);
    if (p.w > 0)
      for (double cut : cuts)
        if (std::fabs(s - cut) <= 1.0) t_sum += t, ++t_count;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (hi_v[i] - lo_v[i] < kMinPlumeAspect * (hi_u[i] - lo_u[i] + 1)) return {};
  const double t_lo = *std::min_element(lo_v.begin(), lo_v.end()), t_hi = *std::max_element(hi_v.begin(), hi_v.end());
  int base_side = 0;  // +1: toward larger t, -1: toward smaller t
  if (t_count > 0) {
    const double off = t_sum / t_count - 0.5 * (t_lo + t_hi);
    if (std::fabs(off) >= kBaseSide * (t_hi - t_lo)) base_side = off > 0 ? 1 : -1;
  }
  std::vector<Component> pieces;
  double largest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const cv::Mat& m = masks[i];
    const cv::Rect box = cv::boundingRect(m);
    if (box.empty()) return {};
    Component c;
    c.bbox = box + region.bbox.tl();
    c.contour = largest_contour(m(box), c.bbox.tl());
    if (c.contour.empty()) return {};
    c.mask = filled(c.contour, c.bbox);
    c.area = cv::contourArea(c.contour);
    measure_shape(c, image);
    c.separated_from = int(n);
    if (base_side != 0) {
      const double s = 0.5 * (lo_u[i] + hi_u[i]) + best.s0, t = base_side > 0 ? hi_v[i] : lo_v[i];
      c.base_px = cv::Point2d(s * best.ux - t * best.uy, s * best.uy + t * best.ux) + cv::Point2d(region.bbox.tl());
    }
    largest = std::max(largest, c.area);
    pieces.push_back(std::move(c));
  }
  for (const Component& c : pieces)
    if (c.area < std::max(min_area, kMinPiece * largest)) return {};
  return pieces;
}

// Faint feathers (grey down on a grey card) clear the colour threshold only in
// patches: their outline there is drawn by the fluff's grain, not by the
// feather's edge, and one feather falls into pieces or two feathers' patches
// fall into one (the blue-jay sheet's grey downy feathers, glued in two rows of
// four). A region is faint when the 95th percentile of its colour distance is
// under kFaintP95 times the threshold (grey downy feathers 1.11-1.24 on that
// sheet, its other feathers 1.7 and over). Where two or more faint regions and
// no other lie mostly in one connected region above `half_level` (half the
// threshold: the hysteresis level before the border's noise raises it; their
// fluff joins them there), that region takes their place: cut along its row
// into feathers (split_faint_row), or else reported as several feathers
// (`faint_pieces`), never analysed as one invented from a patch.
void join_faint_pieces(std::vector<Component>& feathers, const cv::Mat& dist, double threshold,
                       double half_level, const cv::Mat& open_k, const cv::Size& image, double min_area) {
  std::vector<char> faint(feathers.size(), 0);
  int n_faint = 0;
  for (std::size_t i = 0; i < feathers.size(); ++i) {
    const Component& c = feathers[i];
    std::vector<uchar> v;
    v.reserve(std::size_t(cv::countNonZero(c.mask)));
    for (int y = 0; y < c.mask.rows; ++y) {
      const uchar* m = c.mask.ptr<uchar>(y);
      const uchar* d = dist.ptr<uchar>(y + c.bbox.y) + c.bbox.x;
      for (int x = 0; x < c.mask.cols; ++x)
        if (m[x]) v.push_back(d[x]);
    }
    if (v.empty()) continue;
    auto p95 = v.begin() + std::ptrdiff_t(v.size() * kFaintPercentile / 100);
    std::nth_element(v.begin(), p95, v.end());
    faint[i] = *p95 < kFaintP95 * threshold;
    n_faint += faint[i];
  }
  if (n_faint < kMinFaintPieces) return;
  cv::Mat low, labels, stats, centroids;
  cv::threshold(dist, low, half_level, 255, cv::THRESH_BINARY);
  cv::morphologyEx(low, low, cv::MORPH_OPEN, open_k);
  const int n = cv::connectedComponentsWithStats(low, labels, stats, centroids, 8, CV_32S);
  // Each region's joining region: the one most of its pixels lie in.
  std::vector<int> joined(feathers.size(), 0);
  std::vector<int> faint_in(std::size_t(n), 0), other_in(std::size_t(n), 0);
  for (std::size_t i = 0; i < feathers.size(); ++i) {
    const Component& c = feathers[i];
    std::unordered_map<int, int> votes;
    for (int y = 0; y < c.mask.rows; ++y) {
      const uchar* m = c.mask.ptr<uchar>(y);
      const int* l = labels.ptr<int>(y + c.bbox.y) + c.bbox.x;
      for (int x = 0; x < c.mask.cols; ++x)
        if (m[x] && l[x]) ++votes[l[x]];
    }
    int most = 0;
    for (const auto& [label, count] : votes)
      if (count > most) most = count, joined[i] = label;
    (faint[i] ? faint_in : other_in)[std::size_t(joined[i])] += 1;
  }
  std::vector<Component> kept;
  std::vector<char> merged(std::size_t(n), 0);
  for (std::size_t i = 0; i < feathers.size(); ++i) {
    const auto j = std::size_t(joined[i]);
    if (!faint[i] || j == 0 || faint_in[j] < kMinFaintPieces || other_in[j] > 0) {
      kept.push_back(std::move(feathers[i]));
      continue;
    }
    if (merged[j]) continue;
    merged[j] = 1;
    Component c;
    c.bbox = cv::Rect(stats.at<int>(int(j), cv::CC_STAT_LEFT), stats.at<int>(int(j), cv::CC_STAT_TOP),
                      stats.at<int>(int(j), cv::CC_STAT_WIDTH), stats.at<int>(int(j), cv::CC_STAT_HEIGHT));
    const cv::Mat own = labels(c.bbox) == int(j);
    c.contour = largest_contour(own, c.bbox.tl());
    if (c.contour.empty()) continue;
    c.mask = filled(c.contour, c.bbox);
    c.area = cv::contourArea(c.contour);
    measure_shape(c, image);
    std::vector<Component> row = split_faint_row(c, own, dist, image, min_area);
    if (!row.empty()) {
      for (Component& piece : row) kept.push_back(std::move(piece));
      continue;
    }
    c.faint_pieces = faint_in[j];
    c.unseparated = true;
    kept.push_back(std::move(c));
  }
  feathers = std::move(kept);
}

}  // namespace

// Pale parts on a mid-grey card: white tips, white vane margins and white
// downy feathers are lighter than the card by less than the card varies across a
// scan (darker toward the scanner's edge), so one border colour and one threshold
// cut them off. Here a pixel is pale when it is lighter than the card *near it*
// (a normalised Gaussian average of the card pixels, feathers left out) by
// kPaleLevels grey levels and 4 sigma (kPaleGrainSigmas) of the card's grain. A pale part goes to
// the feather that lies along it (contact, below), split between feathers
// that both do, so two white tips that touch never join their feathers; a pale
// part no feather lies along is a feather of its own. `bin`: the feathers found
// by colour (0/255), on return without the pale pixels; returns one label per
// pixel (0 background), feathers numbered from 1, each label one feather.
// Cards this light or lighter (kPaleCardMax) leave no room for paler parts; dark cards (kPaleCardMin) have
// none lighter than the feather itself (its colour already stands out).
cv::Mat label_with_pale_parts(const cv::Mat& bgr, cv::Mat& bin, double sigma, const cv::Mat& open_k,
                              double min_area, cv::Mat& pale) {
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  grey.convertTo(grey, CV_32F);
  // The card near each pixel: feathers and pale parts (grown by a few pixels:
  // their soft edges are not card) weigh nothing. Pale parts are not known
  // before the card is, and a large white tip lifts the card around it enough to
  // hide itself, so card and pale parts are found in turn, kPaleRounds times.
  const cv::Mat grow = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kSoftEdge + 1, 2 * kSoftEdge + 1));
  const cv::Mat bridge = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kBridge + 1, 2 * kBridge + 1));
  const double s = kCardBlur * std::min(bgr.cols, bgr.rows);
  pale = cv::Mat::zeros(bin.size(), CV_8U);
  cv::Mat lighter, card_w, den;
  double level = kPaleLevels;
  // Not card in the next round: feathers and whatever was lighter than the card
  // by half the level (unopened): a pixel of a white tip that fell just short
  // would otherwise count as card, lift the card around itself and stay out.
  cv::Mat not_card = bin.clone();
  for (int round = 0; round < kPaleRounds; ++round) {
    cv::dilate(not_card, card_w, grow);
    card_w = card_w == 0;
    card_w.convertTo(card_w, CV_32F, 1.0 / 255);
    // The card changes over centimetres: its average is taken at 1/kCardScale
    // of the resolution and interpolated back.
    cv::Mat num, small_num, small_den;
    const cv::Size small(std::max(1, grey.cols / kCardScale), std::max(1, grey.rows / kCardScale));
    cv::resize(grey.mul(card_w), small_num, small, 0, 0, cv::INTER_AREA);
    cv::resize(card_w, small_den, small, 0, 0, cv::INTER_AREA);
    // Inside a large pale part (a tail feather's white tip between two other
    // feathers) the card within a few sigma has next to no weight: there the
    // average over kCardWide times the distance takes over, smoothly (its weight
    // kWideWeight is what the near card's weight drops below).
    const double ss = s / kCardScale;
    cv::Mat wide_num, wide_den;
    cv::GaussianBlur(small_num, wide_num, cv::Size(), kCardWide * ss, kCardWide * ss, cv::BORDER_REPLICATE);
    cv::GaussianBlur(small_den, wide_den, cv::Size(), kCardWide * ss, kCardWide * ss, cv::BORDER_REPLICATE);
    cv::GaussianBlur(small_num, small_num, cv::Size(), ss, ss, cv::BORDER_REPLICATE);
    cv::GaussianBlur(small_den, small_den, cv::Size(), ss, ss, cv::BORDER_REPLICATE);
    small_num += kWideWeight * wide_num;
    small_den += kWideWeight * wide_den;
    cv::resize(small_num, num, grey.size(), 0, 0, cv::INTER_LINEAR);
    cv::resize(small_den, den, grey.size(), 0, 0, cv::INTER_LINEAR);
    lighter = grey - num / cv::max(den, 1e-6);
    cv::GaussianBlur(lighter, lighter, cv::Size(kLighterBlurKsize, kLighterBlurKsize), kLighterBlurSigma);
    // The card's own grain, from its pixels' spread about the local card (MAD):
    // the border's spread also counts the scanner's dark edge strip.
    std::vector<float> spread;
    for (int y = 0; y < grey.rows; y += kGrainStride) {
      const float* d = lighter.ptr<float>(y);
      const float* w = card_w.ptr<float>(y);
      for (int x = 0; x < grey.cols; x += kGrainStride)
        if (w[x] > 0) spread.push_back(std::fabs(d[x]));
    }
    const double card_sigma = spread.empty() ? sigma : 1.4826 * median(std::move(spread));
    level = std::max(kPaleLevels, kPaleGrainSigmas * card_sigma);
    if (round + 1 < kPaleRounds) not_card = bin | (lighter > kNearPaleShare * level);
  }
  pale = (lighter > level) & (den > kMinCardWeight);
  cv::morphologyEx(pale, pale, cv::MORPH_OPEN, open_k);
  // A scan's edge has strips lighter and darker than the card (the scanner's lid
  // and glass): no pale part is looked for within kPaleFrame of the short side
  // of the photo's border.
  const int frame = std::max(kPaleFrameMinPx, int(std::lround(kPaleFrame * std::min(bgr.cols, bgr.rows))));
  pale(cv::Rect(0, 0, pale.cols, std::min(frame, pale.rows))).setTo(0);
  pale(cv::Rect(0, std::max(0, pale.rows - frame), pale.cols, std::min(frame, pale.rows))).setTo(0);
  pale(cv::Rect(0, 0, std::min(frame, pale.cols), pale.rows)).setTo(0);
  pale(cv::Rect(std::max(0, pale.cols - frame), 0, std::min(frame, pale.cols), pale.rows)).setTo(0);
  // A region by colour that is mostly lighter than the card (the whitest part
  // of a white tip, standing out by colour too) is pale as a whole: a white tip
  // is then one pale part against its vane, not a region of its own beside it.
  // A region that is mostly darker keeps its pale pixels (the buff spots of a
  // barred vane), which are not pale parts: it would fall apart into pieces.
  {
    cv::Mat colour_labels;
    const int nc = cv::connectedComponents(bin, colour_labels, 8, CV_32S);
    std::vector<int> total(std::size_t(nc), 0), lighter_px(std::size_t(nc), 0);
    for (int y = 0; y < bin.rows; ++y) {
      const int* l = colour_labels.ptr<int>(y);
      const uchar* pl = pale.ptr<uchar>(y);
      for (int x = 0; x < bin.cols; ++x) ++total[std::size_t(l[x])], lighter_px[std::size_t(l[x])] += pl[x] != 0;
    }
    for (int y = 0; y < bin.rows; ++y) {
      const int* l = colour_labels.ptr<int>(y);
      uchar* b = bin.ptr<uchar>(y);
      uchar* pl = pale.ptr<uchar>(y);
      for (int x = 0; x < bin.cols; ++x) {
        if (!l[x]) continue;
        const auto k = std::size_t(l[x]);
        if (2 * lighter_px[k] >= total[k]) b[x] = 0, pl[x] = 255;
        else pl[x] = 0;
      }
    }
  }
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(bin, labels, stats, centroids, 8, CV_32S);
  if (cv::countNonZero(pale) == 0) return labels;

  // Each pale pixel joins a feather whose pixels reach it first, growing through
  // pale pixels and the seeds' soft edge (a geodesic flood from every seed at
  // once, breadth first), so a pale part shared by two touching feathers is
  // split between them where the two floods meet. Seeds: the regions by colour
  // of at least kBaseArea of the smallest feather (the grey base of a white
  // downy feather is that small).
  std::vector<char> seed(std::size_t(n), 0), feather_sized(std::size_t(n), 0);
  for (int i = 1; i < n; ++i) {
    const int area = stats.at<int>(i, cv::CC_STAT_AREA);
    seed[std::size_t(i)] = area >= kBaseArea * min_area;
    feather_sized[std::size_t(i)] = area >= min_area;
  }
  std::vector<cv::Point> queue;
  cv::Mat seeds = cv::Mat::zeros(bin.size(), CV_8U);
  for (int y = 0; y < bin.rows; ++y) {
    const uchar* b = bin.ptr<uchar>(y);
    int* l = labels.ptr<int>(y);
    uchar* sd = seeds.ptr<uchar>(y);
    for (int x = 0; x < bin.cols; ++x) {
      if (!b[x]) continue;
      if (seed[std::size_t(l[x])]) queue.emplace_back(x, y), sd[x] = 255;
      else l[x] = 0;
    }
  }
  // A pale part is a feather's own where that feather lies along it: a white
  // tip against its vane over the vane's width, a margin along the vane, a
  // downy plume on its base. Contact: the pale part's pixels nearer to a seed
  // than kBridge (breadth first from every seed at once, through what is not
  // colour). Where a feather-sized region has the most contact with a pale
  // part and is at least kOwnerArea of the part's area, only feather-sized
  // regions with at least kMinContact of that contact enter it: a small feather beside a tail feather's white tip, coming within
  // the soft edge of it along a short stretch, takes none of it, nor does a dark
  // speck inside the tip; two white tips that touch each lie along their own
  // vane and share the part. Otherwise (white downy feathers whose plumes
  // touch, each on a grey base a fraction of its plume's size) every seed with
  // at least kMinBaseContact of the most contact enters.
  cv::Mat pale_parts;
  const int np = cv::connectedComponents(pale, pale_parts, 8, CV_32S);
  std::unordered_map<std::int64_t, int> contact;  // part * n + seed -> pixels
  {
    cv::Mat near_id = labels.clone();
    std::vector<cv::Point> front = queue, next;
    for (int step = 1; step <= kBridge && !front.empty(); ++step, front.swap(next)) {
      next.clear();
      for (const cv::Point& p : front) {
        const int id = near_id.at<int>(p);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const cv::Point q(p.x + dx, p.y + dy);
            if (q.x < 0 || q.y < 0 || q.x >= bin.cols || q.y >= bin.rows) continue;
            if (bin.at<uchar>(q) || near_id.at<int>(q) != 0) continue;
            near_id.at<int>(q) = id;
            next.push_back(q);
            if (const int part = pale_parts.at<int>(q)) ++contact[std::int64_t(part) * n + id];
          }
      }
    }
  }
  std::vector<int> most(std::size_t(np), 0), most_id(std::size_t(np), 0);
  for (const auto& [key, pixels] : contact) {
    const auto part = std::size_t(key / n);
    if (pixels > most[part]) most[part] = pixels, most_id[part] = int(key % n);
  }
  std::vector<int> part_area(std::size_t(np), 0);
  for (int y = 0; y < pale_parts.rows; ++y) {
    const int* pp = pale_parts.ptr<int>(y);
    for (int x = 0; x < pale_parts.cols; ++x) ++part_area[std::size_t(pp[x])];
  }
  // A white tip is a fraction of its feather; a downy plume many times its base.
  std::vector<char> owned(std::size_t(np), 0);
  for (int part = 1; part < np; ++part) {
    const int best = most_id[std::size_t(part)];
    owned[std::size_t(part)] = best > 0 && feather_sized[std::size_t(best)] &&
                               stats.at<int>(best, cv::CC_STAT_AREA) >= kOwnerArea * part_area[std::size_t(part)];
  }
  auto may_enter = [&](int part, int id) {
    const auto it = contact.find(std::int64_t(part) * n + id);
    if (it == contact.end()) return false;
    if (owned[std::size_t(part)])
      return feather_sized[std::size_t(id)] && it->second >= kMinContact * most[std::size_t(part)];
    return it->second >= kMinBaseContact * most[std::size_t(part)];
  };
  // The flood goes through pale pixels and the soft edge of the seeds, not
  // from speck to speck (grey barbs of a downy base) across what is card.
  cv::Mat reach;
  cv::dilate(seeds, reach, bridge);
  reach |= pale;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const cv::Point p = queue[head];
    const int id = labels.at<int>(p);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const cv::Point q(p.x + dx, p.y + dy);
        if (q.x < 0 || q.y < 0 || q.x >= bin.cols || q.y >= bin.rows) continue;
        if (!reach.at<uchar>(q) || labels.at<int>(q) != 0) continue;
        const int part = pale_parts.at<int>(q);
        if (part && !may_enter(part, id)) continue;
        labels.at<int>(q) = id;
        queue.push_back(q);
      }
  }
  // The soft edge only carried the flood: it is not feather.
  labels.setTo(0, (bin | pale) == 0);
  // Pale regions no feather reaches (with the specks in them) are feathers of
  // their own when they are white somewhere: lighter than the card by
  // kAloneLevels times the level (white downy feathers: 90-100 grey levels
  // above it). Card just over the level beside translucent grey fluff, which
  // darkens the card's average around it, is not (25 levels on the blue-jay
  // sheet, the level there 15).
  cv::Mat alone = (pale | bin) & (labels == 0), alone_labels;
  const int na = cv::connectedComponents(alone, alone_labels, 8, CV_32S);
  if (na > 1) {
    std::vector<float> whitest(std::size_t(na), -1e30f);
    for (int y = 0; y < alone_labels.rows; ++y) {
      const int* a = alone_labels.ptr<int>(y);
      const float* d = lighter.ptr<float>(y);
      for (int x = 0; x < alone_labels.cols; ++x)
        if (a[x]) whitest[std::size_t(a[x])] = std::max(whitest[std::size_t(a[x])], d[x]);
    }
    for (int y = 0; y < alone_labels.rows; ++y) {
      const int* a = alone_labels.ptr<int>(y);
      int* l = labels.ptr<int>(y);
      for (int x = 0; x < alone_labels.cols; ++x)
        if (a[x] && whitest[std::size_t(a[x])] >= kAloneLevels * level) l[x] = n - 1 + a[x];
    }
  }
  return labels;
}

// The outer contours of every label's pixels (labels 1..), each label on its
// own so that neighbouring labels never merge into one outline.
std::vector<std::vector<cv::Point>> label_contours(const cv::Mat& labels, const cv::Mat& pale) {
  double most = 0;
  cv::minMaxLoc(labels, nullptr, &most);
  const int n = int(most) + 1;
  std::vector<cv::Rect> box(n);
  std::vector<char> seen(n, 0);
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x) {
      const int k = l[x];
      if (k <= 0) continue;
      if (!seen[k]) box[k] = cv::Rect(x, y, 1, 1), seen[k] = 1;
      else box[k] |= cv::Rect(x, y, 1, 1);
    }
  }
  std::vector<std::vector<cv::Point>> out;
  const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kBridge + 1, 2 * kBridge + 1));
  for (int k = 1; k < n; ++k) {
    if (!seen[k]) continue;
    // A pale part joined to its feather across a few pixels of soft edge is
    // bridged to it; what stays apart (a stray assigned pixel) is dropped.
    const int pad = kBridge;
    const cv::Rect roi =
        cv::Rect(box[k].x - pad, box[k].y - pad, box[k].width + 2 * pad, box[k].height + 2 * pad) &
        cv::Rect(0, 0, labels.cols, labels.rows);
    const cv::Mat own = labels(roi) == k, own_pale = own & pale(roi);
    // Only around its pale parts (a label with none keeps its outline as found).
    cv::Mat mask;
    if (cv::countNonZero(own_pale) == 0) {
      mask = own;
    } else {
      cv::Mat near_pale;
      cv::morphologyEx(own, mask, cv::MORPH_CLOSE, disc, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
      cv::dilate(own_pale, near_pale, disc);
      mask &= near_pale;
      mask |= own;  // the closing never takes a pixel away, even at the photo's edge
    }
    std::vector<cv::Point> c = largest_contour(mask, roi.tl());
    if (!c.empty()) out.push_back(std::move(c));
  }
  return out;
}

namespace {

// Regions under kMinAreaShare of the photo, and under kMinAreaPx, are specks; the
// area is the pixel count inside the outline, not its polygon (segment_feathers).

// Writing is drawn in strokes far thinner than the letters are tall: an
// opening with a disc kStrokeDisc of the mark's height leaves under
// kStrokeSurvives of its pixels (`found`: the pixels it was outlined from,
// holes and counters open). Letters on the photos: 0-20 % (print on the
// spoonbill sheet, handwriting on the robin sheet); small feathers standing in
// a row like a word (peregrine and robin sheets): 89-97 %. Text lines run across the photo, so the height
// is the box's, and a letter "l" is as thin across as its stroke.
// `disc`: the opening's diameter in pixels, letter_disc(mark) for a letter; print
// too small to tell by its height, kPrintDisc.
int letter_disc(const Component& mark) { return 2 * int(std::lround(0.5 * kStrokeDisc * mark.bbox.height)) + 1; }
bool is_strokes(const cv::Mat& found, const Component& mark, int disc) {
  cv::Mat m = filled(mark.contour, mark.bbox);
  m &= found(mark.bbox);
  const int pixels = cv::countNonZero(m);
  if (pixels == 0) return true;
  cv::Mat opened;
  cv::morphologyEx(m, opened, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(disc, disc)),
                   cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  return cv::countNonZero(opened) < kStrokeSurvives * pixels;
}

}  // namespace

Segmentation segment_feathers(const cv::Mat& bgr) {
  Segmentation seg;
  double sigma = 0;
  border_statistics(bgr, seg.background_bgr, sigma);
  const cv::Vec3d& bg = seg.background_bgr;
  seg.dark_background = luma_bgr(bg) < kDarkBackgroundLuma;

  // Distance to the background colour: the largest channel difference, so a
  // pale pink on white and a grey on black both stand out.
  cv::Mat diff;
  cv::absdiff(bgr, cv::Scalar(bg[0], bg[1], bg[2]), diff);
  std::vector<cv::Mat> ch;
  cv::split(diff, ch);
  const cv::Mat sharp = cv::max(cv::max(ch[0], ch[1]), ch[2]);  // unblurred: small print's strokes stay apart
  cv::Mat dist;
  cv::GaussianBlur(sharp, dist, cv::Size(kDistBlurKsize, kDistBlurKsize), kDistBlurSigma);

  cv::Mat bin;
  const double otsu = cv::threshold(dist, bin, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  seg.threshold = std::max({otsu, kMinThreshold, kBorderNoiseSigmas * sigma});
  cv::threshold(dist, bin, seg.threshold, 255, cv::THRESH_BINARY);
  seg.foreground = bin.clone();

  // Grid lines and hairline text are at most a couple of pixels wide: an
  // opening a little wider than that removes them and cuts feathers free.
  const int k = kOpenKsize + 2 * (std::min(bgr.cols, bgr.rows) / kOpenGrowPx);
  const cv::Mat open_k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k));
  cv::morphologyEx(bin, bin, cv::MORPH_OPEN, open_k);

  // Hysteresis: darker quill ends and downy bases, below Otsu's threshold but
  // joined to a feather, belong to it. The level is half the threshold, raised
  // to the border's noise (4 sigma) where that is higher.
  const double half_level = std::max(kHysteresisShare * seg.threshold, kMinLowThreshold);
  const double low_threshold = std::max(half_level, kBorderNoiseSigmas * sigma);
  cv::Mat low;
  cv::threshold(dist, low, low_threshold, 255, cv::THRESH_BINARY);
  cv::morphologyEx(low, low, cv::MORPH_OPEN, open_k);
  cv::Mat labels;
  const int nl = cv::connectedComponents(low, labels, 8, CV_32S);
  std::vector<uchar> seeded(nl, 0);
  for (int y = 0; y < bin.rows; ++y) {
    const uchar* b = bin.ptr<uchar>(y);
    const int* l = labels.ptr<int>(y);
    for (int x = 0; x < bin.cols; ++x)
      if (b[x]) seeded[l[x]] = 1;
  }
  for (int y = 0; y < bin.rows; ++y) {
    uchar* b = bin.ptr<uchar>(y);
    const int* l = labels.ptr<int>(y);
    for (int x = 0; x < bin.cols; ++x) b[x] = (l[x] > 0 && seeded[l[x]]) ? 255 : 0;
  }

  const double image_area = double(bgr.total());
  // The smallest body feathers found on the peregrine sheet (424 x 600) are
  // 82-143 px; the floor only matters for photos under 0.2 MP.
  const double min_area = std::max(kMinAreaPx, kMinAreaShare * image_area);
  // On a mid-grey card, pale parts lighter than the card join their feathers or
  // stand as feathers of their own (label_with_pale_parts).
  const double bg_luma = luma_bgr(bg);
  std::vector<std::vector<cv::Point>> contours;
  cv::Mat found;  // the pixels the regions were outlined from (holes not filled)
  if (bg_luma >= kPaleCardMin && bg_luma <= kPaleCardMax) {
    cv::Mat pale;
    const cv::Mat labels = label_with_pale_parts(bgr, bin, sigma, open_k, min_area, pale);
    found = labels > 0;
    seg.foreground |= found;
    contours = label_contours(labels, pale);
  } else {
    found = bin.clone();
    cv::findContours(bin, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  }
  std::vector<Component> kept;
  std::vector<cv::Rect> marks;  // everything that could be a letter, for text lines
  double largest = 0;
  std::vector<char> marginal;  // kept on its pixel count, its polygon under min_area
  for (auto& c : contours) {
    const double area = cv::contourArea(c);
    if (area >= kMinMarkArea) marks.push_back(cv::boundingRect(c));
    bool small = false;
    if (area < min_area) {
      // The polygon through the boundary pixels' centres leaves out half of every
      // boundary pixel: on a region a few pixels wide that is a fifth of it.
      const cv::Rect r = cv::boundingRect(c);
      if (double(r.area()) < min_area || cv::countNonZero(filled(c, r)) < min_area) continue;
      small = true;
    }
    const cv::RotatedRect rr = cv::minAreaRect(c);
    const double len = std::max(rr.size.width, rr.size.height);
    if (area / std::max(len, 1.0) < kMinThickness) continue;  // a line, not a vane
    Component comp;
    comp.bbox = cv::boundingRect(c);
    comp.area = area;
    comp.contour = std::move(c);
    largest = std::max(largest, area);
    kept.push_back(std::move(comp));
    marginal.push_back(small);
  }
  // Letters and labels: far smaller than the feathers on the same sheet, and
  // written in lines. A region is text when it is small (under kMinRelativeArea
  // of the largest) or when it is short (under kTextHeight of the photo's height),
  // stands in a line of at least kTextRun marks (any region, however small) of about its height
  // (within a factor 2) that overlap it vertically by half the smaller height,
  // each within 1.5 heights of the next: a title, a word of handwriting, and is
  // drawn in strokes (is_strokes); or, for a region kept only on its pixel
  // count (marginal), when the colour distance before the blur draws it in strokes
  // 1-2 px wide (an axis label "28" on the spoonbill sheet; the blur had joined
  // them into a blob). Small feathers on a sheet are stacked in
  // columns, or are taller than that in rows; a row of small feathers beside a
  // larger one stands like a word, but its vanes are not strokes.
  std::vector<char> text(kept.size(), 0);
  cv::Mat sharp_found;  // only where a region was kept on its pixel count
  if (std::find(marginal.begin(), marginal.end(), 1) != marginal.end()) sharp_found = sharp >= seg.threshold;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const cv::Rect& a = kept[i].bbox;
    if (a.height > kTextHeight * bgr.rows) continue;
    auto same_line = [&](const cv::Rect& b) {
      const int overlap = std::min(a.br().y, b.br().y) - std::max(a.y, b.y);
      return b.height <= kLineHeightRatio * a.height && a.height <= kLineHeightRatio * b.height &&
             overlap >= kLineOverlap * std::min(a.height, b.height);
    };
    // Walk the line both ways from this region.
    int run = 1;
    for (int dir : {-1, +1}) {
      cv::Rect cur = a;
      for (bool found = true; found;) {
        found = false;
        for (const cv::Rect& b : marks) {
          if (b == a || b == cur || !same_line(b)) continue;
          const int gap = dir > 0 ? b.x - cur.br().x : cur.x - b.br().x;
          if (gap >= -kMarkOverlapPx && gap <= kMarkGap * std::max(a.height, b.height)) {
            cur = b, ++run, found = true;
            break;
          }
        }
      }
    }
    text[i] = (run >= kTextRun && is_strokes(found, kept[i], letter_disc(kept[i]))) ||
              (marginal[i] && is_strokes(sharp_found, kept[i], kPrintDisc));
  }
  for (std::size_t i = 0; i < kept.size(); ++i) {
    Component& comp = kept[i];
    if (comp.area < kMinRelativeArea * largest || text[i]) continue;
    comp.mask = filled(comp.contour, comp.bbox);
    close_barb_gaps(comp);
    Cores cores = find_cores(comp.mask);
    comp.cores = cores.n;
    measure_shape(comp, bgr.size());
    // With pale parts joined, how many feathers the region holds is judged on
    // its part that stands out by colour, as without them: white tips that
    // touch would otherwise join two feathers' cores. The pale parts then go
    // with the piece whose flood reaches them first.
    const int whole_cores = cores.n;
    const double whole_solidity = comp.solidity;
    bool judged_by_colour = false;
    const cv::Mat colour_part = comp.mask & bin(comp.bbox);
    const int colour_pixels = cv::countNonZero(colour_part), region_pixels = cv::countNonZero(comp.mask);
    if (colour_pixels == 0 && comp.touches_border) continue;  // a lighter strip along a scan's edge
    if (colour_pixels > 0 && colour_pixels < region_pixels) {
      Component colour;
      colour.bbox = comp.bbox;
      colour.contour = largest_contour(colour_part, comp.bbox.tl());
      if (!colour.contour.empty()) {
        // Filled, as a region by colour alone is (its holes are no background).
        colour.mask = filled(colour.contour, comp.bbox);
        colour.area = cv::contourArea(colour.contour);
        close_barb_gaps(colour);
        measure_shape(colour, bgr.size());
        const Cores judged = find_cores(colour.mask);
        cores.markers = judged.markers;
        cores.n = judged.n;
        comp.cores = judged.n;
        comp.solidity = colour.solidity;
        judged_by_colour = true;
      }
    }
    if (comp.cores > 1) {
      std::vector<Component> pieces = separate(comp, cores, bgr.size(), min_area);
      comp.cores = cores.n;  // lobes of one vane are not feathers
      if (!pieces.empty()) {
        for (Component& c : pieces) seg.feathers.push_back(std::move(c));
        continue;
      }
    }
    if (judged_by_colour && comp.cores > 1 && whole_cores == 1 && whole_solidity >= kSpottedSolidity &&
        colour_pixels < kSpottedColour * region_pixels) {
      // Coloured patches that no cut separates, covering a minority of a region
      // that with its pale parts is one solid core: one spotted feather (the
      // peregrine sheet's buff-spotted body feathers), not several that touch.
      comp.cores = 1;
      comp.solidity = whole_solidity;
    }
    comp.unseparated = comp.cores > 1 || comp.solidity < kMinSolidity;
    seg.feathers.push_back(std::move(comp));
  }
  join_faint_pieces(seg.feathers, dist, seg.threshold, half_level, open_k, bgr.size(), min_area);
  std::sort(seg.feathers.begin(), seg.feathers.end(), [](const Component& a, const Component& b) {
    return a.bbox.x + a.bbox.width / 2 < b.bbox.x + b.bbox.width / 2;
  });
  return seg;
}

}  // namespace plumage::analysis
