// The shaft model: a curve of the requested length whose tangent turns by
// bend_deg in the XY plane and arch_deg out of it, starting at the origin along +Y.
#include <gtest/gtest.h>

#include <cmath>

#include "shaft.h"

using namespace plumage;

namespace {
double degrees_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180 / M_PI;
}
}  // namespace

TEST(Shaft, LengthBendAndArchAreWhatWasAskedFor) {
  for (auto [bend, arch] : {std::pair{0.0, 0.0}, {30.0, 0.0}, {-45.0, 20.0}, {0.0, -60.0}, {90.0, 90.0}}) {
    ShaftParams p;
    p.length = 120;
    p.bend_deg = bend;
    p.arch_deg = arch;
    p.control_points = 24;
    const Shaft s(p);
    // The B-spline through the arc samples is slightly shorter than the arc.
    EXPECT_NEAR(s.length(), p.length, 2e-3 * p.length) << bend << " " << arch;
    const glm::dvec3 base = s.curve().eval(0), tip = s.curve().eval(1);
    EXPECT_NEAR(glm::length(base), 0.0, 1e-12);
    const glm::dvec3 t0 = s.curve().deriv(0), t1 = s.curve().deriv(1);
    EXPECT_LT(degrees_between(t0, {0, 1, 0}), 0.1 + 0.05 * std::hypot(bend, arch));
    // In-plane turn: the angle between the XY projections of the end tangents.
    const double turn = std::atan2(t1.x, t1.y) * 180 / M_PI - std::atan2(t0.x, t0.y) * 180 / M_PI;
    if (std::abs(arch) < 89) {
      EXPECT_NEAR(turn, bend, 0.06 * std::abs(bend) + 0.5);
    }
    // The tip bends toward +X for positive bend and toward -Z for positive arch.
    if (bend != 0) {
      EXPECT_EQ(tip.x > 0, bend > 0);
    }
    if (arch != 0) {
      EXPECT_EQ(tip.z < 0, arch > 0);
    } else {
      EXPECT_NEAR(tip.z, 0.0, 1e-9);
    }
  }
}

TEST(Shaft, FramesAreOrthonormalAndTwistAboutTheTangent) {
  ShaftParams p;
  p.bend_deg = 40;
  p.arch_deg = 25;
  const Shaft s(p);
  for (int i = 0; i <= 20; ++i) {
    const double at = s.length() * i / 20;
    const Shaft::Frame f0 = s.frame(at), f1 = s.frame(at, M_PI / 3);
    for (const Shaft::Frame& f : {f0, f1}) {
      EXPECT_NEAR(glm::length(f.t), 1, 1e-12);
      EXPECT_NEAR(glm::length(f.lateral), 1, 1e-12);
      EXPECT_NEAR(glm::length(f.dorsal), 1, 1e-12);
      EXPECT_NEAR(glm::dot(f.t, f.lateral), 0, 1e-12);
      EXPECT_NEAR(glm::dot(f.t, f.dorsal), 0, 1e-12);
      EXPECT_NEAR(glm::length(glm::cross(f.lateral, f.t) - f.dorsal), 0, 1e-12);  // dorsal = lateral x t
    }
    EXPECT_NEAR(f0.lateral.z, 0, 1e-12);  // untwisted: lateral stays in the XY plane
    EXPECT_GT(f0.dorsal.z, 0);            // and dorsal points up
    EXPECT_NEAR(glm::dot(f0.lateral, f1.lateral), 0.5, 1e-9);  // cos 60 degrees
    EXPECT_NEAR(glm::length(f0.p - s.curve().eval(s.t_at(at))), 0, 1e-12);
  }
}
