// Rows of faint feathers: patches of grey down joined into their feathers and
// cut along their row (rows.h).
#include "rows.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <opencv2/imgproc.hpp>

#include "plumage/common/constants.h"
#include "peaks.h"
#include "regions.h"
#include "thresholds.h"

namespace plumage::analysis {
using namespace thresholds::segmentation;

namespace {

// `raw` convolved with the Gaussian `kernel` (2 reach + 1 weights), the profile's
// ends not padded.
std::vector<double> smoothed(const std::vector<double>& raw, const std::vector<double>& kernel, int reach) {
  std::vector<double> out(raw.size(), 0.0);
  for (std::size_t i = 0; i < raw.size(); ++i)
    for (int k = -reach; k <= reach; ++k) {
      const long j = long(i) + k;
      if (j >= 0 && j < long(raw.size())) out[i] += kernel[std::size_t(k + reach)] * raw[std::size_t(j)];
    }
  return out;
}

// The positions of a profile's peaks that stand out by kRowProminence of its
// maximum, in order along it (profile_peaks' order).
std::vector<int> prominent_peaks(const std::vector<double>& profile) {
  const double most = *std::max_element(profile.begin(), profile.end());
  std::vector<int> at;
  for (const Peak& p : profile_peaks(profile))
    if (p.prominence >= kRowProminence * most) at.push_back(p.at);
  return at;
}

}  // namespace

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
// drawn plume alone is one peak (`reading` sets the smoothing and the aspect
// below; a row of white plumes reads with its own). Returns the pieces when there are two or
// more, each a feather in size (`min_area`, kMinPiece of the largest) and
// standing across the row, at least kMinPlumeAspect times as long along the cut
// as it is wide across the row (those plumes 2.07-3.20; a plume cut from its
// own downy base, where the direction found runs along one feather, 0.73-1.17;
// tufts on a string 1.36-2.02, a row of them 0.73-2.13); otherwise nothing.
std::vector<Component> split_faint_row(const Component& region, const cv::Mat& own, const cv::Mat& dist,
                                       const cv::Size& image, double min_area, const RowReading& reading) {
  struct Px {
    int x, y;
    double w;         // 0 in the region's holes (filled, but card)
    double s = 0, t = 0;  // across and along the row, once its direction is found
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
  const double sigma = std::max(kRowMinSigmaPx, reading.smooth * std::sqrt(double(cv::countNonZero(own))));
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
    std::vector<double> raw(std::size_t(std::lround(s1 - s0)) + 1, 0.0);
    for (const Px& p : px) raw[std::size_t(std::lround(p.x * ux + p.y * uy - s0))] += p.w;
    std::vector<double> smooth = smoothed(raw, kernel, reach);
    const double most = *std::max_element(smooth.begin(), smooth.end());
    if (most <= 0) continue;
    double variation = 0;
    for (std::size_t i = 1; i < smooth.size(); ++i) variation += std::fabs(smooth[i] - smooth[i - 1]);
    variation /= most;
    if (variation > best.variation) best = {ux, uy, s0, variation, std::move(smooth)};
  }
  if (best.profile.empty()) return {};
  const std::vector<double>& v = best.profile;
  const std::vector<int> plumes = prominent_peaks(v);
  if (plumes.size() < 2) return {};
  // Each pixel across the row (s, from the profile's start) and along it (t).
  for (Px& p : px) p.s = p.x * best.ux + p.y * best.uy - best.s0, p.t = -p.x * best.uy + p.y * best.ux;
  // The cuts between neighbouring plumes: lines s = at + slope (t - t_pivot)
  // (s across the row from the profile's start, t along the feathers), straight
  // across the row at the profile's lowest point between the two; with a tilt
  // allowed (reading.max_tilt_deg) and the row's base end known, the line
  // through the gap between their bases, at any tilt up to it, over the fewest
  // of the region's own pixels (weighed as in the profile): plumes that lean
  // apart are cut along the gap between them, each with its own base.
  struct Cut {
    double at = 0, slope = 0;
  };
  double t_min = 1e300, t_max = -1e300;
  for (const Px& p : px) t_min = std::min(t_min, p.t), t_max = std::max(t_max, p.t);
  const double t_mid = 0.5 * (t_min + t_max);
  std::vector<Cut> cuts;
  for (std::size_t i = 0; i + 1 < plumes.size(); ++i)
    cuts.push_back({double(std::min_element(v.begin() + plumes[i], v.begin() + plumes[i + 1]) - v.begin()), 0.0});
  // Feathers in a row join at their bases (a glue band, downy bases): along the
  // cuts, the region's own pixels lie toward that end. When their mean lies
  // kBaseSide of the region's extent along the feathers off its middle, each
  // piece's base is its end on that side (the blue-jay sheet's two groups:
  // 0.20-0.23 and 0.11-0.13 toward their bands at 0.75x, 1x and 1.5x and turned
  // a quarter).
  int base_side = 0;  // +1: toward larger t, -1: toward smaller t
  {
    double t_sum = 0;  // over the region's own pixels within 1 px of a cut
    int t_count = 0;
    for (const Px& p : px) {
      if (p.w <= 0) continue;
      for (const Cut& c : cuts)
        if (std::fabs(p.s - c.at) <= 1.0) t_sum += p.t, ++t_count;
    }
    if (t_count > 0) {
      const double off = t_sum / t_count - t_mid;
      if (std::fabs(off) >= kBaseSide * (t_max - t_min)) base_side = off > 0 ? 1 : -1;
    }
  }
  // A row whose cuts may lean and whose base end is known (the white plumes on
  // their thread): its cuts turn about the gaps between its bases.
  const bool leaning = reading.max_tilt_deg > 0 && base_side != 0;
  double t_pivot = t_mid;  // where leaning cuts turn
  double base_band = 0;    // and the base band's length (px)
  if (leaning) {
    // Leaning cuts turn about the gap between two bases, in the band of the row
    // kBaseBand of its length from its base end, and lean along the gap
    // between the plumes above.
    const int rows_t = int(std::lround(t_max - t_min)) + 1, cols_s = int(v.size());
    cv::Mat grid = cv::Mat::zeros(rows_t, cols_s, CV_64F);  // the own pixels' weights on the (t, s) grid
    for (const Px& p : px) {
      const int si = int(std::lround(p.s)), ti = int(std::lround(p.t - t_min));
      if (si >= 0 && si < cols_s && ti >= 0 && ti < rows_t) grid.at<double>(ti, si) += p.w;
    }
    const int band = std::max(1, int(std::lround(kBaseBand * rows_t)));
    const int band_lo = base_side > 0 ? rows_t - band : 0;
    t_pivot = t_min + band_lo + 0.5 * band;
    base_band = band;
    // The band's own profile, smoothed as the row's: a peak per base. Only
    // when it shows one base per plume do the cuts lean.
    std::vector<double> raw(std::size_t(cols_s), 0.0);
    for (int ti = band_lo; ti < band_lo + band; ++ti)
      for (int si = 0; si < cols_s; ++si) raw[std::size_t(si)] += grid.at<double>(ti, si);
    const std::vector<double> base_profile = smoothed(raw, kernel, reach);
    const std::vector<int> bases = prominent_peaks(base_profile);
    const int steps = bases.size() == plumes.size() ? int(std::floor(reading.max_tilt_deg / (180.0 / kRowAngles))) : -1;
    for (std::size_t i = 0; i + 1 < plumes.size() && steps >= 0; ++i) {
      const int at = int(std::min_element(base_profile.begin() + bases[i], base_profile.begin() + bases[i + 1]) -
                         base_profile.begin());
      double least = 1e300;
      for (int a = 0; a <= 2 * steps; ++a) {
        const int k = (a + 1) / 2 * (a % 2 ? 1 : -1);  // 0, 1, -1, 2, -2, ...: the straighter first on a tie
        const double slope = std::tan(k * kPi / kRowAngles);
        double mass = 0;
        for (int ti = 0; ti < rows_t && mass < least; ++ti) {
          const int si = int(std::lround(at + slope * (ti + t_min - t_pivot)));
          const double* g = grid.ptr<double>(ti);
          for (int d = -1; d <= 1; ++d)
            if (si + d >= 0 && si + d < cols_s) mass += g[si + d];
        }
        if (mass < least) least = mass, cuts[i] = {double(at), slope};
      }
    }
  }
  // Which piece a pixel is in: how many cuts lie on its lower side.
  auto piece_of = [&](double s, double t) {
    std::size_t k = 0;
    for (const Cut& c : cuts) k += s >= c.at + c.slope * (t - t_pivot);
    return k;
  };
  const std::size_t n = plumes.size();
  std::vector<cv::Mat> masks(n);
  for (cv::Mat& m : masks) m = cv::Mat::zeros(region.mask.size(), CV_8U);
  // Each piece's extent across the row (along u, less its lean) and along its
  // feathers (t). A piece between leaning cuts leans as they do on average: its
  // extent across is measured, and its base placed, along that lean.
  std::vector<double> lean(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0;
    int count = 0;
    if (i > 0) sum += cuts[i - 1].slope, ++count;
    if (i < cuts.size()) sum += cuts[i].slope, ++count;
    lean[i] = count ? sum / count : 0.0;
  }
  std::vector<double> lo_u(n, 1e300), hi_u(n, -1e300), lo_v(n, 1e300), hi_v(n, -1e300);
  std::vector<std::vector<double>> spread(n);  // cuts allowed to lean: each piece's pixels across
  std::vector<double> base_sw(n, 0.0), base_w(n, 0.0);  // and its own pixels' weighted sum across in the base band
  for (const Px& p : px) {
    const double s = p.s, t = p.t;
    const std::size_t piece = piece_of(s, t);
    masks[piece].at<uchar>(p.y, p.x) = 255;
    const double across = s - lean[piece] * (t - t_pivot);
    if (leaning && std::fabs(t - t_pivot) <= 0.5 * base_band)
      base_sw[piece] += p.w * s, base_w[piece] += p.w;
    lo_u[piece] = std::min(lo_u[piece], across), hi_u[piece] = std::max(hi_u[piece], across);
    if (reading.max_tilt_deg > 0) spread[piece].push_back(across);
    lo_v[piece] = std::min(lo_v[piece], t), hi_v[piece] = std::max(hi_v[piece], t);
  }
  // Where cuts may lean (a row of white plumes) the fluff a plume spreads past its
  // neighbour's cut widens its extent: its width is the middle kWidthShare of its
  // pixels.
  std::vector<double> width(n);
  for (std::size_t i = 0; i < n; ++i) {
    width[i] = hi_u[i] - lo_u[i] + 1;
    if (spread[i].size() < 2) continue;
    std::sort(spread[i].begin(), spread[i].end());
    const double m = spread[i].size() - 1.0, cut = 0.5 * (1 - kWidthShare);
    width[i] = spread[i][std::size_t(std::lround((1 - cut) * m))] - spread[i][std::size_t(std::lround(cut * m))] + 1;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (hi_v[i] - lo_v[i] < reading.min_aspect * width[i]) return {};
  std::vector<Component> pieces;
  double largest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    cv::Mat& m = masks[i];
    // Plumes on a thread (leaning cuts: the white row): the thread between
    // their bases, a few pixels thin, is no part of a plume's outline.
    if (leaning)
      cv::morphologyEx(m, m, cv::MORPH_OPEN,
                       cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(kThreadOpenPx, kThreadOpenPx)));
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
      const double t = base_side > 0 ? hi_v[i] : lo_v[i];
      const double s = 0.5 * (lo_u[i] + hi_u[i]) + lean[i] * (t - t_pivot) + best.s0;
      c.base_px = cv::Point2d(s * best.ux - t * best.uy, s * best.uy + t * best.ux) + cv::Point2d(region.bbox.tl());
      if (leaning && base_w[i] > 0) {
        // Leaning cuts: the calamus is where the piece's base band weighs, across.
        const double q = base_sw[i] / base_w[i] + best.s0;
        c.quill_px = cv::Point2d(q * best.ux - t * best.uy, q * best.uy + t * best.ux) + cv::Point2d(region.bbox.tl());
      }
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

}  // namespace plumage::analysis
