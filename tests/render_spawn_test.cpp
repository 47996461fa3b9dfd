// Secondary rays leaving a fibre (Scene::spawn, DESIGN §4): a ray leaving a round
// curve crosses up to 2r / cos(theta) of it, so the fibre it left must be skipped
// that far at every angle. Checked three ways: the tube-exit distance against its
// geometry; spawned rays never landing on the fibre they left (shaft, hair-mode
// barb, substructure's shaft, explicit rami and barbules) at any angle; and an
// isolated round fibre under a white sky against the closed form sum_p A_p
// (Chiang et al. 2016 eq. 2 integrates to it), at depth 1 and full depth, from
// head-on to grazing views, and under a grazing directional light.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "one_barb.h"
#include "plumage/common/constants.h"
#include "plumage/renderer/hair_bcsdf.h"
#include "plumage/renderer/ray.h"
#include "plumage/renderer/render.h"
#include "render_test_feather.h"

using namespace plumage;
using test::mean_channel;

namespace {


// Unpolarised Fresnel reflectance (Born & Wolf §1.5), written out here so the
// closed form does not share code with the BCSDF it checks.
double fresnel(double cos_i, double eta) {
  if (cos_i <= 0) return 1;
  const double sin_t2 = (1 - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1) return 1;
  const double cos_t = std::sqrt(1 - sin_t2);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// sum_p A_p(theta_o, h) for one channel (Marschner et al. 2003 §4; Chiang et al.
// 2016 §4.1): what a fibre returns of a uniform white sky toward wo at offset h.
double sum_ap(double theta_o, double h, double sigma_a, double eta) {
  const double sin_o = std::sin(theta_o), cos_o = std::cos(theta_o);
  const double eta_p = std::sqrt(eta * eta - sin_o * sin_o) / cos_o;  // Bravais
  const double gamma_o = std::asin(h), gamma_t = std::asin(h / eta_p);
  const double sin_t = sin_o / eta, cos_t = std::sqrt(1 - sin_t * sin_t);
  const double T = std::exp(-sigma_a * 2 * std::cos(gamma_t) / cos_t);
  const double f = fresnel(cos_o * std::cos(gamma_o), eta);
  const double a1 = (1 - f) * (1 - f) * T, a2 = a1 * f * T, a3 = a2 * f * T / (1 - f * T);
  return f + a1 + a2 + a3;
}

// The mean of sum_ap over h uniform in [-hmax, hmax] (the rows of an orthographic view).
double mean_sum_ap(double theta_o, double hmax, double sigma_a, double eta) {
  const int n = 4000;
  double s = 0;
  for (int i = 0; i < n; ++i) s += sum_ap(theta_o, hmax * (2 * (i + 0.5) / n - 1), sigma_a, eta);
  return s / n;
}

constexpr float kRadius = 1.0f;  // mm, the isolated shaft of the measurement
constexpr float kHmax = 0.98f;   // the view's rows cover h in [-kHmax, kHmax]

Feather isolated_shaft() {
  Feather f;
  f.curves.push_back(test::straight_curve(CurveKind::Shaft, {0, 0, 0}, 40.0f, kRadius));
  return f;
}

// Orthographic view of the shaft (along +X) from wo = (sin theta, 0, cos theta):
// rows run across the fibre (y), so the film covers h in [-kHmax, kHmax] evenly.
Camera shaft_view(double theta_o, const Scene& scene) {
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.look_at = glm::vec3(0);
  cs.position = 50.0f * glm::vec3(std::sin(theta_o), 0, std::cos(theta_o));
  cs.up = {0, 1, 0};
  cs.ortho_height = 2 * kHmax * kRadius;
  return Camera(cs, 4, 32, scene.feather_bounds());
}

double render_mean(const Scene& scene, const LightSet& lights, const HairParams& hp, int depth, double theta_o,
                   int spp = 256) {
  const FibreMaterial material(hp);
  IntegratorSettings is;
  is.max_depth = depth;
  const PathIntegrator integrator(scene, lights, material, is);
  RenderSettings rs;
  rs.spp = spp;
  rs.progress = false;
  rs.seed = 7;
  const Image img = render(shaft_view(theta_o, scene), integrator, rs).developed(0);
  return mean_channel(img, 1);
}

struct ModeCase {
  ShadingMode mode;
  const char* name;
};
const ModeCase kModes[] = {{ShadingMode::Hair, "hair"},
                           {ShadingMode::Substructure, "substructure"},
                           {ShadingMode::Explicit, "explicit"}};

}  // namespace

TEST(TubeExit, MatchesTheGeometryOfACylinder) {
  const glm::vec3 c(0), axis(2, 0, 0);  // any length
  const float R = 0.5f;
  // From the top of the tube straight down through the axis: the diameter.
  EXPECT_NEAR(tube_exit_distance({0, 0, R}, {0, 0, -1}, c, axis, R), 2 * R, 1e-6);
  // Tilted by theta toward the axis: 2R / cos(theta), unbounded toward grazing.
  for (double theta_deg : {30.0, 60.0, 80.0, 89.0}) {
    const double th = theta_deg * kPi / 180;
    const glm::vec3 d(float(std::sin(th)), 0, -float(std::cos(th)));
    EXPECT_NEAR(tube_exit_distance({0, 0, R}, d, c, axis, R), 2 * R / std::cos(th), 2e-4 / std::cos(th))
        << theta_deg;
  }
  // Along the axis from inside: never leaves.
  EXPECT_TRUE(std::isinf(tube_exit_distance({0, 0.1f, 0}, {1, 0, 0}, c, axis, R)));
  // Leaving outward from the surface, or passing outside: already out.
  EXPECT_EQ(tube_exit_distance({0, 0, R}, {0, 0, 1}, c, axis, R), 0.0f);
  EXPECT_EQ(tube_exit_distance({0, 0, 2 * R}, {0, 1, 0}, c, axis, R), 0.0f);
  // A chord off the axis: 2 sqrt(R^2 - y^2).
  EXPECT_NEAR(tube_exit_distance({0, 0.3f, 0.4f}, {0, 0, -1}, c, axis, R), 0.8, 1e-6);
}

// Rays leaving a fibre through its body, from head-on to almost along it, must not
// land on the fibre they left: its BCSDF already carried them across it.
TEST(Spawn, NeverLandsOnTheFibreItLeftAtAnyAngle) {
  struct Case {
    const char* name;
    Feather feather;
    ShadingMode mode;
    float x0;  // hits are sampled over x in [x0 - 0.5, x0 + 0.5], y across the fibre
    float half_width;
  };
  const SubstructureParams sp = test::substructure_params(40, 45, 0.04, 0.01, 0.4, 0, 0);
  Feather barb = test::one_barb(sp);
  Feather shaft = isolated_shaft();
  Feather flat;
  flat.curves.push_back(test::straight_curve(CurveKind::Barb, {0, 0, 0}, 12.0f, 0.3f));
  const Case cases[] = {
      {"hair-mode shaft (round)", shaft, ShadingMode::Hair, 0, kRadius},
      {"hair-mode barb (ray-facing ribbon)", flat, ShadingMode::Hair, 0, 0.3f},
      {"substructure's shaft (round)", shaft, ShadingMode::Substructure, 0, kRadius},
      {"explicit ramus", barb, ShadingMode::Explicit, 0, 0.04f},
      {"explicit barbules", barb, ShadingMode::Explicit, 0, 0.2f},
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u01(0, 1);
  for (const Case& c : cases) {
    const Scene scene(c.feather, SceneOptions{c.mode, {}});
    int spawned = 0, self_hits = 0;
    for (int i = 0; i < 4000; ++i) {
      SurfaceHit h;
      const Ray down = test::down_at(c.x0 + u01(rng) - 0.5f, c.half_width * (2 * u01(rng) - 1));
      if (!scene.intersect(down, h)) continue;
      if (c.half_width > 0.1f && c.mode == ShadingMode::Explicit && scene.explicit_fibre(h).structure == Structure::Ramus)
        continue;  // the barbule case samples barbules only
      // Into the fibre: downward, at a longitudinal angle up to 89.5 degrees.
      const float theta = 89.5f * float(kPi / 180) * u01(rng);
      const float phi = float(kPi) * u01(rng);  // an azimuth in the normal plane's lower half (b = -z)
      const CurvePoint cp = scene.curve_point(h);
      const glm::vec3 t = glm::normalize(cp.dp);
      const glm::vec3 n = glm::normalize(glm::cross(t, glm::vec3(0, 0, 1))), b = glm::cross(t, n);
      const glm::vec3 d = glm::normalize(std::sin(theta) * (u01(rng) < 0.5f ? t : -t) +
                                         std::cos(theta) * (std::cos(phi) * n + std::sin(phi) * b));
      SurfaceHit next;
      ++spawned;
      if (scene.intersect(scene.spawn(h, d), next) && next.geom == h.geom &&
          (c.mode == ShadingMode::Explicit ? scene.explicit_fibre(next).first_cp == scene.explicit_fibre(h).first_cp
                                           : next.curve == h.curve))
        ++self_hits;
    }
    EXPECT_GT(spawned, 500) << c.name;
    EXPECT_EQ(self_hits, 0) << c.name << ": " << self_hits << " of " << spawned << " spawned rays hit their own fibre";
  }
}

// sigma_a = 0 under a white sky: a fibre returns all the light at depth 1 (direct
// lighting only), where nothing else can give energy back.
TEST(Spawn, IsolatedRoundFibreWhiteFurnaceAtDepthOne) {
  HairParams hp;
  hp.sigma_a = glm::vec3(0);
  LightSet sky;
  sky.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  for (const ModeCase& m : kModes) {
    const Scene scene(isolated_shaft(), SceneOptions{m.mode, {}});
    for (double theta_deg : {0.0, 45.0, 75.0, 85.0}) {
      const double got = render_mean(scene, sky, hp, 1, theta_deg * kPi / 180);
      EXPECT_NEAR(got, 1.0, 0.005) << m.name << ", view at " << theta_deg << " degrees to the normal plane";
    }
  }
}

// The measurement: a 1 mm shaft, sigma_a of a brown feather, white sky;
// plumage must match the closed form within 0.5 % at depth 1 and at depth 16.
TEST(Spawn, IsolatedRoundFibreMatchesTheClosedForm) {
  HairParams hp;
  hp.sigma_a = glm::vec3(0.49f, 0.48f, 0.45f);
  LightSet sky;
  sky.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  for (const ModeCase& m : kModes) {
    const Scene scene(isolated_shaft(), SceneOptions{m.mode, {}});
    for (double theta_deg : {0.0, 30.0, 60.0, 80.0}) {
      const double th = theta_deg * kPi / 180;
      const double expected = mean_sum_ap(th, kHmax, hp.sigma_a.y, hp.eta);
      for (int depth : {1, 16}) {
        const double got = render_mean(scene, sky, hp, depth, th);
        EXPECT_NEAR(got, expected, 0.005 * expected)
            << m.name << ", depth " << depth << ", view at " << theta_deg << " degrees";
      }
    }
  }
}

// A directional light behind the fibre and nearly along it: every shadow ray
// crosses the fibre at a grazing angle (TT), where a short skip shadows it by itself.
TEST(Spawn, GrazingLightThroughTheFibreIsNotSelfShadowed) {
  HairParams hp;
  hp.sigma_a = glm::vec3(0.2f);
  const glm::vec3 to_light = glm::normalize(glm::vec3(-0.97f, 0.05f, -0.24f));  // 76 degrees from the normal plane
  LightSet lights;
  lights.add(DirectionalLight{to_light, glm::vec3(1.0f)});
  const double theta_o = 75.0 * kPi / 180;  // grazing view, the light mirrored behind
  // The shaft runs along +X and the view's z is wo in the normal plane, +Z: the
  // fibre frame is the world frame, and h runs along +y (hair_bcsdf.h).
  const glm::vec3 wo(float(std::sin(theta_o)), 0, float(std::cos(theta_o)));
  double expected = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const float h = kHmax * (2 * (float(i) + 0.5f) / float(n) - 1);
    const HairBCSDF bcsdf(hp, h);
    expected += double(bcsdf.f(wo, to_light).y * bcsdf_cos(to_light)) / n;
  }
  ASSERT_GT(expected, 0.01) << "the light must reach the view through the fibre";
  for (const ModeCase& m : kModes) {
    const Scene scene(isolated_shaft(), SceneOptions{m.mode, {}});
    const double got = render_mean(scene, lights, hp, 1, theta_o, 64);
    EXPECT_NEAR(got, expected, 0.005 * expected) << m.name;
  }
}
