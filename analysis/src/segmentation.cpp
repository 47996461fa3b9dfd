// Feather masks: background colour from the border, colour distance to it,
// Otsu threshold, an opening that removes grid lines, and connected components
// filtered by size and thickness so text, labels and rulings are dropped.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <opencv2/imgproc.hpp>

#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "plumage/analysis/analyze.h"
#include "segmentation.h"
#include "regions.h"
#include "rows.h"
#include "separate.h"
#include "luma.h"
#include "thresholds.h"

namespace plumage::analysis {
using namespace thresholds::segmentation;
namespace {

// Calls take(x, y) for every pixel of the frame border_frame_px wide along the
// image's border (where the card's own colour, grain and texture are read).
template <class Take>
void for_border_frame(const cv::Size& size, Take take) {
  const int b = border_frame_px(size.width, size.height);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      if (y < b || y >= size.height - b || x < b || x >= size.width - b)
        take(x, y);
      else
        x = size.width - b - 1;
}

// Median colour and luminance spread of a frame of pixels along the border.
void border_statistics(const cv::Mat& bgr, cv::Vec3d& median, double& sigma) {
  std::vector<uchar> ch[3];
  std::vector<double> luma;
  for_border_frame(bgr.size(), [&](int x, int y) {
    const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
    for (int c = 0; c < 3; ++c) ch[c].push_back(p[c]);
    luma.push_back(luma_bgr(p));
  });
  for (int c = 0; c < 3; ++c) median[c] = plumage::median(std::move(ch[c]));
  sigma = mad_sigma(luma, plumage::median(luma));
}

// Low-contrast outlines: a feather part whose colour is the card's (a white
// feather's shadowed half on a grey card, a grey vane on a grey card) is still
// textured by its barbs, where the card is not. Texture is the local RMS of the
// grey minus its kTextureBlur box blur, over a kTextureWindow box; a pixel is
// textured above the card's own (the border frame's median plus kTextureSigmas
// of its spread, at least kMinTextureLevels grey levels). Textured pixels, opened
// with a kTextureOpen disc (the band of gradient along every edge is thinner and
// goes), join the feather of `labels` (CV_32S, 0 the card) they touch; a textured
// patch that touches two feathers, or none, joins nothing (feathers never merge,
// the card never becomes a feather). Only on mid-grey cards (the pale parts'
// range): on white and black cards a feather's colour stands out from the card.
void grow_into_texture(const cv::Mat& bgr, cv::Mat& labels) {
  cv::Mat grey, blur, hp, power;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::blur(grey, blur, cv::Size(kTextureBlur, kTextureBlur));
  cv::subtract(grey, blur, hp, cv::noArray(), CV_32F);
  cv::multiply(hp, hp, hp);
  cv::boxFilter(hp, power, -1, cv::Size(kTextureWindow, kTextureWindow));  // the texture squared
  std::vector<double> frame;
  for_border_frame(bgr.size(), [&](int x, int y) { frame.push_back(std::sqrt(double(power.at<float>(y, x)))); });
  const double m = plumage::median(frame);
  const double spread = mad_sigma(std::move(frame), m);
  const double level = std::max(m + kTextureSigmas * spread, double(kMinTextureLevels));
  const cv::Mat feather = labels > 0;
  cv::Mat textured = (power > level * level) & ~feather;
  cv::morphologyEx(textured, textured, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(kTextureOpen, kTextureOpen)));
  cv::Mat patches;
  const int np = cv::connectedComponents(textured | feather, patches, 8, CV_32S);
  // Per patch of textured-or-feather pixels: the one feather it holds (-1 for
  // several) and the textured pixels it would add; per feather, its area. A patch
  // adds a part of a feather, at least kMinTexturePart of its area: slivers along
  // an edge (a shadow, a neighbour's fringe) add nothing.
  double most = 0;
  cv::minMaxLoc(labels, nullptr, &most);
  std::vector<int> holds(static_cast<std::size_t>(np), 0), added(static_cast<std::size_t>(np), 0);
  std::vector<int> area(std::size_t(most) + 1, 0);
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    const int* pt = patches.ptr<int>(y);
    const uchar* t = textured.ptr<uchar>(y);
    for (int x = 0; x < labels.cols; ++x) {
      ++area[std::size_t(std::max(0, l[x]))];
      if (t[x]) ++added[std::size_t(pt[x])];
      if (!l[x]) continue;
      int& h = holds[std::size_t(pt[x])];
      h = h == 0 || h == l[x] ? l[x] : -1;
    }
  }
  for (int p = 1; p < np; ++p)
    if (holds[std::size_t(p)] > 0 && added[std::size_t(p)] < kMinTexturePart * area[std::size_t(holds[std::size_t(p)])])
      holds[std::size_t(p)] = 0;
  for (int y = 0; y < labels.rows; ++y) {
    int* l = labels.ptr<int>(y);
    const int* pt = patches.ptr<int>(y);
    const uchar* t = textured.ptr<uchar>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (t[x] && holds[std::size_t(pt[x])] > 0) l[x] = holds[std::size_t(pt[x])];
  }
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
// pixel (0 background), feathers numbered from 1, each label one feather or
// one row of white plumes (marked in `row_of_plumes`, 0/255; below).
// Cards this light or lighter (kPaleCardMax) leave no room for paler parts; dark cards (kPaleCardMin) have
// none lighter than the feather itself (its colour already stands out).
cv::Mat label_with_pale_parts(const cv::Mat& bgr, cv::Mat& bin, double sigma, const cv::Mat& open_k,
                              double min_area, cv::Mat& pale, cv::Mat& row_of_plumes) {
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
    const double card_sigma = spread.empty() ? sigma : mad_sigma(std::move(spread));
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
  row_of_plumes = cv::Mat::zeros(bin.size(), CV_8U);
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
  std::vector<cv::Rect> part_box(static_cast<std::size_t>(np));
  for (int y = 0; y < pale_parts.rows; ++y) {
    const int* pp = pale_parts.ptr<int>(y);
    for (int x = 0; x < pale_parts.cols; ++x) {
      const auto part = std::size_t(pp[x]);
      part_box[part] = part_area[part]++ ? part_box[part] | cv::Rect(x, y, 1, 1) : cv::Rect(x, y, 1, 1);
    }
  }
  // A white tip is a fraction of its feather; a downy plume many times its base.
  std::vector<char> owned(std::size_t(np), 0);
  for (int part = 1; part < np; ++part) {
    const int best = most_id[std::size_t(part)];
    owned[std::size_t(part)] = best > 0 && feather_sized[std::size_t(best)] &&
                               stats.at<int>(best, cv::CC_STAT_AREA) >= kOwnerArea * part_area[std::size_t(part)];
  }
  // White downy feathers whose plumes touch, each on a grey base too small or
  // too faint to seed it well (the blue-jay sheet's row of four white plumes,
  // their bases joined by the thread they are glued on): a flood from the bases
  // would cut the plumes where the floods meet, halfway between the bases rather
  // than between the plumes, and a plume whose base seeds nothing would go to
  // its neighbour. A part no feather owns, at least kCutPartAreas feathers in
  // size, whose own distance-transform core falls into pieces (find_cores,
  // separate.h), is a row of plumes: with its bases (seeds in contact with it,
  // each under kOwnerArea of it divided among its pieces) it becomes one region
  // of its own, which segment_feathers cuts along the row (split_faint_row,
  // rows.h) or reports as several feathers.
  cv::Mat row_id = cv::Mat::zeros(bin.size(), CV_32S);  // 1..: each row of plumes with its bases
  std::vector<char> cut_part(std::size_t(np), 0), is_base(std::size_t(n), 0);
  int rows = 0;
  for (int part = 1; part < np; ++part) {
    if (owned[std::size_t(part)] || part_area[std::size_t(part)] < kCutPartAreas * min_area) continue;
    const cv::Rect box = part_box[std::size_t(part)];
    const Cores cores = find_cores(pale_parts(box) == part);
    if (cores.n < 2) continue;
    cut_part[std::size_t(part)] = 1;
    ++rows;
    for (int y = box.y; y < box.br().y; ++y)
      for (int x = box.x; x < box.br().x; ++x)
        if (pale_parts.at<int>(y, x) == part) row_id.at<int>(y, x) = rows;
    for (int id = 1; id < n; ++id)
      if (seed[std::size_t(id)] && contact.count(std::int64_t(part) * n + id) &&
          stats.at<int>(id, cv::CC_STAT_AREA) < kOwnerArea * part_area[std::size_t(part)] / cores.n) {
        is_base[std::size_t(id)] = 1;
        const cv::Rect b(stats.at<int>(id, cv::CC_STAT_LEFT), stats.at<int>(id, cv::CC_STAT_TOP),
                         stats.at<int>(id, cv::CC_STAT_WIDTH), stats.at<int>(id, cv::CC_STAT_HEIGHT));
        for (int y = b.y; y < b.br().y; ++y)
          for (int x = b.x; x < b.br().x; ++x)
            if (labels.at<int>(y, x) == id) row_id.at<int>(y, x) = rows;
      }
  }
  // Bases of rows seed nothing: their pixels are the row's.
  if (rows > 0)
    queue.erase(std::remove_if(queue.begin(), queue.end(), [&](const cv::Point& p) {
                  if (!is_base[std::size_t(labels.at<int>(p))]) return false;
                  labels.at<int>(p) = 0;
                  return true;
                }),
                queue.end());
  auto may_enter = [&](int part, int id) {
    if (cut_part[std::size_t(part)]) return false;
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
  cv::Mat alone = (pale | bin) & (labels == 0) & (row_id == 0), alone_labels;
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
  row_of_plumes = row_id > 0;
  if (rows > 0) {
    // Each row of plumes is a region of its own, labelled after every other.
    double top = 0;
    cv::minMaxLoc(labels, nullptr, &top);
    const int after = int(top);
    for (int y = 0; y < labels.rows; ++y) {
      int* l = labels.ptr<int>(y);
      const int* p = row_id.ptr<int>(y);
      for (int x = 0; x < labels.cols; ++x)
        if (p[x] > 0) l[x] = after + p[x];
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
  seg.card_sigma = sigma;
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
  cv::Mat row_of_plumes;  // white plumes that touch, each region of them cut along its row below
  if (bg_luma >= kPaleCardMin && bg_luma <= kPaleCardMax) {
    cv::Mat pale;
    cv::Mat labels = label_with_pale_parts(bgr, bin, sigma, open_k, min_area, pale, row_of_plumes);
    grow_into_texture(bgr, labels);
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
    if (!row_of_plumes.empty() && 2 * cv::countNonZero(comp.mask & row_of_plumes(comp.bbox)) > cv::countNonZero(comp.mask)) {
      // A row of white plumes (label_with_pale_parts): cut along the row, each
      // plume from its base, or reported as several feathers.
      measure_shape(comp, bgr.size());
      std::vector<Component> row = split_faint_row(comp, found(comp.bbox) & comp.mask, dist, bgr.size(), min_area,
                                                   {kWhiteRowSmooth, kMinWhitePlumeAspect, kWhiteRowTilt});
      if (!row.empty()) {
        for (Component& c : row) seg.feathers.push_back(std::move(c));
        continue;
      }
      comp.unseparated = true;
      seg.feathers.push_back(std::move(comp));
      continue;
    }
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
