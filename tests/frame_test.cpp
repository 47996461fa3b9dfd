// Orthonormal frames (frame.h): orthonormal, right-handed (b = n x t), never NaN,
// for random directions and for the inputs that break naive constructions.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "plumage/common/finite.h"
#include "plumage/common/frame.h"

using namespace plumage;

namespace {

constexpr float kTol = 1e-5f;
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kDenorm = std::numeric_limits<float>::denorm_min();


// Checked in double so the test's own rounding does not hide or fake an error.
::testing::AssertionResult is_orthonormal_right_handed(const Frame& f) {
  if (!all_finite(f.t) || !all_finite(f.b) || !all_finite(f.n))
    return ::testing::AssertionFailure() << "non-finite frame";
  const glm::dvec3 t(f.t), b(f.b), n(f.n);
  const double errors[] = {std::fabs(glm::length(t) - 1),    std::fabs(glm::length(b) - 1),
                           std::fabs(glm::length(n) - 1),    std::fabs(glm::dot(t, b)),
                           std::fabs(glm::dot(t, n)),        std::fabs(glm::dot(b, n)),
                           glm::length(glm::cross(n, t) - b)};
  for (double e : errors)
    if (!(e <= kTol))
      return ::testing::AssertionFailure()
             << "error " << e << " in frame t=(" << t.x << "," << t.y << "," << t.z << ") b=("
             << b.x << "," << b.y << "," << b.z << ") n=(" << n.x << "," << n.y << "," << n.z
             << ")";
  return ::testing::AssertionSuccess();
}

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    const glm::vec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

// Exact axes, axes nudged by 1e-8 (below float resolution near 1, above it near 0),
// -z exactly (the pole of Frisvad's original construction), signed zeros, denormals.
std::vector<glm::vec3> adversarial_units() {
  std::vector<glm::vec3> v;
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f}) {
      glm::vec3 a(0);
      a[axis] = sign;
      v.push_back(a);
      for (int other = 0; other < 3; ++other) {
        if (other == axis) continue;
        for (float eps : {1e-8f, -1e-8f, 1e-4f, kDenorm, -kDenorm, -0.0f}) {
          glm::vec3 b = a;
          b[other] = eps;
          v.push_back(glm::normalize(glm::dvec3(b)));
          v.push_back(b);  // not renormalised: the denormal survives
        }
      }
    }
  v.push_back({0, 0, -1});
  v.push_back({-0.0f, -0.0f, -1});
  v.push_back({-0.0f, 0.0f, 1});
  v.push_back({kDenorm, kDenorm, -1});
  v.push_back({-kDenorm, kDenorm, -1});
  const float s = 1 / std::sqrt(3.0f);
  v.push_back({s, s, s});
  v.push_back({-s, -s, -s});
  v.push_back({0, std::sqrt(0.5f), -std::sqrt(0.5f)});
  return v;
}

}  // namespace

TEST(Frame, FromNormalOverAMillionRandomDirections) {
  std::mt19937 rng(1);
  int failures = 0;
  for (int i = 0; i < 1000000; ++i) {
    const glm::vec3 n = random_unit(rng);
    const Frame f = frame_from_normal(n);
    const bool ok = is_orthonormal_right_handed(f) && glm::length(f.n - n) <= kTol;
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << is_orthonormal_right_handed(f).message() << " for n=" << n.x << "," << n.y
                    << "," << n.z;
  }
  EXPECT_EQ(failures, 0);
}

TEST(Frame, FromNormalAdversarial) {
  for (const glm::vec3& n : adversarial_units()) {
    const Frame f = frame_from_normal(n);
    EXPECT_TRUE(is_orthonormal_right_handed(f)) << "n=" << n.x << "," << n.y << "," << n.z;
    EXPECT_LE(glm::length(glm::dvec3(f.n) - glm::normalize(glm::dvec3(n))), kTol);
  }
}

TEST(Frame, FromNormalIsContinuousAwayFromThePole) {
  // Duff et al.'s basis only jumps where n.z changes sign; two close normals on the
  // same side must get close tangents (no flip near an axis).
  std::mt19937 rng(2);
  std::normal_distribution<float> g(0, 1e-4f);
  for (int i = 0; i < 100000; ++i) {
    const glm::vec3 n = random_unit(rng);
    const glm::vec3 m = glm::normalize(n + glm::vec3(g(rng), g(rng), g(rng)));
    if (n.z * m.z <= 0 || std::fabs(n.z) < 1e-2f) continue;
    EXPECT_LT(glm::length(frame_from_normal(n).t - frame_from_normal(m).t), 1e-2f);
  }
}

TEST(Frame, FromNormalDegenerateInputIsStillAFrame) {
  for (const glm::vec3& n : {glm::vec3(0), glm::vec3(kNaN, 0, 1), glm::vec3(INFINITY, 0, 0),
                             glm::vec3(kDenorm, kDenorm, kDenorm), glm::vec3(1e30f, 1e30f, 1e30f),
                             glm::vec3(3, 0, 0), glm::vec3(0, 0, -1e-20f)}) {
    EXPECT_TRUE(is_orthonormal_right_handed(frame_from_normal(n)))
        << n.x << "," << n.y << "," << n.z;
  }
  // A valid but unnormalised normal keeps its direction.
  EXPECT_LE(glm::length(frame_from_normal({0, 3, 4}).n - glm::vec3(0, 0.6f, 0.8f)), kTol);
  EXPECT_LE(glm::length(frame_from_normal({1e30f, 1e30f, 0}).n -
                        glm::vec3(std::sqrt(0.5f), std::sqrt(0.5f), 0)),
            kTol);
}

