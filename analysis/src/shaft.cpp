// The shaft: the feather is straightened along its principal axis, the rachis
// is the colour ridge that runs the length of the mask (found by dynamic
// programming over rows), and the calamus is the end where the vane is absent.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <opencv2/imgproc.hpp>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/median.h"
#include "shaft.h"
#include "peaks.h"
#include "segmentation.h"

namespace plumage::analysis {
using namespace thresholds::shaft;
namespace {

// Principal axis of the mask (second moments): centre, unit axis e, normal n.
void principal_axis(const Component& f, cv::Point2d& c, cv::Point2d& e) {
  const cv::Moments m = cv::moments(f.mask, true);
  c = {f.bbox.x + m.m10 / m.m00, f.bbox.y + m.m01 / m.m00};
  const double a = 0.5 * std::atan2(2 * m.mu11, m.mu20 - m.mu02);
  e = {std::cos(a), std::sin(a)};
}

// Where the rachis itself is too faint to see (thin toward the tip, covered by
// the barb roots), the vanes still say where it runs: the barbs of one vane slant
// one way and those of the other the other way. Per row of the straightened image
// the score of a column is how much the slant summed to its right differs from
// that summed to its left (structure-tensor cross term, smoothed), as a fraction
// of all the slant in the row, clamped at 0. Its sign follows from the barbs
// leaning toward the tip: `tip_step` is -1 when the tip is at the first row, +1
// at the last, 0 when unknown (then the sign that peaks over the whole feather;
// on a feather with one narrow vane both signs peak, at opposite edges). It is
// broad where the ridge is sharp, so it guides the path to the right place and
// the ridge puts it on the rachis.
cv::Mat chevron_score(const cv::Mat& S, const cv::Mat& M, int tip_step) {
  cv::Mat g, gx, gy;
  cv::cvtColor(S, g, cv::COLOR_BGR2GRAY);
  g.convertTo(g, CV_32F);
  cv::Scharr(g, gx, CV_32F, 1, 0);
  cv::Scharr(g, gy, CV_32F, 0, 1);
  cv::Mat jxy = gx.mul(gy), energy = gx.mul(gx) + gy.mul(gy);
  cv::GaussianBlur(jxy, jxy, cv::Size(0, 0), kChevronIntegration);
  cv::GaussianBlur(energy, energy, cv::Size(0, 0), kChevronIntegration);
  cv::Mat slant = 2 * jxy / (energy + 1e-3f);
  slant.setTo(0, M == 0);
  const int H = S.rows, W = S.cols;
  // A row's slanted texture (|cross term| per mask pixel) against the median
  // row's: a row with little of it (the bare quill) says little about where the
  // vanes meet.
  cv::Mat texture = cv::abs(jxy);
  texture.setTo(0, M == 0);
  std::vector<double> density(H, 0.0), dens;
  for (int y = 0; y < H; ++y) {
    const int w = cv::countNonZero(M.row(y));
    if (w == 0) continue;
    density[y] = cv::sum(texture.row(y))[0] / w;
    dens.push_back(density[y]);
  }
  const double typical = median(dens);
  cv::Mat diff(H, W, CV_32F, cv::Scalar(0));
  double up = 0, down = 0;  // summed positive and negative row peaks
  for (int y = 0; y < H; ++y) {
    const float* c = slant.ptr<float>(y);
    float* d = diff.ptr<float>(y);
    double total = 0, absum = 0;
    for (int x = 0; x < W; ++x) total += c[x], absum += std::fabs(c[x]);
    if (absum <= 0 || !(typical > 0)) continue;
    const double weight = std::min(1.0, density[y] / typical);
    double left = 0, hi = 0, lo = 0;
    for (int x = 0; x < W; ++x) {
      d[x] = float(weight * ((total - left - c[x]) - left) / absum);
      left += c[x];
      if (M.at<uchar>(y, x)) hi = std::max(hi, double(d[x])), lo = std::min(lo, double(d[x]));
    }
    up += hi, down -= lo;
  }
  // Tip at the first row: a barb right of the rachis runs toward +x and -y, its
  // stripes' gradient along (1, 1), cross term > 0, so the score is right minus left.
  if (tip_step > 0 || (tip_step == 0 && down > up)) diff = -diff;
  cv::max(diff, 0.0, diff);
  return diff;
}

// The path maximising the sum of `score` from row r0 to row r1, one column per
// row, moving at most two columns from row to row at a price of `lambda` per
// column; it stays inside the mask M in rows that hold any of it (`width`), and
// when `centre` is given (one column per row from r0), within `corridor`
// columns of it where that holds any of the mask.
std::vector<cv::Point2d> best_path(const cv::Mat& score, const cv::Mat& M, const std::vector<int>& width, int r0,
                                   int r1, double lambda, const std::vector<double>& centre, double corridor) {
  const int W = score.cols;
  const float NEG = -std::numeric_limits<float>::infinity();
  // Rows where the corridor holds no mask pixel are free of it.
  std::vector<char> bound(r1 - r0 + 1, 0);
  if (!centre.empty())
    for (int y = r0; y <= r1; ++y)
      for (int x = 0; x < W && !bound[y - r0]; ++x)
        bound[y - r0] = std::fabs(x - centre[y - r0]) <= corridor && (width[y] == 0 || M.at<uchar>(y, x));
  // A row none of whose allowed pixels the path can reach (the straightened
  // mask may jump by more than two columns) is free.
  const auto allowed = [&](int y, int x, bool free) {
    if (free) return true;
    if (width[y] > 0 && !M.at<uchar>(y, x)) return false;
    return !bound[y - r0] || std::fabs(x - centre[y - r0]) <= corridor;
  };
  std::vector<float> prev(W), cur(W);
  std::vector<signed char> back(std::size_t(r1 - r0 + 1) * W, 0);
  for (int x = 0; x < W; ++x) prev[x] = allowed(r0, x, false) ? score.at<float>(r0, x) : NEG;
  if (*std::max_element(prev.begin(), prev.end()) == NEG)
    for (int x = 0; x < W; ++x) prev[x] = score.at<float>(r0, x);
  for (int y = r0 + 1; y <= r1; ++y) {
    for (const bool free : {false, true}) {
      for (int x = 0; x < W; ++x) {
        float best = NEG;
        signed char arg = 0;
        if (!allowed(y, x, free)) {
          cur[x] = NEG;
          continue;
        }
        for (int dx = -kMaxStep; dx <= kMaxStep; ++dx) {
          const int xp = x + dx;
          if (xp < 0 || xp >= W || prev[xp] == NEG) continue;
          const float v = prev[xp] - float(lambda * std::abs(dx));
          if (v > best) best = v, arg = static_cast<signed char>(dx);
        }
        cur[x] = best != NEG ? best + score.at<float>(y, x) : NEG;
        back[std::size_t(y - r0) * W + x] = arg;
      }
      if (*std::max_element(cur.begin(), cur.end()) != NEG) break;
    }
    std::swap(prev, cur);
  }
  int x = int(std::max_element(prev.begin(), prev.end()) - prev.begin());
  std::vector<cv::Point2d> path(r1 - r0 + 1);
  for (int y = r1; y >= r0; --y) {
    path[y - r0] = {double(x), double(y)};
    x = std::clamp(x + back[std::size_t(y - r0) * W + x], 0, W - 1);
  }
  return path;
}

// A smooth of a path's column against its row that a stretch of it away from
// the rest does not pull: a running median over 2 half + 1 rows, then three
// rounds of local linear fits (tricube window of `half` rows each side) with
// Tukey's biweight on the residuals from the previous round (scale: kBiweight
// times the residuals' MAD, at least one column). A stretch shorter than
// `half` rows that leaves the line and comes back weighs nothing. This is the
// scheme of smooth_along_shaft (generator/layout_to_params.h), which is built for a few
// dozen stations (it sorts every reading by distance at every station); run on
// 101 rows of the path with the same windows it moved 42 of the photo study's
// 174 shafts by up to 12.5 mm, so it is not used here.
std::vector<double> robust_smooth(const std::vector<cv::Point2d>& path, int half) {
  const int n = int(path.size());
  std::vector<double> fit(n), window;
  for (int i = 0; i < n; ++i) {
    window.clear();
    for (int k = std::max(0, i - half); k <= std::min(n - 1, i + half); ++k) window.push_back(path[k].x);
    fit[i] = median(window);
  }
  std::vector<double> tricube(half + 1);
  for (int d = 0; d <= half; ++d) {
    const double u = double(d) / (half + 1), v = 1 - u * u * u;
    tricube[d] = v * v * v;
  }
  std::vector<double> robust(n), resid(n);
  for (int round = 0; round < kSmoothRounds; ++round) {
    for (int i = 0; i < n; ++i) resid[i] = std::fabs(path[i].x - fit[i]);
    const double c = kBiweight * std::max(1.0, mad_sigma(resid));
    for (int i = 0; i < n; ++i) {
      const double u = resid[i] / c;
      robust[i] = u < 1 ? (1 - u * u) * (1 - u * u) : 0.0;
    }
    std::vector<double> next(n);
    for (int i = 0; i < n; ++i) {
      double s0 = 0, s1 = 0, s2 = 0, t0 = 0, t1 = 0;
      for (int k = std::max(0, i - half); k <= std::min(n - 1, i + half); ++k) {
        const double w = tricube[std::abs(k - i)] * robust[k], u = k - i;
        s0 += w, s1 += w * u, s2 += w * u * u, t0 += w * path[k].x, t1 += w * u * path[k].x;
      }
      const double det = s0 * s2 - s1 * s1;
      next[i] = std::fabs(det) > 1e-9 ? (s2 * t0 - s1 * t1) / det : s0 > 0 ? t0 / s0 : fit[i];
    }
    fit = std::move(next);
  }
  return fit;
}

// The rachis as the photo shows it where it shows it, and as the smoothest
// continuation where it does not (docs/analysis.md, "The rachis"). `path`: one
// point per row (x: column, y: row) in row order, the best path through the
// ridge and chevron scores; `rho`: the ridge there over the feather's mean
// ridge; `lo`, `hi`: the mask's first and last column in each row.
//  * Seen rows. A row is a candidate when its ridge is at least kSeenRidge times
//    the mean. The rachis continues the calamus, so the first run of candidates
//    from the calamus end (gaps of at most kRunGap rows; at least kMinRunRows
//    and a tenth of the rows; else the longest run) is seen; then, round by
//    round, every candidate within kGateMin + kGateGrowth x (rows from the
//    nearest seen row) of the curve fitted so far is seen too. A line that runs
//    beside the rachis where it is hidden (a bar's edge, the colour boundary
//    between the vanes) is left out.
//  * The curve: a penalised least-squares cubic B-spline (fit_bspline_penalised,
//    K = rows / kRowsPerSegment segments, kMinSegments to kMaxSegments) through the seen rows (weight 1) and, in
//    rows narrower than kNarrow of the widest (the bare quill, a pointed tip),
//    the mask's middle (weight 12 / width^2, the inverse variance of a point
//    spread evenly across the row; wider rows are left out, since over a narrow
//    and a wide vane the middle is biased toward the wide one), with a
//    third-difference penalty: where nothing is seen the curve goes on as a
//    parabola, and it bends in an S only where seen rows make it. The penalty's
//    weight kStiffness n K^5 / (2 pi)^6 (n rows) passes half of an S one period
//    long over the shaft and a 65th of one half as long. Rows where the curve
//    comes within kInside px of the mask's edge are held there (weight 1).
struct RachisFit {
  std::vector<double> x;  // per row
  double seen = 0;        // share of the rows seen
};
RachisFit fit_rachis(const std::vector<cv::Point2d>& path, const std::vector<double>& rho,
                     const std::vector<int>& lo, const std::vector<int>& hi, bool calamus_at_bottom) {
  const int n = int(path.size());
  std::vector<char> candidate(n), seen(n, 0);
  for (int i = 0; i < n; ++i) candidate[i] = rho[i] >= kSeenRidge;
  // The first long enough run of candidates from the calamus end; else the longest.
  const int min_run = std::max(kMinRunRows, n / kMinRunShareDiv);
  auto row = [&](int k) { return calamus_at_bottom ? n - 1 - k : k; };
  int best_from = -1, best_to = -1, best_len = 0;
  for (int k = 0; k < n;) {
    if (!candidate[row(k)]) {
      ++k;
      continue;
    }
    int last = k, len = 0;
    for (int j = k; j < n && j - last <= kRunGap + 1; ++j)
      if (candidate[row(j)]) last = j, ++len;
    if (len > best_len) best_from = k, best_to = last, best_len = len;
    if (len >= min_run) break;
    k = last + 1;
  }
  for (int k = best_from; k >= 0 && k <= best_to; ++k) seen[row(k)] = candidate[row(k)];

  const int segments = std::clamp(n / kRowsPerSegment, kMinSegments, kMaxSegments);
  const double lambda = kStiffness * n * std::pow(segments, 5) / std::pow(2 * kPi, 6);
  std::vector<glm::dvec3> pts(n);
  std::vector<double> t(n), w(n);
  for (int i = 0; i < n; ++i) t[i] = n > 1 ? double(i) / (n - 1) : 0.0;
  std::vector<double> widths(n);
  for (int i = 0; i < n; ++i) widths[i] = std::max(1, hi[i] - lo[i] + 1);
  const double widest = *std::max_element(widths.begin(), widths.end());
  std::vector<double> bound(n, 0.0);  // where the curve is held inside the mask: the column it is held to
  std::vector<char> held(n, 0);
  RachisFit fit;
  fit.x.assign(n, 0.0);
  for (int round = 0; round < kMaxFitRounds; ++round) {
    for (int i = 0; i < n; ++i) {
      const double wm = widths[i] <= kNarrow * widest ? 12.0 / (widths[i] * widths[i]) : 0.0;
      const double ws = seen[i] ? kSeenWeight : 0.0, wb = held[i] ? kHeldWeight : 0.0;
      w[i] = ws + wm + wb;
      const double x = w[i] > 0 ? (ws * path[i].x + wm * 0.5 * (lo[i] + hi[i]) + wb * bound[i]) / w[i] : path[i].x;
      pts[i] = glm::dvec3(x, 0.0, 0.0);
    }
    const BSpline3 c = fit_bspline_penalised(pts, t, w, segments + 3, 3, lambda);
    for (int i = 0; i < n; ++i) fit.x[i] = c.eval(t[i]).x;
    // Rows from the nearest seen row, both ways.
    std::vector<int> dist(n, n);
    for (int i = 0, d = n; i < n; ++i) dist[i] = d = seen[i] ? 0 : std::min(n, d + 1);
    for (int i = n - 1, d = n; i >= 0; --i) dist[i] = std::min(dist[i], d = seen[i] ? 0 : std::min(n, d + 1));
    bool grew = false;
    for (int i = 0; i < n; ++i) {
      if (candidate[i] && !seen[i] && std::fabs(path[i].x - fit.x[i]) <= kGateMin + kGateGrowth * dist[i])
        seen[i] = 1, grew = true;
      const double margin = std::min(kInside, kInsideOfWidth * (hi[i] - lo[i]));
      if (!held[i] && (fit.x[i] < lo[i] + margin || fit.x[i] > hi[i] - margin)) {
        held[i] = 1, grew = true;
        bound[i] = fit.x[i] < lo[i] + margin ? lo[i] + margin : hi[i] - margin;
      }
    }
    if (!grew) break;
  }
  for (int i = 0; i < n; ++i) fit.x[i] = std::clamp(fit.x[i], double(lo[i]), double(hi[i]));
  fit.seen = n > 0 ? double(std::count(seen.begin(), seen.end(), 1)) / n : 0.0;
  return fit;
}

// Near a rounded tip the rachis fades out before the outline ends, and the best
// path there follows noise to the apex of the outline. From where the ridge
// along the path last holds a third of its typical strength, the path goes on
// straight in the direction it had over the rows before, until that line leaves
// the mask (unless that is well before the mask ends: a curved tip). `path` holds
// one point per row (x: column, y: row) in row order; `tip_step` is -1 when the
// tip is at the first row, +1 at the last.
void straighten_faded_tip(std::vector<cv::Point2d>& path, const cv::Mat& ridge, const cv::Mat& M,
                          int tip_step) {
  const int n = int(path.size());
  if (n < kMinFadeRows) return;
  std::vector<float> along(n), smooth(n);
  for (int i = 0; i < n; ++i) along[i] = ridge.at<float>(int(path[i].y), int(path[i].x));
  const int half = std::max(kFadeSmoothMin, n / kFadeSmoothDiv);
  for (int i = 0; i < n; ++i) {
    float s = 0;
    int c = 0;
    for (int k = std::max(0, i - half); k <= std::min(n - 1, i + half); ++k) s += along[k], ++c;
    smooth[i] = s / c;
  }
  const float typical =
      median(std::vector<float>(along.begin() + n / kTypicalTrimDiv, along.end() - n / kTypicalTrimDiv));
  if (!(typical > 0)) return;
  // Index order from the tip inward.
  auto at = [&](int k) { return tip_step > 0 ? n - 1 - k : k; };
  int faded = 0;  // rows at the tip end where the ridge has faded
  while (faded < n && smooth[at(faded)] < typical / kFadedRidgeDiv) ++faded;
  const int fit = std::max(kFadeFitMin, n / kFadeFitDiv);
  if (faded < kMinFadedRows || faded > n / kMaxFadedDiv) return;  // nothing to mend, or no rachis to trust
  // Least-squares line x = a + b y over the `fit` rows before the faded part.
  double sy = 0, sx = 0, syy = 0, sxy = 0;
  for (int k = faded; k < faded + fit; ++k) {
    const cv::Point2d& p = path[at(k)];
    sy += p.y, sx += p.x, syy += p.y * p.y, sxy += p.x * p.y;
  }
  const double den = fit * syy - sy * sy;
  if (!(std::fabs(den) > 1e-9)) return;
  const double b = (fit * sxy - sx * sy) / den, a = (sx - b * sy) / fit;
  const std::vector<cv::Point2d> traced = path;
  int kept = faded;  // rows at the tip end that end up beyond the mask
  for (int k = faded - 1; k >= 0; --k) {
    const int i = at(k);
    const double x = a + b * path[i].y;
    const int xi = int(std::lround(x));
    if (xi < 0 || xi >= M.cols || !M.at<uchar>(int(path[i].y), xi)) break;
    path[i].x = x;
    kept = k;
  }
  // A line that leaves the mask well before its last row means the feather
  // itself curves there (a hooked tip): keep the traced path then.
  if (kept > std::max(kMaxBeyondRows, n / kMaxBeyondDiv)) {
    path = traced;
    return;
  }
  // Drop the rows past the point where the line left the mask.
  if (tip_step > 0)
    path.resize(n - kept);
  else
    path.erase(path.begin(), path.begin() + kept);
}

// Which end of the rows r0..r1 of the straightened feather (per-row mask widths
// `width`, line strength `ridge`) is the calamus; `base_at_bottom`, when known,
// says it.
struct CalamusEnd {
  bool at_bottom = false;  // at row r1
  bool known = false;      // false: the ends are alike by every cue (then the chevron's sign decides)
  int run = 0;             // rows under kRunWidth of the widest at the calamus end (the bare quill)
};
CalamusEnd calamus_end(const std::vector<int>& width, const cv::Mat& ridge, int r0, int r1,
                       std::optional<bool> base_at_bottom) {
  // The calamus end is the one with the longer run of rows where only the
  // bare quill is left (width well under the vane's). A rounded tip (a white
  // tip on a mid-grey card, where the quill's end may hide under a glue dot)
  // can have the longer run under kRunWidth of the widest, but a quill is narrow
  // throughout: an end where at least kMinQuillRows rows, and half of its run
  // under kRunWidth, are under kQuillWidth of the widest is a quill; a rounded or pointed
  // tip narrows gradually (a half disc: a tenth as many rows under kQuillWidth as
  // under kRunWidth; a straight taper: a third). When exactly one end is a quill, it
  // is the calamus.
  const int wmax = *std::max_element(width.begin(), width.end());
  auto run = [&](int from, int step, double below) {
    int k = 0;
    for (int y = from; y >= r0 && y <= r1 && width[y] < below * wmax; y += step) ++k;
    return k;
  };
  const int run_top = run(r0, +1, kRunWidth), run_bottom = run(r1, -1, kRunWidth);
  const int quill_top = run(r0, +1, kQuillWidth), quill_bottom = run(r1, -1, kQuillWidth);
  const bool top_is_quill = quill_top >= kMinQuillRows && kQuillRunDiv * quill_top >= run_top;
  const bool bottom_is_quill = quill_bottom >= kMinQuillRows && kQuillRunDiv * quill_bottom >= run_bottom;
  CalamusEnd end;
  // Where the segmentation knows the base (a row of feathers joined there), it decides.
  if (base_at_bottom) {
    end.at_bottom = *base_at_bottom, end.known = true;
    end.run = end.at_bottom ? run_bottom : run_top;
    return end;
  }
  end.at_bottom = top_is_quill != bottom_is_quill ? bottom_is_quill : run_bottom >= run_top;
  end.known = top_is_quill != bottom_is_quill || run_top != run_bottom;
  // When neither end is a quill and both runs are a few rows (a glue dot or
  // downy barbs widen a small feather's base; blue-jay sheet F12, F22), the run
  // rule is a guess. Two cues of the feather's shape then decide when they agree:
  // the rachis is strongest toward the calamus and tapers to the tip (the mean of
  // each row's strongest ridge over the end fifth of the rows, at least kRidgeEndRatio
  // times the other end's), and a body feather is widest toward its tip (the
  // mask's area centroid along the axis lies on the tip's side of the middle).
  // Each alone disagrees with the run rule on many feathers the run rule gets
  // right (docs/analysis.md, step 4).
  if (top_is_quill == bottom_is_quill && std::max(run_top, run_bottom) <= kFewRunRows * (r1 - r0)) {
    const int end_rows = std::max(kMinEndRows, (r1 - r0) / kEndRowsDiv);
    double ridge_top = 0, ridge_bottom = 0;
    for (int k = 0; k < end_rows; ++k) {
      double hi_top, hi_bottom;
      cv::minMaxLoc(ridge.row(r0 + k), nullptr, &hi_top);
      cv::minMaxLoc(ridge.row(r1 - k), nullptr, &hi_bottom);
      ridge_top += hi_top, ridge_bottom += hi_bottom;
    }
    double area = 0, moment = 0;
    for (int y = r0; y <= r1; ++y) area += width[y], moment += width[y] * double(y - r0) / (r1 - r0);
    const double centroid = moment / std::max(area, 1.0);  // 0: first row, 1: last
    if (ridge_bottom >= kRidgeEndRatio * ridge_top && centroid < 0.5) end.at_bottom = true, end.known = true;
    if (ridge_top >= kRidgeEndRatio * ridge_bottom && centroid > 0.5) end.at_bottom = false, end.known = true;
  }
  end.run = end.at_bottom ? run_bottom : run_top;
  return end;
}

// How many quills leave the calamus end side by side: 2 when two feathers lie
// side by side with overlapping vanes (a blob whose core is one piece, so
// segmentation took it for one feather), else 1. In the rows from the calamus
// end up to where the mask is half its widest, a row holds two quills when its
// mask falls into pieces with a gap of at least kMinGap px; two quills are
// there when such rows run on for a tenth of the feather's rows (at least
// kMinRows), with a median gap of at least a fifth of the widest row. A glue
// band across one quill, a downy tuft beside it, or a split at the base makes
// a few such rows, or a narrow gap (docs/analysis.md, "Sheets").
int quills_at_calamus(const cv::Mat& M, const std::vector<int>& width, int r0, int r1, bool calamus_at_bottom) {
  const int wmax = *std::max_element(width.begin() + r0, width.begin() + r1 + 1);
  int stretch = 0, longest = 0;
  std::vector<double> gaps, longest_gaps;
  for (int k = 0; k <= r1 - r0; ++k) {
    const int y = calamus_at_bottom ? r1 - k : r0 + k;
    if (width[y] >= kQuillZoneWidth * wmax) break;
    const uchar* m = M.ptr<uchar>(y);
    int gap = 0, last_end = -1;
    for (int x = 0; x < M.cols; ++x) {
      if (!m[x]) continue;
      if (last_end >= 0 && x - last_end - 1 > gap) gap = x - last_end - 1;
      last_end = x;
    }
    if (gap >= kMinGap) {
      ++stretch;
      gaps.push_back(gap);
      if (stretch > longest) longest = stretch, longest_gaps = gaps;
    } else {
      stretch = 0;
      gaps.clear();
    }
  }
  const bool two = longest >= std::max(double(kMinRows), kMinStretch * (r1 - r0)) &&
                   median(longest_gaps) >= kMinGapOfWidest * wmax;
  return two ? 2 : 1;
}

// The first and last column of the mask in each row of the straightened frame
// (-1, -1 for a row without any).
struct RowExtent {
  int lo = -1, hi = -1;
};
std::vector<RowExtent> row_extents(const cv::Mat& M) {
  std::vector<RowExtent> extent(std::size_t(M.rows));
  for (int y = 0; y < M.rows; ++y) {
    const uchar* m = M.ptr<uchar>(y);
    for (int x = 0; x < M.cols; ++x)
      if (m[x]) extent[y].hi = x, extent[y].lo = extent[y].lo < 0 ? x : extent[y].lo;
  }
  return extent;
}

// How many tips stand out along the straightened mask's more lobed side. A
// feather's outline rises from the base to its widest and falls to the tip on
// each side, one broad lobe with perhaps a notch or two where the vane splits; a
// row of small feathers mounted side by side on a string (one blob, its long axis
// along the string) shows a tip for each feather along one side. Per row, the
// mask's extent on each side of the frame's middle column, averaged over
// 2 max(kTipSmoothMin, rows / kTipSmoothDiv) + 1 rows; a tip is a local maximum of it whose prominence
// (how far it stands above the higher of the lowest points reached on either
// side before the profile rises above it again) is at least kTipProminence of the
// largest extent on either side.
int tips_along_a_side(const cv::Mat& M, int r0, int r1) {
  const int n = r1 - r0 + 1;
  const double middle = 0.5 * M.cols;
  const std::vector<RowExtent> extent = row_extents(M);
  std::vector<double> left(n, 0.0), right(n, 0.0);
  for (int y = r0; y <= r1; ++y) {
    if (extent[y].lo < 0) continue;
    left[y - r0] = std::max(0.0, middle - extent[y].lo);
    right[y - r0] = std::max(0.0, extent[y].hi - middle);
  }
  const int half = std::max(kTipSmoothMin, n / kTipSmoothDiv);
  auto smooth = [&](const std::vector<double>& v) {
    std::vector<double> out(n, 0.0);
    for (int i = 0; i < n; ++i) {
      double sum = 0;
      for (int k = std::max(0, i - half); k <= std::min(n - 1, i + half); ++k) sum += v[k];
      out[i] = sum / (2 * half + 1);  // rows past either end count as empty
    }
    return out;
  };
  const std::vector<double> L = smooth(left), R = smooth(right);
  const double widest = std::max(*std::max_element(L.begin(), L.end()), *std::max_element(R.begin(), R.end()));
  auto tips = [&](const std::vector<double>& v) {
    int count = 0;
    for (const Peak& p : profile_peaks(v)) count += p.prominence >= kTipProminence * widest;
    return count;
  };
  return std::max(tips(L), tips(R));
}

// The coarse lines of a region: the local orientation of the grey picture in the
// straightened frame (structure tensor, gradients of the picture blurred by
// `blur` px, integrated over kIntegration of the widest row, so that barbs the
// photo barely resolves blur away while a feather's edges, rachis and colour
// bands stay), at every mask pixel 2 px from the outline, weighted by
// coherence^2 sqrt(energy).
struct Line {
  cv::Point2d p, normal;  // where, and across the line (the gradient's direction)
  double w;
};
std::vector<Line> coarse_lines(const cv::Mat& S, const cv::Mat& M, int widest, double blur = kLineBlur) {
  cv::Mat g, gx, gy;
  cv::cvtColor(S, g, cv::COLOR_BGR2GRAY);
  g.convertTo(g, CV_32F);
  cv::GaussianBlur(g, g, cv::Size(0, 0), blur);
  cv::Sobel(g, gx, CV_32F, 1, 0);
  cv::Sobel(g, gy, CV_32F, 0, 1);
  cv::Mat jxx = gx.mul(gx), jyy = gy.mul(gy), jxy = gx.mul(gy);
  const double rho = std::max(kMinIntegration, kIntegration * widest);
  for (cv::Mat* j : {&jxx, &jyy, &jxy}) cv::GaussianBlur(*j, *j, cv::Size(0, 0), rho);
  cv::Mat inner;
  cv::erode(M, inner, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kInnerKernel, kInnerKernel)));
  std::vector<Line> lines;
  for (int y = 0; y < M.rows; ++y)
    for (int x = 0; x < M.cols; ++x) {
      if (!inner.at<uchar>(y, x)) continue;
      const double xx = jxx.at<float>(y, x), yy = jyy.at<float>(y, x), xy = jxy.at<float>(y, x);
      const double energy = xx + yy;
      if (energy <= 1e-6) continue;
      const double coherence = std::sqrt((xx - yy) * (xx - yy) + 4 * xy * xy) / energy;
      const double a = 0.5 * std::atan2(2 * xy, xx - yy);  // the gradient: across the line
      lines.push_back(
          {cv::Point2d(x, y), cv::Point2d(std::cos(a), std::sin(a)), coherence * coherence * std::sqrt(energy)});
    }
  return lines;
}

