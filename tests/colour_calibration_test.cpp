// Colour calibration by rendering (apps/pipeline colour_calibration.h): the gain
// search on responses of known form, whose answer is known, and on hostile ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "plumage/pipeline/colour_calibration.h"

namespace plumage {
namespace {

// A render whose mean is floor + slope * gain per channel: light that never reaches
// the card (the R lobe) plus light that scales with the fibres' albedo.
struct Affine {
  glm::vec3 floor, slope;
  int calls = 0;
  glm::vec3 operator()(const glm::vec3& g) {
    ++calls;
    return floor + slope * g;
  }
};

TEST(ColourCalibration, AnAffineResponseIsMatchedByItsSecondProbesSecant) {
  Affine r{{0.03f, 0.02f, 0.01f}, {0.06f, 0.05f, 0.09f}};
  const glm::vec3 photo(0.10f, 0.04f, 0.05f);
  CalibrationSettings s;
  s.probes = 2;
  s.tolerance_de = 0.0;  // never stop early
  const ColourCalibration c = calibrate_colour(std::ref(r), photo, s);
  ASSERT_EQ(r.calls, 2);
  ASSERT_EQ(c.probes.size(), 2u);
  EXPECT_EQ(c.probes[0].gain, glm::vec3(1.0f));
  // The first step scales by photo / render; the second is the secant, exact here.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR((r.floor + r.slope * c.gain)[k], photo[k], 1e-5f) << k;
  EXPECT_GT(c.probes[0].de2000, 1.0);  // it was off to begin with
}

TEST(ColourCalibration, AProbeWithinToleranceEndsTheSearchAtItsGain) {
  Affine r{{0.0f, 0.0f, 0.0f}, {0.2f, 0.2f, 0.2f}};
  CalibrationSettings s;
  s.probes = 5;
  const ColourCalibration c = calibrate_colour(std::ref(r), glm::vec3(0.2f), s);
  EXPECT_EQ(r.calls, 1);
  EXPECT_EQ(c.gain, glm::vec3(1.0f));
  EXPECT_NEAR(c.probes.at(0).de2000, 0.0, 1e-9);
}

TEST(ColourCalibration, AProbeThrownOffEndsAtTheClosestProbe) {
  // A response that jumps past the photo once the gain crosses 1.2 (the inversion's
  // clear -> medulla step): the step beyond the last probe is not taken, the
  // closest probe's gain is.
  const auto jump = [](const glm::vec3& g) { return g.x < 1.2f ? 0.1f * g : 0.3f * g; };
  CalibrationSettings s;
  s.probes = 2;
  s.tolerance_de = 0.0;
  const ColourCalibration c = calibrate_colour(jump, glm::vec3(0.13f), s);
  ASSERT_EQ(c.probes.size(), 2u);
  EXPECT_LT(c.probes[0].de2000, c.probes[1].de2000);
  EXPECT_EQ(c.gain, c.probes[0].gain);
}

TEST(ColourCalibration, AProbeThrownOffIsFollowedByTheMidpointAndNoStepBeyond) {
  // The photo at 1.06 x the first render; the response jumps up by 40 % past a gain
  // of 1.035: the ratio step (1.06) lands beyond the jump, farther than the first
  // probe; the third probe halves the step back (1.03) and is the closest; the
  // probes not having converged steadily, no unprobed step beyond is taken.
  const auto jump = [](const glm::vec3& g) { return g.x < 1.035f ? 0.5f * g : 0.7f * g; };
  CalibrationSettings s;
  s.probes = 3;
  s.tolerance_de = 0.0;
  const ColourCalibration c = calibrate_colour(jump, glm::vec3(0.53f), s);
  ASSERT_EQ(c.probes.size(), 3u);
  EXPECT_NEAR(c.probes[1].gain.x, 1.06f, 1e-5);
  EXPECT_GT(c.probes[1].de2000, c.probes[0].de2000);
  EXPECT_NEAR(c.probes[2].gain.x, 1.03f, 1e-5);
  EXPECT_LT(c.probes[2].de2000, c.probes[0].de2000);
  EXPECT_EQ(c.gain, c.probes[2].gain);
}

// A white plume whose render cannot reach the photo's white (blue-jay F26 in
// substructure mode): each channel rises with its gain up to its own knee, where
// its texels clamp at the brightest fibre, the red's knee a little higher. Past
// the knees a step toward the photo barely moves the render; following the red
// on, the search had taken gains (1.57, 1.29, 1.30) and tinted the plume pink.
// It goes back to the gains before the saturated step, which differ by the
// photo's own colour, not by the knees.
struct Saturating {
  glm::vec3 slope, knee;
  glm::vec3 operator()(const glm::vec3& g) const {
    glm::vec3 r;
    for (int k = 0; k < 3; ++k) r[k] = std::min(slope[k] * g[k], knee[k] + 0.02f * slope[k] * g[k]);
    return r;
  }
};

TEST(ColourCalibration, ASaturatingRenderGoesBackToTheGainsBeforeTheSaturatedStep) {
  const Saturating r{{0.70f, 0.68f, 0.67f}, {0.77f, 0.73f, 0.72f}};
  const glm::vec3 photo(0.855f, 0.808f, 0.800f);
  CalibrationSettings s;
  s.tolerance_de = 0.0;
  const ColourCalibration c = calibrate_colour(std::cref(r), photo, s);
  ASSERT_EQ(c.probes.size(), 3u);
  // The second probe (the ratio step) is past the knees; the third, on the secant,
  // barely moved the render: the result is the second probe's gain.
  EXPECT_EQ(c.gain, c.probes[1].gain);
  const float spread = std::max({c.gain.x, c.gain.y, c.gain.z}) / std::min({c.gain.x, c.gain.y, c.gain.z});
  EXPECT_LT(spread, 1.03f);
  // A response that keeps rising (no knee) is still followed past the second probe.
  const Saturating open{{0.70f, 0.68f, 0.67f}, {9.0f, 9.0f, 9.0f}};
  const ColourCalibration d = calibrate_colour(std::cref(open), photo, s);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(open(d.gain)[k], photo[k], 1e-3f) << k;
}

TEST(ColourCalibration, NoProbesIsNoCalibration) {
  Affine r{{0.1f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.1f}};
  CalibrationSettings s;
  s.probes = 0;
  const ColourCalibration c = calibrate_colour(std::ref(r), glm::vec3(0.5f), s);
  EXPECT_EQ(r.calls, 0);
  EXPECT_EQ(c.gain, glm::vec3(1.0f));
  EXPECT_TRUE(c.probes.empty());
}

TEST(ColourCalibration, ATargetBelowTheFloorStopsAtTheSmallestGain) {
  // The photo is darker than the render's floor: no gain reaches it; the search
  // walks down by at most a factor 4 a probe and stops at min_gain.
  Affine r{{0.05f, 0.05f, 0.05f}, {0.1f, 0.1f, 0.1f}};
  CalibrationSettings s;
  s.probes = 6;
  s.tolerance_de = 0.0;
  const ColourCalibration c = calibrate_colour(std::ref(r), glm::vec3(0.01f), s);
  for (std::size_t i = 1; i < c.probes.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_GE(c.probes[i].gain[k], c.probes[i - 1].gain[k] / 4.0f * 0.999f);
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(c.gain[k], s.min_gain);
}

TEST(ColourCalibration, AChannelTheRenderDoesNotReachKeepsItsGain) {
  const auto dark_blue = [](const glm::vec3& g) { return glm::vec3(0.1f * g.x, 0.1f * g.y, 0.0f); };
  const auto nan_blue = [](const glm::vec3& g) { return glm::vec3(0.1f * g.x, 0.1f * g.y, std::nanf("")); };
  for (const auto& f : {std::function<glm::vec3(const glm::vec3&)>(dark_blue), std::function<glm::vec3(const glm::vec3&)>(nan_blue)}) {
    CalibrationSettings s;
    s.probes = 3;
    const ColourCalibration c = calibrate_colour(f, glm::vec3(0.2f, 0.05f, 0.1f), s);
    EXPECT_FLOAT_EQ(c.gain.z, 1.0f);
    EXPECT_NEAR(c.gain.x, 2.0f, 1e-4f);
    EXPECT_NEAR(c.gain.y, 0.5f, 1e-4f);
  }
}

TEST(ColourCalibration, FallingOrFlatResponsesNeverLeaveTheGainsRange) {
  // Stress: responses that are flat, fall with the gain, saturate or jump (the
  // inversion's clear -> medulla step), photo means from 1e-6 to 10: every gain is
  // finite and in [min_gain, max_gain]; where the response is rising and affine and
  // the target inside its range, three probes land within 1 %.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const CalibrationSettings s{4, 8, 0.0, 0.125f, 8.0f};
  for (int trial = 0; trial < 4000; ++trial) {
    const int kind = trial % 4;
    const glm::vec3 a(u(rng) * 0.1f, u(rng) * 0.1f, u(rng) * 0.1f);
    const glm::vec3 b(0.01f + u(rng), 0.01f + u(rng), 0.01f + u(rng));
    const auto response = [&](const glm::vec3& g) -> glm::vec3 {
      switch (kind) {
        case 0: return a + b * g;
        case 1: return a;                                   // flat
        case 2: return a + b / (glm::vec3(1.0f) + g);       // falling
        default: return a + b * g + glm::step(glm::vec3(1.5f), g) * 0.3f;  // a jump
      }
    };
    const float e = std::pow(10.0f, -6.0f + 7.0f * u(rng));
    const glm::vec3 photo(e, e * (0.2f + u(rng)), e * (0.2f + u(rng)));
    const ColourCalibration c = calibrate_colour(response, photo, s);
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(std::isfinite(c.gain[k])) << trial;
      ASSERT_GE(c.gain[k], s.min_gain) << trial;
      ASSERT_LE(c.gain[k], s.max_gain) << trial;
    }
    if (kind == 0) {
      const glm::vec3 need = (photo - a) / b;
      bool reachable = true;
      for (int k = 0; k < 3; ++k) reachable = reachable && need[k] > 0.25f && need[k] < 4.0f;
      if (reachable) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(response(c.gain)[k], photo[k], 0.01f * photo[k]) << trial << " " << k;
      }
    }
  }
}

}  // namespace
}  // namespace plumage
