// Per-side vane measurements in the shaft's own frame: the photo is unrolled
// along the shaft (rows: arc length from the calamus, columns: signed distance
// to the right), then width, barb angle (structure tensor) and barb spacing
// (spectral) are read per station.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "vane.h"
#include "plumage/layout/layout.h"
#include "segmentation.h"

namespace plumage::analysis {
using namespace thresholds::vane;
namespace {

// Spacing is read on lines out to kSpacingOuter of the vane's width. A barb
// that leaves the shaft a little steeper or flatter than its neighbours crosses
// a line at offset o displaced by o times the change of cot(theta), which at
// small angles (1/sin^2 theta ~ 5 at 25 deg) outgrows the spacing itself in the
// outer vane: there the barbs meet in pairs and the periodogram peaks near two
// barbs (closed-loop study, feather 12). Nearer the shaft they are still even.

struct Unrolled {
  cv::Mat gray;  // CV_32F
  cv::Mat mask;  // CV_8U
  int R = 0;     // column of the shaft
};

// Resamples the photo on the shaft's normals: pixel (i, j) is the photo at
// C(s=j) + (i - R) N(s), with N the normal toward the feather's +X side.
Unrolled unroll(const cv::Mat& bgr, const Component& f, const BSpline2& shaft, int R) {
  const int n = kUnrollArcSamples;
  std::vector<double> ts(n + 1), ss(n + 1, 0.0);
  glm::dvec2 prev = shaft.eval(0);
  for (int i = 0; i <= n; ++i) {
    ts[i] = double(i) / n;
    const glm::dvec2 p = shaft.eval(ts[i]);
    if (i) ss[i] = ss[i - 1] + glm::length(p - prev);
    prev = p;
  }
  const int L = std::max(1, int(ss.back()));
  cv::Mat mx(L + 1, 2 * R + 1, CV_32F), my(L + 1, 2 * R + 1, CV_32F);
  std::size_t k = 0;
  for (int j = 0; j <= L; ++j) {
    while (k + 1 < ss.size() && ss[k + 1] < j) ++k;
    const double a = k + 1 < ss.size() ? (j - ss[k]) / std::max(ss[k + 1] - ss[k], 1e-9) : 0.0;
    const double t = ts[k] + a * (k + 1 < ts.size() ? ts[k + 1] - ts[k] : 0.0);
    const glm::dvec2 C = shaft.eval(t);
    const glm::dvec2 T = glm::normalize(shaft.deriv(t));
    // In the image (y down) the feather's +X side, tip up, is (-T.y, T.x).
    const glm::dvec2 N(-T.y, T.x);
    for (int i = 0; i <= 2 * R; ++i) {
      mx.at<float>(j, i) = float(C.x + (i - R) * N.x);
      my.at<float>(j, i) = float(C.y + (i - R) * N.y);
    }
  }
  Unrolled u;
  u.R = R;
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::remap(gray, u.gray, mx, my, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  u.gray.convertTo(u.gray, CV_32F);
  cv::Mat mxo = mx - float(f.bbox.x), myo = my - float(f.bbox.y);
  cv::remap(f.mask, u.mask, mxo, myo, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
  return u;
}

// Barb spacing along the shaft: the dominant period of brightness along lines
// parallel to the shaft inside the vane, from the averaged periodogram.
void spacing(const Unrolled& U, int j0, int j1, int side, double w, double shaft_w, double& period,
             double& conf) {
  period = 0, conf = 0;
  const int len = j1 - j0;
  if (len < kSpacingMinRows) return;
  const double pmin = kSpacingMinPeriodPx, pmax = std::max(pmin * kSpacingMinBandRatio, len / kSpacingWindowPeriods);
  constexpr int nf = kSpacingFrequencies;
  std::vector<double> power(nf, 0.0);
  const int hp = std::max(kSpacingHighPassMinHalf, int(pmax / 2));
  int used = 0;
  const int inner = int(std::max(shaft_w, kSpacingInner * w)), outer = int(kSpacingOuter * w);
  const int step = std::max(1, (outer - inner) / kSpacingLineSteps);
  // What every line shares: the taper of its ends and Goertzel's coefficient
  // 2 cos(2 pi f) at each frequency.
  std::vector<double> taper(len), c2(nf);
  for (int j = 0; j < len; ++j) taper[j] = 0.5 - 0.5 * std::cos(2 * kPi * (j + 0.5) / len);
  for (int k = 0; k < nf; ++k) c2[k] = 2 * std::cos(2 * kPi * (1.0 / pmax + (1.0 / pmin - 1.0 / pmax) * k / (nf - 1)));
  for (int o = inner; o <= outer; o += step) {
    const int col = U.R + side * o;
    if (col < 0 || col >= U.gray.cols) continue;
    std::vector<double> x(len);
    int in = 0;
    for (int j = 0; j < len; ++j) {
      x[j] = U.gray.at<float>(j0 + j, col);
      in += U.mask.at<uchar>(j0 + j, col) != 0;
    }
    if (in < kSpacingLineInside * len) continue;
    // High-pass (remove the slow shading: a running mean over 2 hp + 1
    // samples, shorter at the ends) and taper the ends.
    std::vector<double> prefix(len + 1, 0.0), y(len);
    for (int j = 0; j < len; ++j) prefix[j + 1] = prefix[j] + x[j];
    for (int j = 0; j < len; ++j) {
      const int a = std::max(0, j - hp), b = std::min(len - 1, j + hp);
      y[j] = (x[j] - (prefix[b + 1] - prefix[a]) / (b - a + 1)) * taper[j];
    }
    // |DFT|^2 at each frequency by Goertzel's recurrence (one multiply per
    // sample), kBlock frequencies side by side so their independent recurrences
    // overlap in the pipeline.
    constexpr int kBlock = 8;
    static_assert(nf % kBlock == 0);
    for (int k0 = 0; k0 < nf; k0 += kBlock) {
      const double* c = c2.data() + k0;
      double s1[kBlock] = {}, s2[kBlock] = {};
      for (int j = 0; j < len; ++j)
        for (int b = 0; b < kBlock; ++b) {
          const double s0 = y[j] + c[b] * s1[b] - s2[b];
          s2[b] = s1[b], s1[b] = s0;
        }
      for (int b = 0; b < kBlock; ++b) power[k0 + b] += s1[b] * s1[b] + s2[b] * s2[b] - c[b] * s1[b] * s2[b];
    }
    ++used;
  }
  if (!used) return;
  int k = int(std::max_element(power.begin(), power.end()) - power.begin());
  // Octave errors: barbs that alternate in brightness (light catching every other
  // one, or beating with the pixel grid) give a period of two barbs whose
  // harmonic at the true spacing is strong too. Take the harmonic at twice the
  // frequency when it is a clear peak of its own.
  const double f0 = 1.0 / pmax, df = (1.0 / pmin - 1.0 / pmax) / (nf - 1);
  for (;;) {
    const int k2 = int(std::lround((2 * (f0 + k * df) - f0) / df));
    if (k2 + 1 >= nf) break;
    int best = k2;
    for (int j = std::max(0, k2 - kOctaveSearchBins); j <= std::min(nf - 1, k2 + kOctaveSearchBins); ++j)
      if (power[j] > power[best]) best = j;
    const bool local_peak = best > 0 && best + 1 < nf && power[best] >= power[best - 1] &&
                            power[best] >= power[best + 1];
    if (!local_peak || power[best] < kOctavePeakShare * power[k]) break;
    k = best;
  }
  double kk = k;
  if (k > 0 && k + 1 < nf) {
    const double den = power[k - 1] - 2 * power[k] + power[k + 1];
    if (den < 0) kk = k + 0.5 * (power[k - 1] - power[k + 1]) / den;
  }
  period = 1.0 / (f0 + kk * df);
  double mean = 0;
  for (double p : power) mean += p;
  mean /= nf;
  // A single clean period stands out far above the mean of the band; noise
  // peaks reach a few times it.
  conf = std::clamp((power[k] / std::max(mean, 1e-12) - kSpacingConfFloor) / kSpacingConfRange, 0.0, 1.0);
}

// The period along a line parallel to the shaft, at offset o from it, is the
// spacing of the barbs where they cross that line, not at their roots: a barb
// rooted at s crosses it at s + o cot(theta(s)), so where the barb angle changes
// along the shaft the crossings are spread by 1 + o d(cot theta)/ds. The slope
// of cot(theta) comes from a confidence-weighted line through the station and
// its three neighbours either side (kFanningNeighbours); the measured period is divided by the factor.
void correct_spacing_for_fanning(SideMeasure& S, const std::vector<double>& offset,
                                 double station_rows) {
  const int n = int(S.angle_deg.size());
  for (int k = 0; k < n; ++k) {
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int j = std::max(0, k - kFanningNeighbours); j <= std::min(n - 1, k + kFanningNeighbours); ++j) {
      const double wgt = S.angle_conf[j];
      const double theta = S.angle_deg[j] * kPi / 180;
      if (!(wgt > kFanningMinConf) || !(theta > kFanningMinAngleRad && theta < kPi / 2)) continue;
      const double x = (j - k) * station_rows, y = 1.0 / std::tan(theta);
      sw += wgt, sx += wgt * x, sy += wgt * y, sxx += wgt * x * x, sxy += wgt * x * y;
    }
    const double den = sw * sxx - sx * sx;
    if (!(sw > 0) || !(den > 1e-9 * sw * sw * station_rows * station_rows)) continue;
    const double slope = (sw * sxy - sx * sy) / den;
    const double factor = std::clamp(1.0 + offset[k] * slope, kFanningFactorMin, kFanningFactorMax);
    if (std::isfinite(S.spacing_px[k])) S.spacing_px[k] /= factor;
  }
}

// Scales of the barb-angle tensor (pixels; kBarbScalePx, kTensorScalePx): the high-pass that removes what is
// broader than barbs, and the integration of each pixel's outer product.

// A pixel whose gradients, averaged over kEdgeScalePx, still point one way is
// on a step edge (a colour bar's edge, the outline, a highlight's rim); barbs are
// a grating of thin lines whose gradients cancel there. The share of the
// gradient energy that survives the averaging, |G * grad I|^2 / G * |grad I|^2
// (G: Gaussian of kEdgeScalePx), is ~0.5 on a blurred step and under 0.05 on
// barbs 3-10 px apart; a pixel's vote is scaled by 1 - share / kEdgeShare.

// The dominant barb orientation in a window of the unrolled image: each pixel's
// integrated tensor gives an orientation (as a barb angle from the shaft toward
// the tip, 0..180 degrees, pointing away from the shaft on `side`) and a
// coherence; a histogram (1-degree bins, smoothed over +-3, kAngleHistSmoothDeg) of the coherences,
// scaled down on step edges (`edge`, above), gives the mode, refined by the
// weighted mean of the orientations within 8 degrees (kAngleRefineDeg) of it. Confidence: the
// share of the (edge-scaled) coherence within 10 degrees (kAngleConfWindowDeg) of the mode times
// their mean, scaled by 1.4 (kAngleConfScale) so a clean barb pattern reads ~1.
// The pixels a station's barb angle and fine texture are read from: rows j0..j1 of
// the unrolled image, offsets inner..outer from the shaft on `side`, inside the
// eroded mask `interior`; fn(j, i) for each.
template <typename Fn>
void for_each_window_pixel(const cv::Mat& interior, int R, int side, int j0, int j1, int inner, int outer, Fn fn) {
  for (int j = j0; j < j1; ++j)
    for (int o = inner; o <= outer; ++o) {
      const int i = R + side * o;
      if (i >= 0 && i < interior.cols && interior.at<uchar>(j, i)) fn(j, i);
    }
}

void angle_mode(const cv::Mat& Jxx, const cv::Mat& Jxy, const cv::Mat& Jyy, const cv::Mat& edge,
                const cv::Mat& interior, int R, int side, int j0, int j1, int inner, int outer, double& angle,
                double& conf) {
  angle = NAN, conf = 0;
  std::vector<double> hist(180, 0.0);
  struct Vote {
    float angle, weight;
  };
  std::vector<Vote> votes;
  double total = 0;
  for_each_window_pixel(interior, R, side, j0, j1, inner, outer, [&](int j, int i) {
    const double a = Jxx.at<float>(j, i), b = Jxy.at<float>(j, i), d = Jyy.at<float>(j, i);
    if (!(a + d > 1e-9)) return;
    const double coherence = std::sqrt((a - d) * (a - d) + 4 * b * b) / (a + d);
    // Dominant gradient direction; barbs run across it.
    const double phi = 0.5 * std::atan2(2 * b, a - d);
    double bo = -std::sin(phi), bs = std::cos(phi);  // (offset, arc length)
    if (bo * side < 0) bo = -bo, bs = -bs;           // point away from the shaft
    const double deg = std::acos(std::clamp(bs, -1.0, 1.0)) * 180.0 / kPi;
    const double barb = std::clamp(1.0 - edge.at<float>(j, i) / kEdgeShare, 0.0, 1.0);
    if (!(barb > 0)) return;
    total += coherence * barb;
    hist[std::min(179, int(deg))] += coherence * barb;
    votes.push_back({float(deg), float(coherence * barb)});
  });
  if (!(total > 0)) return;
  int best = 0;
  double best_v = -1;
  for (int k = 0; k < 180; ++k) {
    double v = 0;
    for (int q = -kAngleHistSmoothDeg; q <= kAngleHistSmoothDeg; ++q) v += hist[std::clamp(k + q, 0, 179)];
    if (v > best_v) best_v = v, best = k;
  }
  const double mode = best + 0.5;
  double sw = 0, sa = 0, near = 0, near_c = 0;
  for (const Vote& v : votes) {
    const double dd = std::fabs(v.angle - mode);
    if (dd <= kAngleRefineDeg) sw += v.weight, sa += v.weight * v.angle;
    if (dd <= kAngleConfWindowDeg) near += v.weight, near_c += double(v.weight) * v.weight;
  }
  angle = sw > 0 ? sa / sw : mode;
  const double share = near / total, mean_coherence = near > 0 ? near_c / near : 0.0;
  conf = std::clamp(kAngleConfScale * share * mean_coherence, 0.0, 1.0);
}

// The fine texture of a window: RMS of `fine` over the pixels angle_mode reads.
void texture_rms(const cv::Mat& fine, const cv::Mat& interior, int R, int side, int j0, int j1, int inner,
                 int outer, double& rms, int& count) {
  double sum = 0;
  count = 0;
  for_each_window_pixel(interior, R, side, j0, j1, inner, outer, [&](int j, int i) {
    const double v = fine.at<float>(j, i);
    sum += v * v;
    ++count;
  });
  rms = count ? std::sqrt(sum / count) : 0.0;
}

}  // namespace

void find_downy_base(SideMeasure& S, const std::vector<double>& t, double period_px) {
  S.downy.assign(t.size(), 0);
  S.afterfeather_to_t = 0;
  // A station's texture is read when its window holds a patch of at least two
  // barb periods square (kDownyMinPeriodsSq); the vane's is the median over the middle of the shaft,
  // where a feather is pennaceous.
  const double min_px = kDownyMinPeriodsSq * period_px * period_px;
  std::vector<double> middle;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= kDownyVaneFromT && t[k] <= kDownyVaneToT && S.texture_px[k] >= min_px) middle.push_back(S.texture[k]);
  if (middle.empty()) return;
  const double vane = median(middle);
  // From the first station with a texture toward the tip, while it stays downy.
  std::size_t k = 0;
  while (k < t.size() && S.texture_px[k] < min_px) ++k;
  const std::size_t first = k;
  while (k < t.size() && S.texture_px[k] >= min_px && S.texture[k] < kDownyTexture * vane) ++k;
  // Two stations at least (kDownyMinStations; one can be a window caught on the vane's ragged
  // base), and a base, not half the feather (kDownyMaxEndT).
  if (k - first < kDownyMinStations || k >= t.size() || t[k - 1] >= kDownyMaxEndT) return;
  for (std::size_t i = first; i < k; ++i) S.downy[i] = 1;
  S.afterfeather_to_t = 0.5 * (t[k - 1] + t[k]);
}

double vane_open_share(const cv::Mat& bgr, const cv::Vec3d& card_bgr, double card_sigma, const BSpline2& shaft_px,
                       const std::vector<double>& t, const SideMeasure& measure, int side) {
  const double level = std::max(kOpenCardSigmas * card_sigma, kOpenMinLevels);
  std::size_t open = 0, read = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double w = measure.width_px[i];
    if (!(w > 0)) continue;
    const glm::dvec2 C = shaft_px.eval(t[i]);
    const glm::dvec2 d = shaft_px.deriv(t[i]);
    if (!(glm::length(d) > 0)) continue;
    const glm::dvec2 T = glm::normalize(d);
    const glm::dvec2 N = double(side) * glm::dvec2(-T.y, T.x);  // the feather's +X side is (-T.y, T.x)
    for (double r = kOpenFromWidth * w; r <= kOpenToWidth * w; r += 1.0) {
      const glm::dvec2 P = C + r * N;
      const int x = int(std::lround(P.x)), y = int(std::lround(P.y));
      if (x < 0 || y < 0 || x >= bgr.cols || y >= bgr.rows) continue;
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      bool card = true;
      for (int c = 0; c < 3; ++c) card = card && std::abs(double(p[c]) - card_bgr[c]) <= level;
      open += card;
      ++read;
    }
  }
  return read ? double(open) / double(read) : 0.0;
}

