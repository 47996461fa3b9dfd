// The shading interface (bsdf.h, barb_shading.h): every Bsdf — the card, a fibre
// with and without a medulla, and the Bsdf each shading mode's model gives a barb
// hit — keeps the contract the path integrator relies on: sample()'s pdf and weight
// agree with f_cos, its pdf integrates to one, it creates no energy, its light
// weights follow f_cos, and the same numbers give the same sample. Each mode's
// model gives its own kind of Bsdf, and a BsdfSlot destroys what it held.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "plumage/common/constants.h"
#include "plumage/common/image.h"
#include "plumage/renderer/barb_shading.h"
#include "plumage/renderer/diffuse_bsdf.h"
#include "plumage/renderer/farfield_bsdf.h"
#include "plumage/renderer/fibre_bsdf.h"
#include "plumage/renderer/scene.h"
#include "fibre_sampling.h"
#include "one_barb.h"

namespace plumage {
namespace {

using test::Rng;

glm::vec4 u4(Rng& rng) { return {rng.uniformf(), rng.uniformf(), rng.uniformf(), rng.uniformf()}; }

glm::vec3 unit(Rng& rng) { return test::uniform_direction(rng); }

// An oblique fibre frame: tangent and wo in general position.
FibreFrame some_fibre_frame(const glm::vec3& wo, float h) {
  return flat_fibre_frame(glm::normalize(glm::vec3(0.6f, 0.3f, -0.2f)), wo, h);
}

HairParams white_fibre() {
  HairParams hp;
  hp.sigma_a = glm::vec3(0.0f);
  return hp;
}

HairParams coloured_medulla_fibre() {
  HairParams hp;
  hp.sigma_a = glm::vec3(0.1f, 0.4f, 1.2f);
  hp.medulla_ratio = 0.7f;
  hp.medulla_sigma_s = glm::vec3(2.0f);
  hp.medulla_sigma_a = glm::vec3(0.05f);
  return hp;
}

// The contract, checked on one Bsdf. `absorbs` false: a white surface, which must
// send back (nearly) all it receives; `exact_weights`: estimate_weights is f_cos
// itself (else an approximation within 2 % where it matters).
void expect_contract(const Bsdf& b, const std::string& what, bool absorbs, bool exact_weights) {
  SCOPED_TRACE(what);
  Rng rng(7);
  // sample() against f_cos: the same pdf, weight = f cos / pdf, a unit direction.
  const int n = 20000;
  glm::dvec3 mean_weight(0.0);
  int sampled = 0;
  for (int k = 0; k < n; ++k) {
    const glm::vec4 u = u4(rng);
    const auto s = b.sample(u);
    if (!s) continue;
    ++sampled;
    ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-4f);
    ASSERT_GT(s->pdf, 0.0f);
    float pdf = 0;
    const glm::vec3 f = b.f_cos(s->wi, &pdf);
    ASSERT_NEAR(pdf, s->pdf, 2e-3f * s->pdf + 1e-6f) << "sample " << k;
    EXPECT_NEAR(b.pdf(s->wi), pdf, 1e-6f * pdf);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(s->weight[c], f[c] / pdf, 2e-3f * f[c] / pdf + 1e-6f) << "channel " << c;
    mean_weight += glm::dvec3(s->weight);
    // The same numbers, the same sample.
    const auto again = b.sample(u);
    ASSERT_TRUE(again);
    ASSERT_EQ(again->wi, s->wi);
  }
  ASSERT_GT(sampled, n / 2);
  mean_weight /= double(n);
  // No energy created; a white surface returns (nearly) all of it.
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(mean_weight[c], 1.02) << "channel " << c;
    if (!absorbs) {
      EXPECT_GE(mean_weight[c], 0.95) << "channel " << c;
    }
  }
  // The pdf integrates to one over the sphere.
  const glm::dvec3 total = test::stratified_sphere_integral(300, rng, [&](const glm::vec3& wi) {
    return glm::vec3(b.pdf(wi));
  });
  EXPECT_NEAR(total.x, 1.0, 0.03);

  // Light weights: lum(strength f cos), exactly or as the documented estimate.
  LightProxies lp;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 d = unit(rng);
    lp.x.push_back(d.x), lp.y.push_back(d.y), lp.z.push_back(d.z);
    lp.r.push_back(rng.uniformf()), lp.g.push_back(rng.uniformf()), lp.b.push_back(rng.uniformf());
  }
  lp.environment = lp.size();
  std::vector<float> w(lp.size()), want(lp.size());
  b.estimate_weights(lp, w.data());
  float pdf;
  for (std::size_t i = 0; i < lp.size(); ++i) want[i] = luminance(lp.strength(i) * b.f_cos(lp.wi(i), &pdf));
  const float top = *std::max_element(want.begin(), want.end());
  ASSERT_GT(top, 0.0f);
  for (std::size_t i = 0; i < lp.size(); ++i) {
    ASSERT_TRUE(std::isfinite(w[i]) && w[i] >= 0) << "light " << i;
    if (exact_weights) {
      EXPECT_NEAR(w[i], want[i], 1e-5f * top) << "light " << i;
    } else if (want[i] > 1e-3f * top) {
      EXPECT_NEAR(w[i], want[i], 0.02f * want[i] + 1e-4f * top) << "light " << i;
    }
  }
}

}  // namespace

