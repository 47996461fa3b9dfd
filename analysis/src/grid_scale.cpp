// Scale from a regular grid or ruler: the period of the grid lines, found from
// the autocorrelation of the row and column brightness profiles of the
// background (feathers masked out), refined over many periods.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "grid_scale.h"

namespace plumage::analysis {
namespace {

// Mean brightness per row (or column) over unmasked pixels, high-passed so only
// line-like structure is left.
std::vector<double> profile(const cv::Mat& gray, const cv::Mat& keep, bool rows) {
  const int n = rows ? gray.rows : gray.cols;
  std::vector<double> sum(n, 0.0), cnt(n, 0.0);
  for (int y = 0; y < gray.rows; ++y) {
    const uchar* g = gray.ptr<uchar>(y);
    const uchar* k = keep.ptr<uchar>(y);
    for (int x = 0; x < gray.cols; ++x)
      if (k[x]) {
        const int i = rows ? y : x;
        sum[i] += g[x];
        cnt[i] += 1;
      }
  }
  std::vector<double> p(n, 0.0);
  for (int i = 0; i < n; ++i) p[i] = cnt[i] > 0 ? sum[i] / cnt[i] : 0.0;
  const int w = 15;  // wider than a line, narrower than a cell of any useful grid
  std::vector<double> hp(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double s = 0;
    int c = 0;
    for (int j = std::max(0, i - w); j <= std::min(n - 1, i + w); ++j) s += p[j], ++c;
    hp[i] = cnt[i] > 0 ? p[i] - s / c : 0.0;
  }
  return hp;
}

// Normalised autocorrelation at integer lags 0..max_lag.
std::vector<double> autocorrelation(const std::vector<double>& x, int max_lag) {
  std::vector<double> r(max_lag + 1, 0.0);
  const int n = int(x.size());
  for (int lag = 0; lag <= max_lag; ++lag) {
    double s = 0;
    for (int i = 0; i + lag < n; ++i) s += x[i] * x[i + lag];
    r[lag] = s / (n - lag);
  }
  const double r0 = r[0] > 0 ? r[0] : 1.0;
  for (double& v : r) v /= r0;
  return r;
}

struct Period {
  double px = 0, strength = 0;
};

Period line_period(const std::vector<double>& x) {
  const int n = int(x.size());
  const int max_lag = n / 3;
  if (max_lag < 16) return {};
  const auto r = autocorrelation(x, max_lag);
  // First clear peak after the zero-lag lobe.
  int best = -1;
  for (int lag = 6; lag < max_lag; ++lag)
    if (r[lag] > r[lag - 1] && r[lag] >= r[lag + 1] && r[lag] > 0.25) {
      best = lag;
      break;
    }
  if (best < 0) return {};
  // Refine: the peak positions at k * period, fitted by least squares through 0.
  double sxy = 0, sxx = 0, strength = 0;
  int used = 0;
  for (int k = 1; k * best + 2 < max_lag; ++k) {
    const int c = int(std::lround(k * (sxx > 0 ? sxy / sxx : best)));
    int m = c;
    for (int j = c - 2; j <= c + 2; ++j)
      if (j > 0 && j < max_lag && r[j] > r[m]) m = j;
    if (m <= 0 || m >= max_lag) break;
    const double den = r[m - 1] - 2 * r[m] + r[m + 1];
    const double peak = m + (den < 0 ? 0.5 * (r[m - 1] - r[m + 1]) / den : 0.0);
    sxy += k * peak;
    sxx += double(k) * k;
    strength += r[m];
    ++used;
  }
  if (used < 3) return {};
  return {sxy / sxx, strength / used};
}

}  // namespace

GridScale detect_grid(const cv::Mat& bgr, const cv::Mat& feather_mask) {
  cv::Mat gray, keep;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  const int d = std::max(3, std::min(bgr.cols, bgr.rows) / 100);
  cv::dilate(feather_mask, keep,
             cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * d + 1, 2 * d + 1)));
  keep = keep == 0;
  const Period rows = line_period(profile(gray, keep, true));
  const Period cols = line_period(profile(gray, keep, false));
  GridScale g;
  // A square grid shows the same period both ways; a ruler shows it one way,
  // which is accepted only when it is very regular.
  if (rows.px > 0 && cols.px > 0 &&
      std::fabs(rows.px - cols.px) < 0.05 * std::max(rows.px, cols.px)) {
    g.found = true;
    g.period_px = 0.5 * (rows.px + cols.px);
    g.confidence = std::clamp(std::min(rows.strength, cols.strength), 0.0, 1.0);
  } else {
    const Period& p = rows.strength > cols.strength ? rows : cols;
    if (p.px > 0 && p.strength > 0.6) {
      g.found = true;
      g.period_px = p.px;
      g.confidence = std::clamp(0.7 * p.strength, 0.0, 1.0);
    }
  }
  return g;
}

}  // namespace plumage::analysis