// How far the stripes of a fan of overlapping feathers (a spread wing or tail,
// one blob) spread, in degrees, seen from the point they fan out from; 0 when the
// region is no fan. Each feather of a fan runs out from the wrist, so its edges,
// rachis and colour bands are lines through one point; a single feather's lines
// run along its rachis, or across it (bars), or in a herringbone (barbs), through
// no one point. The lines: coarse_lines at 1 px. The point: the least-squares
// intersection of all of them. A fan: the lines point at it (weighted mean
// cos^2 between a line and its bearing from the point at least kMinAlignment;
// 0.96 on the goldfinch sheet's spread wing, at most 0.89 on every single
// feather of the six photos) and their bearings spread over kMinSpread to
// kMaxSpread degrees (weighted 10 %-90 % range; a point inside a single
// feather, where lines along its axis point at it too, sees them all round).
double fan_spread_deg(const std::vector<Line>& lines) {
  double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
  for (const Line& l : lines) {
    const cv::Point2d& n = l.normal;
    const double pn = l.p.dot(n);
    a11 += l.w * n.x * n.x, a12 += l.w * n.x * n.y, a22 += l.w * n.y * n.y;
    b1 += l.w * n.x * pn, b2 += l.w * n.y * pn;
  }
  const double det = a11 * a22 - a12 * a12;
  if (lines.size() < kMinFanLines || det <= 1e-9 * (a11 + a22) * (a11 + a22)) return 0;  // parallel lines: no point
  const cv::Point2d c((a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det);
  double aligned = 0, total = 0;
  cv::Point2d mean_bearing(0, 0);
  for (const Line& l : lines) {
    const cv::Point2d r = l.p - c;
    const double len = std::hypot(r.x, r.y);
    if (len < 1e-9) continue;
    const double along = (-l.normal.y * r.x + l.normal.x * r.y) / len;  // cos(line, bearing)
    aligned += l.w * along * along, total += l.w;
    mean_bearing += l.w * r / len;
  }
  if (total <= 0 || aligned < kMinAlignment * total) return 0;
  const double mid = std::atan2(mean_bearing.y, mean_bearing.x);
  std::vector<std::pair<double, double>> bearing;  // (angle from the mean bearing, weight)
  for (const Line& l : lines) {
    const cv::Point2d r = l.p - c;
    bearing.emplace_back(std::remainder(std::atan2(r.y, r.x) - mid, 2 * kPi), l.w);
  }
  std::sort(bearing.begin(), bearing.end());
  const auto quantile = [&](double q) {
    double acc = 0;
    for (const auto& [angle, w] : bearing)
      if ((acc += w) >= q * total) return angle;
    return bearing.back().first;
  };
  const double spread = (quantile(kSpreadHighQuantile) - quantile(kSpreadLowQuantile)) * 180 / kPi;
  return spread >= kMinSpread && spread <= kMaxSpread ? spread : 0;
}

// How much of a region's coarse lines run along its long axis (the straightened
// frame's columns): their weighted mean cos^2 to it, 1 where there are none; an
// isotropic texture gives 1/2. `on`: where to count them (all lines when empty).
// A feather's edges and rachis run along its length; downy feathers side by
// side on a string, each plume's edges and rachis across the string, make a
// region whose lines run across it. Barbs the photo resolves run across too (a
// drawn feather with barbs 9 px apart at 60 deg to the shaft: 0.25 at 1 px), so
// the lines are taken again at kAlongBlur of the widest row, where they blur
// away (0.86); bold bars across one feather do not blur away, but its outline
// still runs along its length, while a row's rim is its tufts' ragged tips and
// the string: the rim (mask pixels within kRim of the widest row of the
// outline) is read on its own. On the six photos, at 1 px, the elongated single
// feathers read 0.43-0.94 and the robin sheet's rows of downy tufts 0.09-0.27;
// at kAlongBlur the rows read 0.18-0.27 over the region and 0.22-0.54 on the
// rim; drawn chevron bars at 75 deg, seven times the barbs' contrast
// (tests/analysis_barring_test.cpp), 0.25-0.53 over the feather and 0.79-0.86
// on its rim.
double share_along_axis(const std::vector<Line>& lines, const cv::Mat& on = cv::Mat()) {
  double along = 0, total = 0;
  for (const Line& l : lines) {
    if (!on.empty() && !on.at<uchar>(int(l.p.y), int(l.p.x))) continue;
    along += l.w * l.normal.x * l.normal.x, total += l.w;
  }
  return total > 0 ? along / total : 1.0;
}

// The weighted mean of a region's lines' doubled angles, measured from the
// straightened frame's rows (x) and divided by the total weight: its length
// says how strongly the lines run one way (0 isotropic, 1 every line one way),
// and its x is positive when that way is more than 45 deg off the long axis (y).
// A region about as wide as it is long is traced across its principal axis
// when its lines run across that axis by at least kMinLineStrength: of the three
// such regions analysed on the six photos, a blue-jay white downy plume read
// with half its neighbour (0.51, 72 deg off: its shaft ran across it) and goldfinch F17 (a fragment of
// downy tufts, 0.60, 88 deg) turn and robin F12 (0.47, 14 deg) does not; a drawn
// round feather with streaky barbs reads 0.17-0.19, its dark outline on white
// card weighing in all round (tests/analysis_test.cpp).
cv::Point2d doubled_angle_mean(const std::vector<Line>& lines) {
  double cx = 0, sx = 0, total = 0;
  for (const Line& l : lines) {
    // The line runs across its normal: (-n.y, n.x); doubled, (cos 2a, sin 2a) of that.
    const double dx = -l.normal.y, dy = l.normal.x;
    cx += l.w * (dx * dx - dy * dy), sx += l.w * 2 * dx * dy, total += l.w;
  }
  return total > 0 ? cv::Point2d(cx, sx) / total : cv::Point2d(0, 0);
}

// Sets shaft.lines_along and shaft.rim_along (Shaft::lines_across): the share
// at 1 px (`fine`, the fan's lines), and only where that runs across (rows, and
// feathers whose resolved barbs or bars cross them), the shares over the region
// and its rim at kAlongBlur of the widest row.
void lines_along_axis(const cv::Mat& S, const cv::Mat& M, int widest, const std::vector<Line>& fine, Shaft& shaft) {
  shaft.lines_along = share_along_axis(fine);
  if (shaft.lines_along >= kMaxLinesAlong) return;
  const std::vector<Line> coarse = coarse_lines(S, M, widest, std::max(1.0, kAlongBlur * widest));
  cv::Mat dt;
  cv::distanceTransform(M, dt, cv::DIST_L2, 3);
  shaft.lines_along = share_along_axis(coarse);
  shaft.rim_along = share_along_axis(coarse, dt < kRim * widest);
}

// The shaft traced in the frame straightened along `e` through `c`; `may_turn`:
// whether a region about as wide as it is long may be traced across `e` instead.
Shaft trace_along(const cv::Mat& bgr, const Component& f, const cv::Point2d& c, const cv::Point2d& e, bool may_turn) {
  const cv::Point2d n(-e.y, e.x);
  double smin = 1e300, smax = -1e300, tmin = 1e300, tmax = -1e300;
  for (const cv::Point& p : f.contour) {
    const cv::Point2d d = cv::Point2d(p) - c;
    smin = std::min(smin, d.dot(e)), smax = std::max(smax, d.dot(e));
    tmin = std::min(tmin, d.dot(n)), tmax = std::max(tmax, d.dot(n));
  }
  const int m = kFrameMargin;
  const int W = int(std::ceil(tmax - tmin)) + 2 * m, H = int(std::ceil(smax - smin)) + 2 * m;
  // Straightened frame S: column along n, row along e (S -> image).
  const cv::Point2d o = c + (tmin - m) * n + (smin - m) * e;
  const cv::Matx23d S_to_img(n.x, e.x, o.x, n.y, e.y, o.y);
  cv::Mat S, M;
  cv::warpAffine(bgr, S, S_to_img, cv::Size(W, H), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REPLICATE);
  const cv::Matx23d S_to_mask(n.x, e.x, o.x - f.bbox.x, n.y, e.y, o.y - f.bbox.y);
  cv::warpAffine(f.mask, M, S_to_mask, cv::Size(W, H), cv::INTER_NEAREST | cv::WARP_INVERSE_MAP);

  // Rows the feather spans, and its width in each.
  std::vector<int> width(H, 0);
  int r0 = H, r1 = -1;
  for (int y = 0; y < H; ++y) {
    width[y] = cv::countNonZero(M.row(y));
    if (width[y] > 0) r0 = std::min(r0, y), r1 = std::max(r1, y);
  }
  if (r1 - r0 < kMinShaftRows) throw Error("feather too short to trace a shaft");

  // A row of feathers needs no ridge: its outline says what it is.
  Shaft shaft;
  shaft.tips = tips_along_a_side(M, r0, r1);
  if (shaft.several_feathers()) return shaft;
  const int widest = *std::max_element(width.begin(), width.end());
  const std::vector<Line> lines = coarse_lines(S, M, widest);
  // Only a region longer than wide has a long axis to speak of. The principal
  // axis of one about as wide as it is long may lie across the feather (a round
  // downy plume): when its lines run across that axis, it is traced across it.
  const bool elongated = r1 - r0 + 1 >= kMinAcrossAspect * widest;
  if (may_turn && !elongated) {
    const cv::Point2d m = doubled_angle_mean(lines);
    if (m.x > 0 && std::hypot(m.x, m.y) >= kMinLineStrength) return trace_along(bgr, f, c, n, false);
  }
  shaft.fan_deg = fan_spread_deg(lines);
  if (shaft.several_feathers()) return shaft;
  if (elongated) lines_along_axis(S, M, widest, lines, shaft);
  if (shaft.several_feathers()) return shaft;

  // Ridge strength: how much a pixel differs, in the same direction, from the
  // vane on both sides of it (a line detector, so vane edges and splits, which
  // differ on one side only, score nothing), taken over a few widths and after
  // smoothing along the axis so the slanted barbs blur away while the rachis stays.
  cv::Mat Sf;
  S.convertTo(Sf, CV_32FC3);
  const double sy = std::max(kAlongSmoothMin, kAlongSmooth * H);
  cv::GaussianBlur(Sf, Sf, cv::Size(1, 2 * int(3 * sy) + 1), 0, sy);
  cv::Mat ridge(H, W, CV_32F, cv::Scalar(0));
  const int dmax = std::max(kRidgeMaxOffsetMin, int(kRidgeMaxOffset * H));
  for (int d = kRidgeMinOffset; d <= dmax; d = d < kRidgeStepFrom ? d + 1 : int(d * kRidgeGrowth))
    for (int y = 0; y < H; ++y) {
      const uchar* m = M.ptr<uchar>(y);
      const cv::Vec3f* s = Sf.ptr<cv::Vec3f>(y);
      float* r = ridge.ptr<float>(y);
      for (int x = d; x < W - d; ++x) {
        if (!m[x] || !m[x - d] || !m[x + d]) continue;
        float v = 0;
        for (int c = 0; c < 3; ++c) {
          const float a = s[x][c] - s[x - d][c], b = s[x][c] - s[x + d][c];
          if (a * b > 0) v += std::min(std::fabs(a), std::fabs(b));
        }
        r[x] = std::max(r[x], v);
      }
    }

  std::optional<bool> base_at_bottom;
  if (f.base_px) {
    const double row = (*f.base_px - o).dot(e);
    base_at_bottom = std::fabs(row - r1) < std::fabs(row - r0);
  }
  const CalamusEnd calamus = calamus_end(width, ridge, r0, r1, base_at_bottom);
  const bool calamus_at_bottom = calamus.at_bottom;
  shaft.quills = quills_at_calamus(M, width, r0, r1, calamus_at_bottom);
  if (shaft.several_feathers()) return shaft;

  // Dynamic programming: the path maximising the line score plus the vanes'
  // chevron score, moving at most two columns per row, with a small price per
  // column moved. The line score grows with the logarithm of the ridge strength
  // above the feather's mean ridge r: r log(1 + ridge / r). A line counts for being
  // a line more than for its contrast, so a faint rachis near one edge is not left
  // for a stronger line elsewhere (on flight feathers, the pale fringe of the wide
  // vane with the feather's shadow beyond it), and where two lines compete the
  // chevron score, which says on which side the barbs lie, decides. The chevron
  // weighs 2r: at 4r it alone outweighed a strong rachis where barring rather than
  // barbs sets the slant (blue-jay tail feathers).
  const double mean_ridge = cv::mean(ridge, M)[0];
  const double lambda = kMovePrice * mean_ridge;
  cv::Mat line;
  cv::log(1.0 + ridge / std::max(mean_ridge, 1e-6), line);
  line *= mean_ridge;
  const int tip_step = !calamus.known ? 0 : calamus_at_bottom ? -1 : +1;
  const cv::Mat score = line + kChevronWeight * lambda * chevron_score(S, M, tip_step);
  std::vector<cv::Point2d> rows_path = best_path(score, M, width, r0, r1, lambda, {}, 0);
  // A rachis is smooth, but where a second line runs beside it (a pale inner
  // vane's edge, a bar's border) the best path may leave it for a stretch and
  // come back. Where the path strays from its robust smooth by more than a
  // tenth of the feather's typical width, it is traced again within that
  // distance of the smooth.
  std::vector<int> widths;
  for (int y = r0; y <= r1; ++y)
    if (width[y] > 0) widths.push_back(width[y]);
  const double corridor = std::max(kCorridorMin, kCorridor * median(widths));
  const std::vector<double> centre =
      robust_smooth(rows_path, std::max(kSmoothHalfMin, int(rows_path.size()) / kSmoothHalfDiv));
  bool strays = false;
  for (std::size_t i = 0; i < rows_path.size(); ++i) strays |= std::fabs(rows_path[i].x - centre[i]) > corridor;
  if (strays) rows_path = best_path(score, M, width, r0, r1, lambda, centre, corridor);
  // The rachis seen and inferred, then traced again close to that curve so that
  // the path lies on the rachis wherever it shows, and fitted again.
  std::vector<RowExtent> extent = row_extents(M);  // an empty row takes the last one's above it
  for (int y = 0; y < H; ++y)
    if (extent[y].lo < 0) extent[y] = y > 0 ? extent[y - 1] : RowExtent{0, W - 1};
  auto rachis = [&](const std::vector<cv::Point2d>& p) {
    std::vector<double> rho(p.size());
    std::vector<int> lo(p.size()), hi(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const int y = int(p[i].y), x = int(p[i].x);
      float r = 0;
      for (int dx = -1; dx <= 1; ++dx) r = std::max(r, ridge.at<float>(y, std::clamp(x + dx, 0, W - 1)));
      rho[i] = r / std::max(mean_ridge, 1e-6);
      lo[i] = extent[y].lo, hi[i] = extent[y].hi;
    }
    return fit_rachis(p, rho, lo, hi, calamus_at_bottom);
  };
  const RachisFit first = rachis(rows_path);
  rows_path = best_path(score, M, width, r0, r1, lambda, first.x, std::max(kRetraceMin, kRetrace * median(widths)));
  const RachisFit fitted = rachis(rows_path);
  for (std::size_t i = 0; i < rows_path.size(); ++i) rows_path[i].x = fitted.x[i];
  shaft.seen = fitted.seen;
  double on_path = 0;
  for (const cv::Point2d& p : rows_path) on_path += ridge.at<float>(int(p.y), int(p.x));

  straighten_faded_tip(rows_path, ridge, M, calamus_at_bottom ? -1 : +1);

  const int step = std::max(1, (r1 - r0) / kPathSamples);
  std::vector<cv::Point2d> sampled;
  for (int i = 0; i < int(rows_path.size()); i += step) sampled.push_back(rows_path[i]);
  if (sampled.back() != rows_path.back()) sampled.push_back(rows_path.back());
  if (calamus_at_bottom) std::reverse(sampled.begin(), sampled.end());
  for (const auto& p : sampled)
    shaft.path.push_back({S_to_img(0, 0) * p.x + S_to_img(0, 1) * p.y + S_to_img(0, 2),
                          S_to_img(1, 0) * p.x + S_to_img(1, 1) * p.y + S_to_img(1, 2)});

  // Shaft width: the bare quill's width where there is one, else a typical
  // rachis proportion of the length.
  std::vector<int> quill;
  for (int k = 0; k < calamus.run; ++k) quill.push_back(width[calamus_at_bottom ? r1 - k : r0 + k]);
  if (quill.size() >= kMinQuillWidthRows) {
    shaft.width_px = median(quill);
  } else {
    shaft.width_px = std::max(kMinShaftWidth, kShaftWidthOfLength * (r1 - r0));
  }
  const double contrast = on_path / rows_path.size() / std::max(mean_ridge, 1e-6);
  shaft.confidence = std::clamp((contrast - kZeroConfidenceContrast) / kFullConfidenceSpan, 0.0, 1.0);
  return shaft;
}
}  // namespace