TEST(Bsdf, CardKeepsTheContract) {
  Rng rng(3);
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 n = unit(rng), wo = unit(rng);
    const DiffuseBsdf card(n, wo, glm::vec3(0.8f, 0.5f, 0.2f));
    expect_contract(card, "card " + std::to_string(k), true, true);
    // Cosine sampling of a Lambertian surface weighs every sample by the albedo.
    const auto s = card.sample({0.3f, 0.6f, 0.1f, 0.9f});
    ASSERT_TRUE(s);
    EXPECT_EQ(s->weight, glm::vec3(0.8f, 0.5f, 0.2f));
    // Seen from either side: wi on wo's side only.
    EXPECT_GT(glm::dot(s->wi, n) * glm::dot(wo, n), 0.0f);
  }
  expect_contract(DiffuseBsdf({0, 0, 1}, {0.2f, 0.1f, 0.97f}, glm::vec3(1.0f)), "white card", false, true);
}

TEST(Bsdf, FibresKeepTheContract) {
  Rng rng(5);
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 wo = unit(rng);
    const float h = float(rng.range(-0.95, 0.95));
    expect_contract(FibreBsdf(some_fibre_frame(wo, h), white_fibre(), wo, true), "white fibre " + std::to_string(k),
                    false, false);
    expect_contract(FibreBsdf(some_fibre_frame(wo, h), coloured_medulla_fibre(), wo, true),
                    "medulla fibre " + std::to_string(k), true, false);
  }
}

// Without MIS a fibre samples the same directions, weighed by lobe selection and
// with no pdf: the two estimators agree in the mean.
TEST(Bsdf, FibreWithoutPdfSamplesTheSameDirectionsUnbiased) {
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.5f, 0.8f));
  for (const HairParams& hp : {white_fibre(), coloured_medulla_fibre()}) {
    const FibreBsdf with(some_fibre_frame(wo, 0.3f), hp, wo, true), without(some_fibre_frame(wo, 0.3f), hp, wo, false);
    Rng rng(9);
    const int n = 200000;
    glm::dvec3 a(0.0), b(0.0), b2(0.0);
    for (int k = 0; k < n; ++k) {
      const glm::vec4 u = u4(rng);
      const auto s = with.sample(u), t = without.sample(u);
      if (t) {
        EXPECT_EQ(t->pdf, 0.0f);
        b += glm::dvec3(t->weight);
        b2 += glm::dvec3(t->weight) * glm::dvec3(t->weight);
      }
      if (s) a += glm::dvec3(s->weight);
      if (s && t) {
        ASSERT_NEAR(glm::dot(s->wi, t->wi), 1.0f, 1e-5f) << "sample " << k;
      }
    }
    a /= double(n);
    b /= double(n);
    for (int c = 0; c < 3; ++c) {
      const double sigma = std::sqrt(std::max(b2[c] / n - b[c] * b[c], 0.0) / n);
      EXPECT_NEAR(a[c], b[c], 5 * sigma + 1e-3) << "channel " << c;
    }
  }
}

// Each mode's model shades a barb hit with its own Bsdf, and that Bsdf keeps the
// contract. Rays go straight down onto one barb (one_barb.h) until one hits it.
TEST(BarbShading, EachModeItsOwnModelKeepingTheContract) {
  const Feather f = test::one_barb(test::substructure_params(100, 45, 0.04, 0.006, 0.4, 10, 0.3));
  const FibreMaterial material(white_fibre());
  for (ShadingMode mode : kShadingModes) {
    SCOPED_TRACE(to_string(mode));
    SceneOptions so;
    so.mode = mode;
    const Scene scene(f, so);
    const auto shading = make_barb_shading({scene, material, true});
    ASSERT_TRUE(shading);
    EXPECT_EQ(shading->mode(), mode);
    Rng rng(1);
    SurfaceHit hit;
    bool found = false;
    for (int k = 0; k < 2000 && !found; ++k)
      found = scene.intersect(test::down_at(rng.range(-1.5, 1.5), rng.range(-0.19, 0.19)), hit) &&
              hit.kind == HitKind::Barb;
    ASSERT_TRUE(found);
    const glm::vec3 wo(0, 0, 1);
    BsdfSlot slot;
    const Bsdf& b = shading->at(hit, wo, slot);
    const bool table = mode == ShadingMode::Farfield;
    EXPECT_EQ(dynamic_cast<const FarfieldBsdf*>(&b) != nullptr, table);
    EXPECT_EQ(dynamic_cast<const FibreBsdf*>(&b) != nullptr, !table);
    EXPECT_EQ(b.samples_like_f_cos(), !table) << "a table's sampling is uniform within a bin";
    // The far-field table of white fibres still lets light through the vane, so it
    // returns less than it receives; a white fibre returns all.
    expect_contract(b, to_string(mode), table, table);
  }
}

namespace {

struct Counted final : Bsdf {
  int* destroyed;
  explicit Counted(int* d) : destroyed(d) {}
  ~Counted() override { ++*destroyed; }
  glm::vec3 f_cos(const glm::vec3&, float* pdf) const override {
    *pdf = 0;
    return glm::vec3(0);
  }
  std::optional<BsdfSample> sample(const glm::vec4&) const override { return std::nullopt; }
};

}  // namespace

TEST(BsdfSlot, DestroysWhatItHeldOnceOnReuseAndAtTheEnd) {
  int destroyed = 0;
  {
    BsdfSlot slot;
    slot.emplace<Counted>(&destroyed);
    EXPECT_EQ(destroyed, 0);
    slot.emplace<Counted>(&destroyed);
    EXPECT_EQ(destroyed, 1) << "reuse destroys the first";
    slot.reset();
    EXPECT_EQ(destroyed, 2);
    slot.reset();
    EXPECT_EQ(destroyed, 2) << "an empty slot destroys nothing";
    slot.emplace<Counted>(&destroyed);
  }
  EXPECT_EQ(destroyed, 3) << "the slot's end destroys what it holds";
}

}  // namespace plumage