TEST(Frame, FromTangentNormalOverAMillionRandomPairs) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> scale(0.01f, 100.0f);
  int failures = 0;
  for (int i = 0; i < 1000000; ++i) {
    const glm::vec3 t = random_unit(rng) * scale(rng);
    const glm::vec3 hint = random_unit(rng) * scale(rng);
    const Frame f = frame_from_tangent_normal(t, hint);
    // t is kept exactly (up to normalisation) and n leans toward the hint.
    bool ok = is_orthonormal_right_handed(f) && glm::length(f.t - glm::normalize(t)) <= kTol;
    const glm::dvec3 td = glm::normalize(glm::dvec3(t));
    const glm::dvec3 projected = glm::dvec3(hint) - glm::dot(glm::dvec3(hint), td) * td;
    if (glm::length(projected) > 1e-2 * glm::length(glm::dvec3(hint)))
      ok = ok && glm::length(glm::dvec3(f.n) - glm::normalize(projected)) <= 1e-4;
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << is_orthonormal_right_handed(f).message() << " at i=" << i;
  }
  EXPECT_EQ(failures, 0);
}

TEST(Frame, FromTangentNormalAdversarial) {
  const auto units = adversarial_units();
  for (const glm::vec3& t : units)
    for (const glm::vec3& hint : units) {
      const Frame f = frame_from_tangent_normal(t, hint);
      ASSERT_TRUE(is_orthonormal_right_handed(f))
          << "t=" << t.x << "," << t.y << "," << t.z << " hint=" << hint.x << "," << hint.y << ","
          << hint.z;
      EXPECT_LE(glm::length(glm::dvec3(f.t) - glm::normalize(glm::dvec3(t))), kTol);
    }
}

TEST(Frame, FromTangentNormalDegenerateHints) {
  std::mt19937 rng(4);
  for (int i = 0; i < 10000; ++i) {
    const glm::vec3 t = random_unit(rng);
    // Zero, parallel, anti-parallel, almost parallel, NaN, Inf, denormal, huge.
    const glm::vec3 hints[] = {glm::vec3(0),
                               t,
                               -t,
                               3.0f * t,
                               t + 1e-7f * random_unit(rng),
                               glm::vec3(kNaN),
                               glm::vec3(kNaN, 0, 0),
                               glm::vec3(INFINITY, 1, 0),
                               glm::vec3(kDenorm, 0, kDenorm),
                               1e30f * random_unit(rng)};
    for (const glm::vec3& hint : hints) {
      const Frame f = frame_from_tangent_normal(t, hint);
      ASSERT_TRUE(is_orthonormal_right_handed(f))
          << "i=" << i << " hint=" << hint.x << "," << hint.y << "," << hint.z;
      EXPECT_LE(glm::length(f.t - t), kTol);
    }
  }
  // Degenerate tangents too: the frame is still a frame.
  for (const glm::vec3& t : {glm::vec3(0), glm::vec3(kNaN), glm::vec3(INFINITY, 0, 0)})
    EXPECT_TRUE(is_orthonormal_right_handed(frame_from_tangent_normal(t, {0, 0, 1})));
}

TEST(Frame, FromTangentNormalFollowsTheHintAtGrazingAngles) {
  // A hint 1e-3 rad off the tangent still carries a direction; float Gram-Schmidt
  // loses ~3 digits there, so this is where a single-precision projection fails.
  const glm::vec3 t = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  const Frame g = frame_from_normal(t);
  for (float angle : {1e-1f, 1e-2f, 1e-3f}) {
    const glm::vec3 hint = std::cos(angle) * t + std::sin(angle) * g.t;
    const Frame f = frame_from_tangent_normal(t, hint);
    EXPECT_TRUE(is_orthonormal_right_handed(f)) << angle;
    EXPECT_LE(glm::length(f.n - g.t), 1e-3f) << angle;
  }
}

TEST(Frame, LocalWorldRoundTrip) {
  std::mt19937 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const Frame f = frame_from_tangent_normal(random_unit(rng), random_unit(rng));
    const glm::vec3 v = random_unit(rng) * 7.0f;
    EXPECT_LE(glm::length(f.to_world(f.to_local(v)) - v), 1e-5f);
    EXPECT_NEAR(f.to_local(f.n).z, 1.0f, 1e-6f);
  }
}

TEST(SafeNormalize, FallbackAndNormalCases) {
  const glm::vec3 fb(0, 1, 0);
  for (const glm::vec3& v :
       {glm::vec3(0), glm::vec3(kNaN, 1, 1), glm::vec3(1, INFINITY, 0), glm::vec3(-INFINITY),
        glm::vec3(kDenorm, 0, 0), glm::vec3(1e-20f, 0, 0)})
    EXPECT_EQ(safe_normalize(v, fb), fb) << v.x << "," << v.y << "," << v.z;
  EXPECT_EQ(safe_normalize(glm::vec3(0)), glm::vec3(0, 0, 1));
  // Large and small but representable vectors normalise without overflow or underflow.
  EXPECT_LE(glm::length(safe_normalize({3e30f, 4e30f, 0}) - glm::vec3(0.6f, 0.8f, 0)), 1e-6f);
  EXPECT_LE(glm::length(safe_normalize({0, 3e-12f, -4e-12f}) - glm::vec3(0, 0.6f, -0.8f)), 1e-6f);
  std::mt19937 rng(6);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 u = random_unit(rng);
    EXPECT_NEAR(glm::length(safe_normalize(u * 1e3f)), 1.0f, 1e-6f);
    EXPECT_LE(glm::length(safe_normalize(u * 1e3f) - u), 1e-6f);
  }
}
