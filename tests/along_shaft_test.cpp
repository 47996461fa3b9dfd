// The robust, confidence-weighted smoother along the shaft (smooth_along_shaft)
// and the barb-angle profile built on it (barb_angles_along_shaft): outliers
// rejected, gaps filled from the neighbours, the prior only when nothing is
// confident, and nothing but finite angles in (0, 90] out of any input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "plumage/common/error.h"
#include "plumage/generator/feather_params.h"
#include "plumage/generator/layout_to_params.h"

using namespace plumage;

namespace {

std::vector<double> stations(int n) {
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back((i + 0.5) / n);
  return t;
}

double truth(double t) { return 62.0 - 30.0 * t - 8.0 * t * t; }  // falling toward the tip, curved

}  // namespace

TEST(AlongShaft, NoisyReadingsWithOutliersFollowTheTruth) {
  // 200 seeded trials: 24 stations, Gaussian noise sigma 1.5 deg, confidences
  // 0.5-1, and up to 4 isolated stations that read something else (+-25..60 deg
  // off, fully confident). The fit's median error is half the noise, its worst
  // 3.5 deg over 4000 stations (6 deg at the two stations at either end, fitted from one side), and
  // it flags every far reading and few of the others.
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const std::vector<double> t = stations(24);
  int flagged = 0, planted = 0, false_flags = 0;
  double worst = 0, worst_end = 0;
  std::vector<double> errors;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> v, w, prior(t.size(), 45.0);
    for (double x : t) v.push_back(truth(x) + noise(rng)), w.push_back(0.5 + 0.5 * U(rng));
    std::vector<bool> bad(t.size(), false);
    for (int k = 0; k < 4; ++k) {
      const std::size_t i = std::size_t(U(rng) * t.size()) % t.size();
      // Isolated: no two within two stations (side by side at the end of the
      // shaft, two of three agreeing readings are the profile there).
      bool near = false;
      for (std::size_t j = i >= 2 ? i - 2 : 0; j <= std::min(t.size() - 1, i + 2); ++j) near |= bad[j];
      if (near) continue;
      bad[i] = true, ++planted;
      v[i] = truth(t[i]) + (U(rng) < 0.5 ? -1 : 1) * (25 + 35 * U(rng));
      w[i] = 1.0;
    }
    const AlongShaftFit fit = smooth_along_shaft(t, v, w, prior);
    ASSERT_FALSE(fit.from_prior);
    for (std::size_t i = 0; i < t.size(); ++i) {
      // The two stations at either end are fitted from one side only.
      const double e = std::fabs(fit.value[i] - truth(t[i]));
      double& w_ = i >= 2 && i + 2 < t.size() ? worst : worst_end;
      w_ = std::max(w_, e);
      errors.push_back(e);
      flagged += bad[i] && fit.outlier[i];
      false_flags += !bad[i] && fit.outlier[i];
    }
  }
  std::sort(errors.begin(), errors.end());
  printf("error median %.2f, p99 %.2f; worst inside %.2f, at the ends %.2f deg\n", errors[errors.size() / 2],
         errors[errors.size() * 99 / 100], worst, worst_end);
  EXPECT_LT(errors[errors.size() / 2], 0.8);  // noise sigma 1.5 deg
  EXPECT_LT(worst, 3.5);
  EXPECT_LT(worst_end, 6.0);
  EXPECT_EQ(flagged, planted);
  EXPECT_LT(false_flags, planted / 20);  // a clean reading is rarely 6 scales off
}

TEST(AlongShaft, SmoothingLowersTheJitterAndKeepsAStraightProfile) {
  const std::vector<double> t = stations(24);
  std::vector<double> line, zig, w(t.size(), 0.8), prior(t.size(), 45.0);
  for (std::size_t i = 0; i < t.size(); ++i) {
    line.push_back(60.0 - 25.0 * t[i]);
    zig.push_back(line.back() + (i % 2 ? 3.0 : -3.0));
  }
  const AlongShaftFit exact = smooth_along_shaft(t, line, w, prior);
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(exact.value[i], line[i], 1e-9) << i;
  const AlongShaftFit smooth = smooth_along_shaft(t, zig, w, prior);
  for (std::size_t i = 1; i + 1 < t.size(); ++i) EXPECT_NEAR(smooth.value[i], line[i], 1.0) << i;
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_FALSE(smooth.outlier[i]) << i;
}

TEST(AlongShaft, NoConfidenceGivesThePriorOneStationGivesItsValue) {
  const std::vector<double> t = stations(12);
  std::vector<double> v(t.size(), 170.0), w(t.size(), 0.0), prior;
  for (double x : t) prior.push_back(60.0 - 25.0 * x);
  const AlongShaftFit none = smooth_along_shaft(t, v, w, prior);
  EXPECT_TRUE(none.from_prior);
  EXPECT_EQ(none.value, prior);
  w[7] = 0.6, v[7] = 41.0;
  const AlongShaftFit one = smooth_along_shaft(t, v, w, prior);
  EXPECT_FALSE(one.from_prior);
  for (double a : one.value) EXPECT_DOUBLE_EQ(a, 41.0);
  // Two stations: a line through them, held within their range past the ends.
  w[2] = 0.6, v[2] = 51.0;
  const AlongShaftFit two = smooth_along_shaft(t, v, w, prior);
  EXPECT_NEAR(two.value[2], 51.0, 1e-9);
  EXPECT_NEAR(two.value[7], 41.0, 1e-9);
  EXPECT_NEAR(two.value[0], 51.0, 1e-9);
  EXPECT_NEAR(two.value[11], 41.0, 1e-9);
  EXPECT_NEAR(two.value[4], 47.0, 1e-9);
}

