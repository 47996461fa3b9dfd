// The monotone cubic profile (Fritsch-Carlson) and the generator's random numbers.
#include <gtest/gtest.h>

#include <cmath>

#include "plumage/generator/profile.h"
#include "plumage/generator/random.h"

using namespace plumage;

TEST(Profile, InterpolatesKnotsAndNeverOvershoots) {
  Rng rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + int(rng.uniform() * 8);
    std::vector<glm::dvec2> k;
    for (int i = 0; i < n; ++i) {
      // Extreme inputs: jumps of nine orders of magnitude, knots 1e-9 apart.
      const double scale = std::pow(10.0, rng.uniform(-3, 6));
      k.push_back({double(i) / (n - 1), scale * rng.uniform()});
    }
    if (trial % 3 == 0 && n > 2) k[1].x = k[0].x + 1e-9;
    const Profile p(k);
    for (std::size_t i = 0; i < k.size(); ++i) EXPECT_NEAR(p(k[i].x), k[i].y, 1e-9 * (1 + std::abs(k[i].y)));
    for (std::size_t i = 0; i + 1 < k.size(); ++i) {
      const double lo = std::min(k[i].y, k[i + 1].y), hi = std::max(k[i].y, k[i + 1].y);
      for (int s = 1; s < 50; ++s) {
        const double x = k[i].x + (k[i + 1].x - k[i].x) * s / 50.0;
        const double y = p(x);
        ASSERT_TRUE(std::isfinite(y));
        EXPECT_GE(y, lo - 1e-9 * hi);
        EXPECT_LE(y, hi + 1e-9 * hi);
      }
    }
  }
}

TEST(Profile, DerivativeMatchesFiniteDifferences) {
  const Profile p({{0, 2}, {0.3, 9}, {0.6, 7}, {1, 0}});
  for (int i = 1; i < 100; ++i) {
    const double x = i / 100.0, h = 1e-6;
    EXPECT_NEAR(p.derivative(x), (p(x + h) - p(x - h)) / (2 * h), 1e-4) << x;
  }
  EXPECT_EQ(p(-1), 2);  // clamped outside [0,1]
  EXPECT_EQ(p(2), 0);
}

TEST(Rng, MatchesTheStandardEngineAndIsUniform) {
  // The C++ standard fixes mt19937_64's 10000th output for the default seed.
  std::mt19937_64 e;
  e.discard(9999);
  EXPECT_EQ(e(), 9981545732273789042ull);

  // Chi-square over 32 bins; 99.9% critical value for 31 dof is 61.1.
  Rng r(12345);
  const int n = 200000, bins = 32;
  std::vector<int> count(bins, 0);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    ++count[int(u * bins)];
  }
  double chi2 = 0;
  for (int c : count) chi2 += (c - double(n) / bins) * (c - double(n) / bins) / (double(n) / bins);
  EXPECT_LT(chi2, 61.1);
  EXPECT_NEAR(sum / n, 0.5, 4 * std::sqrt(1.0 / 12 / n));
  // Derived streams differ from each other and from the parent.
  EXPECT_NE(Rng::derive(1, 0), Rng::derive(1, 1));
  EXPECT_NE(Rng::derive(1, 0), Rng::derive(2, 0));
  EXPECT_NE(Rng(Rng::derive(1, 0)).uniform(), Rng(1).uniform());
}