VaneMeasure measure_vanes(const cv::Mat& bgr, const Component& f, const BSpline2& shaft,
                          double shaft_width_px, int stations) {
  // Unroll only as far out as the outline reaches from the shaft.
  std::vector<glm::dvec2> axis;
  for (int i = 0; i <= kReachAxisSegments; ++i) axis.push_back(shaft.eval(i / double(kReachAxisSegments)));
  double reach = 0;
  for (std::size_t k = 0; k < f.contour.size(); k += kReachContourStride) {
    const glm::dvec2 p(f.contour[k].x, f.contour[k].y);
    double best = 1e300;
    for (std::size_t i = 0; i + 1 < axis.size(); ++i) {
      const glm::dvec2 ab = axis[i + 1] - axis[i];
      const double t =
          std::clamp(glm::dot(p - axis[i], ab) / std::max(glm::dot(ab, ab), 1e-12), 0.0, 1.0);
      best = std::min(best, glm::length(p - (axis[i] + t * ab)));
    }
    reach = std::max(reach, best);
  }
  const int R = int(std::ceil(reach)) + kUnrollMarginPx;
  const Unrolled U = unroll(bgr, f, shaft, std::min(R, kUnrollMaxHalfWidthPx));
  const int L = U.gray.rows;

  // Structure tensor at the barb scale: gradients of the photo minus its blur
  // (shading, highlights and the broad bodies of colour bars removed), each
  // pixel's outer product integrated over a few pixels so it carries the local
  // orientation of the barbs there.
  cv::Mat smooth, fine, gx, gy;
  cv::GaussianBlur(U.gray, smooth, cv::Size(0, 0), kBarbScalePx);
  fine = U.gray - smooth;
  cv::Scharr(fine, gx, CV_32F, 1, 0);
  cv::Scharr(fine, gy, CV_32F, 0, 1);
  cv::Mat Jxx = gx.mul(gx), Jxy = gx.mul(gy), Jyy = gy.mul(gy);
  for (cv::Mat* J : {&Jxx, &Jxy, &Jyy}) cv::GaussianBlur(*J, *J, cv::Size(0, 0), kTensorScalePx);
  // Step edges (angle_mode): the gradient of the blurred photo against the
  // blurred gradient energy of the photo.
  cv::Mat edge;
  {
    cv::Mat rx, ry, mx, my;
    cv::Scharr(U.gray, rx, CV_32F, 1, 0);
    cv::Scharr(U.gray, ry, CV_32F, 0, 1);
    cv::Mat energy = rx.mul(rx) + ry.mul(ry), mean_x, mean_y;
    cv::GaussianBlur(energy, energy, cv::Size(0, 0), kEdgeScalePx);
    cv::GaussianBlur(rx, mean_x, cv::Size(0, 0), kEdgeScalePx);
    cv::GaussianBlur(ry, mean_y, cv::Size(0, 0), kEdgeScalePx);
    cv::divide(mean_x.mul(mean_x) + mean_y.mul(mean_y), energy + 1e-6f, edge);
    // The tensor carries an edge's orientation a few pixels either side of it.
    cv::dilate(edge, edge, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kEdgeDilatePx, kEdgeDilatePx)));
  }
  // The outline is the strongest edge in the photo; where it runs across the
  // window (a rounded tip) it would pass for a barb pointing back toward the
  // calamus. Orientations are read only a few pixels inside the mask.
  cv::Mat interior;
  cv::erode(U.mask, interior, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(kInteriorErodePx, kInteriorErodePx)));

  // Width per row and side: the outermost mask pixel.
  std::vector<int> wl(L, 0), wr(L, 0);
  for (int j = 0; j < L; ++j) {
    const uchar* m = U.mask.ptr<uchar>(j);
    for (int i = U.gray.cols - 1; i > U.R; --i)
      if (m[i]) {
        wr[j] = i - U.R;
        break;
      }
    for (int i = 0; i < U.R; ++i)
      if (m[i]) {
        wl[j] = U.R - i;
        break;
      }
  }

  VaneMeasure out;
  std::vector<double> offsets[2];  // mean offset of the spacing lines, per station (left, right)
  for (int k = 0; k < stations; ++k) {
    const double t = (k + 0.5) / stations;
    out.t.push_back(t);
    const int c = int(t * (L - 1));
    const int h = std::max(kStationMinHalfRows, L / (2 * stations));
    const int j0 = std::max(0, c - h), j1 = std::min(L, c + h + 1);
    // A side is present where the mask reaches past the rachis, which narrows from the
    // quill's width at the calamus toward the tip as the built one does.
    const double half_shaft = 0.5 * shaft_width_px * rachis_width_fraction(t);
    for (int side : {-1, +1}) {
      SideMeasure& S = side < 0 ? out.left : out.right;
      const std::vector<int>& wv = side < 0 ? wl : wr;
      std::vector<double> ws;
      int present = 0;
      for (int j = j0; j < j1; ++j) {
        ws.push_back(wv[j]);
        present += wv[j] > half_shaft + 1;
      }
      const double w = median(ws);
      S.width_px.push_back(w);
      S.width_conf.push_back(double(present) / (j1 - j0));

      // Barb angle over the middle of the vane on this side: the most common
      // local orientation, not the mean, so that the edges of colour bars
      // across the vane (a minority of pixels, at about 90 degrees), highlights
      // and splits do not pull it (angle_mode).
      const int inner = int(std::max(shaft_width_px, kAngleInner * w)), outer = int(kAngleOuter * w);
      double angle = NAN, conf = 0, texture = 0;
      int texture_px = 0;
      if (outer > inner) {
        angle_mode(Jxx, Jxy, Jyy, edge, interior, U.R, side, j0, j1, inner, outer, angle, conf);
        texture_rms(fine, interior, U.R, side, j0, j1, inner, outer, texture, texture_px);
      }
      S.texture.push_back(texture);
      S.texture_px.push_back(texture_px);
      // Barbs leave the shaft toward the tip: an orientation pointing back
      // toward the calamus is something else (an edge, a split) and not trusted.
      S.angle_deg.push_back(angle);
      S.angle_conf.push_back(std::isfinite(angle) && angle < kAngleMaxDeg ? conf : 0.0);

      // Barb spacing over a window long enough for several periods.
      const int hw = std::max(h, kSpacingMinHalfRows);
      double p, pc;
      spacing(U, std::max(0, c - hw), std::min(L, c + hw + 1), side, w, shaft_width_px, p, pc);
      S.spacing_px.push_back(p > 0 ? p : NAN);
      S.spacing_conf.push_back(pc);
      offsets[side > 0].push_back(0.5 * (std::max(shaft_width_px, kSpacingInner * w) + kSpacingOuter * w));
    }
  }
  const double station_rows = double(L - 1) / stations;
  correct_spacing_for_fanning(out.left, offsets[0], station_rows);
  correct_spacing_for_fanning(out.right, offsets[1], station_rows);
  // Stations with nothing measurable take their nearest neighbour's value at
  // zero confidence, so every profile is complete.
  for (SideMeasure* S : {&out.left, &out.right})
    for (auto* v : {&S->angle_deg, &S->spacing_px}) {
      for (int k = 0; k < stations; ++k) {
        if (!std::isnan((*v)[k])) continue;
        double fill = NAN;
        for (int dk = 1; dk < stations && std::isnan(fill); ++dk) {
          if (k - dk >= 0 && !std::isnan((*v)[k - dk]))
            fill = (*v)[k - dk];
          else if (k + dk < stations && !std::isnan((*v)[k + dk]))
            fill = (*v)[k + dk];
        }
        (*v)[k] = std::isnan(fill) ? (v == &S->angle_deg ? kAngleFillDeg : 0.0) : fill;
      }
    }
  return out;
}

}  // namespace plumage::analysis
