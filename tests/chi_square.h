#pragma once
// Chi-square tests for the sampling tests (hair BCSDF, far-field model).
#include <algorithm>
#include <cmath>
#include <vector>

namespace plumage::test {

// Regularised upper incomplete gamma Q(a, x) (Abramowitz & Stegun 6.5.29 series for
// x < a + 1, Legendre's continued fraction 6.5.31 otherwise), for chi-square p-values.
inline double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 100000 && term > sum * 1e-15; ++n) sum += term *= x / (a + n);
    return 1.0 - sum * std::exp(log_prefix);
  }
  // Modified Lentz evaluation of the continued fraction.
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

// Pearson's chi-square of observed counts against expected ones, cells expecting
// fewer than 5 pooled into one; `total_expected` (the expected counts' sum) lets a
// test check that the pdf integrates to 1.
struct ChiSquare {
  double chi2 = 0, total_expected = 0, pvalue = 1;
  int dof = -1;
};
inline ChiSquare pearson_pooled(const std::vector<double>& expected, const std::vector<double>& observed) {
  ChiSquare r;
  double pooled_e = 0, pooled_o = 0;
  for (std::size_t k = 0; k < expected.size(); ++k) {
    r.total_expected += expected[k];
    if (expected[k] < 5) {
      pooled_e += expected[k];
      pooled_o += observed[k];
      continue;
    }
    r.chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++r.dof;
  }
  if (pooled_e > 0) {
    r.chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / std::max(pooled_e, 5.0);
    ++r.dof;
  }
  r.pvalue = gamma_q(0.5 * r.dof, 0.5 * r.chi2);
  return r;
}

}  // namespace plumage::test
