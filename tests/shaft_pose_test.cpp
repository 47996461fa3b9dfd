// lay_along_shaft: a built feather carried from its own shaft onto a measured one
// keeps each point's arc length along the shaft and its lateral offset from it.
#include <gtest/gtest.h>

#include <cmath>

#include "plumage/common/bspline.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/generator/shaft_pose.h"

using namespace plumage;

namespace {

constexpr double kLength = 10.0;

// A straight built shaft along +Y from the origin, and barbs as straight rows of
// points at a fixed lateral offset (+X is the right vane).
Feather straight_feather(const std::vector<double>& offsets) {
  Feather f;
  Curve shaft;
  shaft.kind = CurveKind::Shaft;
  for (int i = -1; i <= 9; ++i) shaft.points.push_back({glm::vec3(0, float(kLength * i / 8.0), 0), 0.1f});
  f.curves.push_back(shaft);
  for (double d : offsets) {
    Curve barb;
    barb.side = d < 0 ? VaneSide::Left : VaneSide::Right;
    for (int i = 0; i <= 8; ++i)
      barb.points.push_back({glm::vec3(float(d), float(kLength * i / 8.0), 0.25f), 0.02f, glm::vec3(0, 0, 1)});
    f.curves.push_back(barb);
  }
  return f;
}

// A measured shaft of the same length bending both ways: x = a sin(2 pi y / L).
BSpline2 s_shaft(double a) {
  std::vector<glm::dvec2> p;
  const int n = 40;
  for (int i = -1; i <= n + 1; ++i) {
    const double y = kLength * i / n;
    p.push_back({a * std::sin(2 * kPi * y / kLength), y});
  }
  return BSpline2(p);
}

// Nearest point of the curve, by dense sampling: (distance, arc length there, signed lateral offset).
struct Near {
  double dist, s, d;
};
Near nearest(const BSpline2& c, const glm::dvec2& q) {
  Near best{1e300, 0, 0};
  double s = 0;
  glm::dvec2 prev = c.eval(0);
  for (int i = 0; i <= 20000; ++i) {
    const glm::dvec2 p = c.eval(i / 20000.0);
    s += glm::length(p - prev);
    prev = p;
    const double dist = glm::length(q - p);
    if (dist < best.dist) {
      const glm::dvec2 t = glm::normalize(c.deriv(i / 20000.0));
      best = {dist, s, glm::dot(q - p, glm::dvec2(t.y, -t.x))};
    }
  }
  return best;
}

}  // namespace

TEST(ShaftPose, PointsKeepTheirArcLengthAndOffsetOnABentShaft) {
  const double amplitude = 0.5;  // the measured shaft swings 0.5 mm either way of the built one
  const std::vector<double> offsets = {-2.0, -0.5, 0.7, 3.0};
  Feather f = straight_feather(offsets);
  const BSpline2 target = s_shaft(amplitude);
  // Arc length of the target: the built points' arc length maps by the ratio of lengths.
  const double scale = arc_length(BSpline3([&] {
                         std::vector<glm::dvec3> v;
                         for (const auto& p : target.control_points()) v.push_back(glm::dvec3(p, 0));
                         return v;
                       }())) /
                       kLength;
  lay_along_shaft(f, target);

  double worst_shaft = 0, worst_offset = 0, worst_along = 0;
  for (std::size_t k = 1; k < f.curves.size(); ++k)
    for (std::size_t i = 0; i < f.curves[k].points.size(); ++i) {
      const ControlPoint& cp = f.curves[k].points[i];
      const Near n = nearest(target, glm::dvec2(cp.p));
      worst_offset = std::max(worst_offset, std::fabs(n.d - offsets[k - 1]));
      worst_along = std::max(worst_along, std::fabs(n.s - scale * kLength * i / 8.0));
      EXPECT_FLOAT_EQ(cp.p.z, 0.25f);
      // The normal stays a unit vector and, having no in-plane part, stays +Z.
      EXPECT_NEAR(glm::length(cp.n), 1.0f, 1e-5f);
      EXPECT_NEAR(cp.n.z, 1.0f, 1e-5f);
    }
  // The built shaft's points inside the shaft (not its phantom ends) lie on the target.
  for (std::size_t i = 1; i + 1 < f.curves[0].points.size(); ++i)
    worst_shaft = std::max(worst_shaft, nearest(target, glm::dvec2(f.curves[0].points[i].p)).dist);
  EXPECT_LT(worst_shaft, 0.005) << "built shaft off the measured one";
  // Offsets up to 3 mm, inside the shaft's smallest radius of curvature (L^2 / (4 pi^2 a) = 5 mm).
  EXPECT_LT(worst_offset, 0.01) << "lateral offset not kept";
  EXPECT_LT(worst_along, 0.02) << "arc length along the shaft not kept";
}

TEST(ShaftPose, InPlaneNormalsTurnWithTheShaft) {
  Feather f = straight_feather({1.0});
  for (ControlPoint& cp : f.curves[1].points) cp.n = glm::vec3(1, 0, 0);  // lateral, toward the right vane
  // A straight measured shaft turned 30 degrees anticlockwise.
  const double a = 30 * kPi / 180;
  std::vector<glm::dvec2> p;
  for (int i = -1; i <= 9; ++i) p.push_back(kLength * i / 8.0 * glm::dvec2(-std::sin(a), std::cos(a)));
  lay_along_shaft(f, BSpline2(p));
  for (const ControlPoint& cp : f.curves[1].points) {
    EXPECT_NEAR(cp.n.x, std::cos(a), 1e-5);
    EXPECT_NEAR(cp.n.y, std::sin(a), 1e-5);
  }
  // A point beyond the tip continues along the tip's tangent.
  Feather g = straight_feather({});
  Curve far;
  far.points.assign(4, {glm::vec3(0, float(kLength + 2), 0), 0.01f});
  g.curves.push_back(far);
  lay_along_shaft(g, BSpline2(p));
  const glm::dvec2 q(g.curves[1].points[0].p);
  EXPECT_NEAR(q.x, -(kLength + 2) * std::sin(a), 1e-3);
  EXPECT_NEAR(q.y, (kLength + 2) * std::cos(a), 1e-3);
}

TEST(ShaftPose, AFeatherWithoutAShaftOrAShaftWithoutLengthIsRefused) {
  Feather no_shaft = straight_feather({1.0});
  no_shaft.curves.erase(no_shaft.curves.begin());
  EXPECT_THROW(lay_along_shaft(no_shaft, s_shaft(1.0)), Error);
  Feather f = straight_feather({1.0});
  EXPECT_THROW(lay_along_shaft(f, BSpline2(std::vector<glm::dvec2>(5, glm::dvec2(1, 1)))), Error);
  EXPECT_THROW(lay_along_shaft(f, BSpline2(std::vector<glm::dvec2>(3, glm::dvec2(0, 1)))), Error);
  const Feather before = straight_feather({1.0});
  Feather nan_target = before;
  EXPECT_THROW(lay_along_shaft(nan_target, BSpline2(std::vector<glm::dvec2>(5, glm::dvec2(NAN, 0)))), Error);
}