Shaft trace_shaft(const cv::Mat& bgr, const Component& f) {
  cv::Point2d c, e;
  principal_axis(f, c, e);
  if (f.quill_px) {
    double far = 0;
    cv::Point2d tip = *f.quill_px;
    for (const cv::Point& p : f.contour)
      if (const double d = cv::norm(cv::Point2d(p) - *f.quill_px); d > far) far = d, tip = cv::Point2d(p);
    if (far > 0) {
      e = (tip - *f.quill_px) / far;
      // Traced from the calamus on: what lies behind it along that axis, and
      // near it what lies off the axis (the corners where the cuts beside it
      // meet the base band, the neighbours' fluff), is no rachis.
      Component ahead = f;
      ahead.mask = f.mask.clone();
      const cv::Point2d across(-e.y, e.x);
      for (int y = 0; y < ahead.mask.rows; ++y)
        for (int x = 0; x < ahead.mask.cols; ++x) {
          const cv::Point2d d = cv::Point2d(x + f.bbox.x, y + f.bbox.y) - *f.quill_px;
          const double along = d.dot(e);
          if (along < 0 || (along < kQuillReach * far && std::fabs(d.dot(across)) > kQuillCorridor * far))
            ahead.mask.at<uchar>(y, x) = 0;
        }
      if (cv::countNonZero(ahead.mask) > 0) return trace_along(bgr, ahead, c, e, true);
    }
  }
  return trace_along(bgr, f, c, e, true);
}

