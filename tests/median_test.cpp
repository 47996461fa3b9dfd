// The project's median (the upper middle of an even count) and the MAD sigma
// built on it (common/include/plumage/common/median.h).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "plumage/common/median.h"

using namespace plumage;

TEST(Median, TheUpperMiddleAndTheMadSigmaIgnoreAnOutlier) {
  EXPECT_EQ(median(std::vector<int>{4, 1, 3, 2}), 3);
  EXPECT_EQ(median(std::vector<double>{}, -1.0), -1.0);
  // |x - 3| = 2, 1, 0, 1, 97: median 1, times 1.4826; the outlier does not count.
  EXPECT_DOUBLE_EQ(mad_sigma(std::vector<double>{1, 2, 3, 4, 100}, 3.0), 1.4826);
  // Deviations already taken (centre 0), and floats as the pale parts' grain gives them.
  EXPECT_FLOAT_EQ(float(mad_sigma(std::vector<float>{0.5f, 2.f, 1.f})), float(1.4826));
  // A Gaussian sample's MAD sigma is its sigma: 20000 draws of sigma 3, within 3 %.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(10.0, 3.0);
  std::vector<double> v(20000);
  for (double& x : v) x = g(rng);
  EXPECT_NEAR(mad_sigma(v, median(v)), 3.0, 0.09);
}
