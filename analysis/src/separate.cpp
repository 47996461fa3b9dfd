// Touching feathers separated: a blob's core pieces, and the cut between them
// where two feathers barely touch (separate.h).
#include "separate.h"

#include <algorithm>
#include <queue>
#include <opencv2/imgproc.hpp>

#include "regions.h"
#include "thresholds.h"

namespace plumage::analysis {
using namespace thresholds::segmentation;

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

namespace {

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

}  // namespace

Cores find_cores(const cv::Mat& blob_mask) {
  Cores c;
  cv::copyMakeBorder(blob_mask, c.mask, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  c.n = core_markers(c.mask, c.dt, c.markers);
  return c;
}

namespace {

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

}  // namespace

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

}  // namespace plumage::analysis
