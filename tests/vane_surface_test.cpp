// The vane surface must be OpenSubdiv's Catmull-Clark limit surface of its cage.
// For a regular grid with sharp boundary edges and corners that limit is known in
// closed form: the tensor-product uniform cubic B-spline whose border rows are
// extended by phantom points (2 P0 - P1), so we check Bfr against that.
#include <gtest/gtest.h>

#include <random>

#include "plumage/common/bspline.h"
#include "plumage/common/error.h"
#include "plumage/generator/vane_surface.h"

using namespace plumage;

namespace {

struct TensorBSpline {
  int nc, nr;
  std::vector<glm::dvec3> cage;  // cage[i * nr + j]

  // Column of control points at row j extended with phantom ends -> a curve in u.
  glm::dvec3 eval(double u, double v, int du = 0, int dv = 0) const {
    std::vector<glm::dvec3> rows_at_u;
    for (int j = 0; j < nr; ++j) {
      std::vector<glm::dvec3> col;
      for (int i = 0; i < nc; ++i) col.push_back(cage[i * nr + j]);
      const BSpline3 cu(with_phantom_ends(col));
      rows_at_u.push_back(du ? cu.deriv(u) : cu.eval(u));
    }
    const BSpline3 cv(with_phantom_ends(rows_at_u));
    return dv ? cv.deriv(v) : cv.eval(v);
  }
};

}  // namespace

TEST(VaneSurface, MatchesClosedFormLimitOfRegularGrid) {
  std::mt19937_64 rng(7);
  for (auto [nc, nr] : {std::pair{4, 2}, {6, 4}, {9, 5}}) {
    TensorBSpline ref{nc, nr, {}};
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < nr; ++j) {
        const double jitter = double(rng() % 1000) / 1000.0 - 0.5;
        ref.cage.push_back({3.0 * j + 0.3 * jitter, 5.0 * i, std::sin(i * 0.7 + j) + jitter});
      }
    const VaneSurface s(nc, nr, ref.cage, 1.0);
    for (int a = 0; a <= 20; ++a)
      for (int b = 0; b <= 10; ++b) {
        const double u = a / 20.0, v = b / 10.0;
        const auto smp = s.eval(u, v);
        const glm::dvec3 p = ref.eval(u, v), pu = ref.eval(u, v, 1, 0), pv = ref.eval(u, v, 0, 1);
        EXPECT_NEAR(glm::length(smp.p - p), 0.0, 1e-9) << nc << "x" << nr << " at " << u << "," << v;
        EXPECT_NEAR(glm::length(smp.du - pu), 0.0, 1e-7 * glm::length(pu) + 1e-9);
        EXPECT_NEAR(glm::length(smp.dv - pv), 0.0, 1e-7 * glm::length(pv) + 1e-9);
        EXPECT_NEAR(glm::length(smp.n), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(smp.n, glm::normalize(glm::cross(pu, pv))), 1.0, 1e-9);
      }
  }
}

TEST(VaneSurface, CornersAreInterpolatedAndSignFlipsNormal) {
  std::vector<glm::dvec3> cage;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j) cage.push_back({double(j), double(i), 0.1 * i * j});
  const VaneSurface up(5, 3, cage, 1.0), down(5, 3, cage, -1.0);
  EXPECT_NEAR(glm::length(up.eval(0, 0).p - cage[0]), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(up.eval(1, 1).p - cage.back()), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(up.eval(0.3, 0.6).n + down.eval(0.3, 0.6).n), 0.0, 1e-12);
  // Out-of-domain requests clamp instead of reading past the cage.
  EXPECT_EQ(up.eval(-5, 7).p, up.eval(0, 1).p);
}

TEST(VaneSurface, RejectsBadGrids) {
  EXPECT_THROW(VaneSurface(1, 3, std::vector<glm::dvec3>(3), 1.0), Error);
  EXPECT_THROW(VaneSurface(3, 3, std::vector<glm::dvec3>(8), 1.0), Error);
}
