#pragma once
// What the fibre BCSDF tests share (hair_bcsdf_test.cpp, medulla_test.cpp,
// stress_test.cpp): a platform-independent random stream, directions on the sphere
// parameterised by x = sin(theta) (the tangent component) and phi, a jittered
// equal-area integral over the sphere, and Pearson's chi-square of a BCSDF's sampler
// against its pdf.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "chi_square.h"
#include "plumage/common/constants.h"
#include "plumage/renderer/hair_bcsdf.h"

namespace plumage::test {

// splitmix64: tiny, fast and the same on every platform (std distributions are not).
struct Rng {
  std::uint64_t s;
  explicit Rng(std::uint64_t seed) : s(seed) {}
  std::uint64_t bits() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(bits() >> 11) * 0x1.0p-53; }  // [0,1)
  float uniformf() { return float(bits() >> 40) * 0x1.0p-24f; }  // [0,1)
  double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  template <class T, std::size_t N>
  T pick(const T (&a)[N]) { return a[bits() % N]; }
};

// A unit direction in the fibre frame (+x the tangent) from sin(theta) and phi:
// equal areas in (x, phi) are equal solid angles, d omega = dx dphi.
inline glm::vec3 direction(double x, double phi) {
  const double c = std::sqrt(std::max(0.0, 1.0 - x * x));
  return glm::vec3(float(x), float(c * std::sin(phi)), float(c * std::cos(phi)));
}

inline glm::vec3 uniform_direction(Rng& rng) { return direction(rng.range(-1, 1), rng.range(-kPi, kPi)); }

// Jittered-stratified uniform estimate of the integral over the sphere of g(wi):
// n x n equal-area cells, one uniform point in each.
template <class G>
glm::dvec3 stratified_sphere_integral(int n, Rng& rng, G&& g) {
  glm::dvec3 sum(0.0);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double x = -1.0 + 2.0 * (a + rng.uniform()) / n;
      const double phi = -kPi + 2.0 * kPi * (b + rng.uniform()) / n;
      sum += glm::dvec3(g(direction(x, phi)));
    }
  return sum * (4.0 * kPi / (double(n) * n));
}

// Pearson's chi-square of `nsamples` directions from bcsdf.sample(wo, ...) against
// its pdf integrated over 24 x 48 equal-area (sin theta, phi) cells (8 x 8 midpoints
// each), cells expecting fewer than 5 samples pooled. `sampled` is false when a
// sample was refused.
inline ChiSquare sampler_chi_square(const HairBCSDF& bcsdf, const glm::vec3& wo, Rng& rng, int nsamples,
                                    bool* sampled) {
  const int nx = 24, nphi = 48, sub = 8;
  std::vector<double> expected(nx * nphi, 0.0), observed(nx * nphi, 0.0);
  const double dx = 2.0 / nx, dphi = 2 * kPi / nphi;
  for (int a = 0; a < nx; ++a)
    for (int b = 0; b < nphi; ++b) {
      double sum = 0;
      for (int i = 0; i < sub; ++i)
        for (int j = 0; j < sub; ++j)
          sum += bcsdf.pdf(wo, direction(-1 + (a + (i + 0.5) / sub) * dx, -kPi + (b + (j + 0.5) / sub) * dphi));
      expected[a * nphi + b] = sum * dx * dphi / (sub * sub) * nsamples;
    }
  *sampled = true;
  for (int k = 0; k < nsamples; ++k) {
    const auto s = bcsdf.sample(wo, {rng.uniformf(), rng.uniformf()}, {rng.uniformf(), rng.uniformf()});
    if (!s) {
      *sampled = false;
      continue;
    }
    const double x = std::clamp(double(s->wi.x), -1.0, 1.0);
    const double phi = std::atan2(double(s->wi.y), double(s->wi.z));
    observed[std::min(nx - 1, int((x + 1) / dx)) * nphi + std::clamp(int((phi + kPi) / dphi), 0, nphi - 1)] += 1;
  }
  return pearson_pooled(expected, observed);
}

}  // namespace plumage::test
