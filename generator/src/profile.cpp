#include "plumage/generator/profile.h"

#include <algorithm>
#include <cmath>

namespace plumage {

Profile::Profile(std::vector<glm::dvec2> knots) : knots_(std::move(knots)) {
  const std::size_t n = knots_.size();
  slopes_.assign(n, 0.0);
  if (n < 2) return;
  std::vector<double> delta(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i)
    delta[i] = (knots_[i + 1].y - knots_[i].y) / (knots_[i + 1].x - knots_[i].x);
  slopes_[0] = delta[0];
  slopes_[n - 1] = delta[n - 2];
  for (std::size_t i = 1; i + 1 < n; ++i)
    slopes_[i] = delta[i - 1] * delta[i] <= 0 ? 0.0 : 0.5 * (delta[i - 1] + delta[i]);
  // Fritsch-Carlson step 5: keep (alpha, beta) inside the circle of radius 3.
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (delta[i] == 0) {
      slopes_[i] = slopes_[i + 1] = 0;
      continue;
    }
    const double a = slopes_[i] / delta[i], b = slopes_[i + 1] / delta[i];
    const double r = a * a + b * b;
    if (r > 9) {
      const double tau = 3 / std::sqrt(r);
      slopes_[i] = tau * a * delta[i];
      slopes_[i + 1] = tau * b * delta[i];
    }
  }
}

std::size_t Profile::segment(double x) const {
  const auto it = std::upper_bound(knots_.begin(), knots_.end(), x,
                                   [](double v, const glm::dvec2& k) { return v < k.x; });
  const std::size_t i = it == knots_.begin() ? 0 : std::size_t(it - knots_.begin()) - 1;
  return std::min(i, knots_.size() - 2);
}

double Profile::operator()(double x) const {
  if (knots_.empty()) return 0;
  if (knots_.size() == 1) return knots_[0].y;
  x = std::clamp(x, knots_.front().x, knots_.back().x);
  const std::size_t i = segment(x);
  const double h = knots_[i + 1].x - knots_[i].x, t = (x - knots_[i].x) / h;
  const double t2 = t * t, t3 = t2 * t;
  // Cubic Hermite basis.
  return (2 * t3 - 3 * t2 + 1) * knots_[i].y + (t3 - 2 * t2 + t) * h * slopes_[i] +
         (-2 * t3 + 3 * t2) * knots_[i + 1].y + (t3 - t2) * h * slopes_[i + 1];
}

double Profile::derivative(double x) const {
  if (knots_.size() < 2) return 0;
  x = std::clamp(x, knots_.front().x, knots_.back().x);
  const std::size_t i = segment(x);
  const double h = knots_[i + 1].x - knots_[i].x, t = (x - knots_[i].x) / h;
  const double t2 = t * t;
  return ((6 * t2 - 6 * t) * knots_[i].y + (6 * t - 6 * t2) * knots_[i + 1].y) / h +
         (3 * t2 - 4 * t + 1) * slopes_[i] + (3 * t2 - 2 * t) * slopes_[i + 1];
}

double Profile::max_value() const {
  double m = -INFINITY;
  for (const auto& k : knots_) m = std::max(m, k.y);
  return m;
}

double Profile::min_value() const {
  double m = INFINITY;
  for (const auto& k : knots_) m = std::min(m, k.y);
  return m;
}

}  // namespace plumage