std::string Shaft::several_feathers_why() const {
  if (quills > 1)
    return "is several feathers that lie side by side and could not be told apart (" + std::to_string(quills) +
           " quills at its base)";
  if (fan_deg > 0)
    return "is a fan of overlapping feathers (a spread wing or tail) that could not be told apart (lines fanning "
           "out over " + std::to_string(int(std::lround(fan_deg))) + " deg from one point)";
  if (tips >= kMinRowTips)
    return "is a row of feathers side by side that could not be told apart (" + std::to_string(tips) +
           " tips along one side)";
  if (lines_across())
    return "is a row of feathers side by side that could not be told apart (its lines run across it: " +
           std::to_string(int(std::lround(100 * lines_along))) + " % along its length, " +
           std::to_string(int(std::lround(100 * rim_along))) + " % along its rim)";
  return {};
}

BSpline2 fit_spline(const std::vector<glm::dvec2>& pts, int ncp) {
  // plumage::fit_bspline (chord-length parameters, ends held) on the plane z = 0.
  ncp = std::max(4, std::min(ncp, int(pts.size())));
  if (int(pts.size()) < ncp) throw Error("too few shaft points to fit a curve");
  std::vector<glm::dvec3> p3;
  for (const auto& p : pts) p3.emplace_back(p, 0.0);
  const BSpline3 c = fit_bspline(p3, ncp);
  std::vector<glm::dvec2> cp;
  for (const auto& q : c.control_points()) cp.emplace_back(q.x, q.y);
  return BSpline2(cp);
}

double spline_length(const BSpline2& c) {
  double L = 0;
  glm::dvec2 prev = c.eval(0.0);
  const int n = kLengthSamples;
  for (int i = 1; i <= n; ++i) {
    const glm::dvec2 p = c.eval(double(i) / n);
    L += glm::length(p - prev);
    prev = p;
  }
  return L;
}

}  // namespace plumage::analysis