TEST(AlongShaft, AGapTakesItsNeighboursValues) {
  // Stations 8-15 unsure (weight 0, nonsense values): filled from either side
  // of the gap, between the values there, not from the prior.
  const std::vector<double> t = stations(24);
  std::vector<double> v, w, prior(t.size(), 10.0);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool gap = i >= 8 && i < 16;
    v.push_back(gap ? 175.0 : 60.0 - 25.0 * t[i]);
    w.push_back(gap ? 0.0 : 0.9);
  }
  const AlongShaftFit fit = smooth_along_shaft(t, v, w, prior);
  for (std::size_t i = 8; i < 16; ++i) {
    EXPECT_LE(fit.value[i], v[7] + 1e-9) << i;
    EXPECT_GE(fit.value[i], v[16] - 1e-9) << i;
    EXPECT_NEAR(fit.value[i], 60.0 - 25.0 * t[i], 1.0) << i;
    EXPECT_FALSE(fit.outlier[i]);
  }
}

TEST(AlongShaft, NonFiniteInputsCarryNoWeight) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  std::vector<double> t = stations(12), v, w(t.size(), 0.9), prior(t.size(), 45.0);
  for (double x : t) v.push_back(50.0 - 10.0 * x);
  v[1] = nan, v[3] = inf, v[5] = -inf;
  w[7] = nan, w[8] = inf, w[9] = -1.0;
  v[7] = v[8] = v[9] = 1e300;
  t[10] = nan;
  const AlongShaftFit fit = smooth_along_shaft(t, v, w, prior);
  for (std::size_t i = 0; i < t.size(); ++i) {
    ASSERT_TRUE(std::isfinite(fit.value[i])) << i;
    EXPECT_GE(fit.value[i], 40.0 - 1e-9) << i;
    EXPECT_LE(fit.value[i], 50.0 + 1e-9) << i;
    EXPECT_FALSE(fit.outlier[i]) << i;
  }
  EXPECT_NEAR(fit.value[3], 50.0 - 10.0 * t[3], 1e-9);
  // Nothing finite at all: the prior.
  std::vector<double> all_nan(t.size(), nan);
  EXPECT_TRUE(smooth_along_shaft(t, all_nan, w, prior).from_prior);
  // One value per station, each, or a named error.
  EXPECT_THROW(smooth_along_shaft(t, v, w, std::vector<double>(3, 45.0)), Error);
  AlongShaftOptions bad;
  bad.bandwidth = 0;
  EXPECT_THROW(smooth_along_shaft(t, v, w, prior, bad), Error);
}

TEST(AlongShaft, BarbAnglesAreAlwaysFiniteAndInRange) {
  // Any readings at all, confident or not: finite angles in (0, 90], and what
  // is not a barb (backward, flat away from the tip) is counted, not used.
  const double extremes[] = {0.0,  -0.0, 1e-300, 5.0,   14.9,  15.0,   45.0,   89.999, 90.0,  90.001,
                             135.0, 180.0, 360.0, 1e300, -1e300, -45.0, std::numeric_limits<double>::denorm_min()};
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> pick(0, int(std::size(extremes)) - 1);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 2 + trial % 40;
    const std::vector<double> t = stations(n);
    std::vector<double> a, c;
    for (int i = 0; i < n; ++i) a.push_back(extremes[pick(rng)]), c.push_back(U(rng) < 0.3 ? U(rng) : 0.5 + 0.5 * U(rng));
    const BarbAngleFit fit = barb_angles_along_shaft(t, a, c, 0.3 * U(rng));
    ASSERT_EQ(fit.angle_deg.size(), std::size_t(n));
    for (double v : fit.angle_deg) {
      ASSERT_TRUE(std::isfinite(v)) << trial;
      EXPECT_GT(v, 0.0) << trial;
      EXPECT_LE(v, 90.0) << trial;
    }
    EXPECT_LE(fit.backward + fit.flat + fit.outliers, fit.confident);
  }
}

TEST(AlongShaft, BarbAnglesFallBackToThePriorAndRejectNonBarbs) {
  const std::vector<double> t = stations(24);
  const double calamus_t = 0.2;
  const Profile preset = default_feather_params().left.angle_deg;
  // Backward and flat readings, however confident, are not barbs: the prior.
  std::vector<double> a(t.size(), 170.0), c(t.size(), 1.0);
  int flat = 0;
  for (std::size_t i = 0; i < t.size(); i += 2)
    if ((t[i] - calamus_t) / (1 - calamus_t) < 0.9) a[i] = 5.0, ++flat;
  BarbAngleFit fit = barb_angles_along_shaft(t, a, c, calamus_t);
  EXPECT_TRUE(fit.from_prior);
  EXPECT_EQ(fit.flat, flat);
  EXPECT_EQ(fit.backward, int(t.size()) - flat);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] > calamus_t && t[i] < 0.9) {
      EXPECT_NEAR(fit.angle_deg[i], preset((t[i] - calamus_t) / (1 - calamus_t)), 1e-9) << i;
    }
  // Flat readings near the tip are barbs: the fit keeps them there.
  std::vector<double> b, cb(t.size(), 0.9);
  for (double x : t) b.push_back(x < 0.95 ? 45.0 - 30.0 * x : 10.0);
  fit = barb_angles_along_shaft(t, b, cb, 0.0);
  EXPECT_EQ(fit.flat, 0);
  EXPECT_EQ(fit.outliers, 0);
  EXPECT_NEAR(fit.angle_deg.back(), 10.0, 4.0);
}
