// The fibre's scattering medulla (issue 33; docs/hair-bcsdf.md, "The medulla"):
// energy (white and weak furnaces, never created), exact sampling weights, chi-square
// of the sampler, reciprocity of the scattered lobe, its closed form at eta = 1, the
// diffuse cylinder's azimuth, and the medulla off being Chiang's fibre to the bit.
// Every random stream has a fixed seed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "chi_square.h"
#include "fibre_sampling.h"
#include "medulla_terms.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/renderer/hair_bcsdf.h"

using namespace plumage;

namespace {

using test::direction;
using test::Rng;
using test::uniform_direction;

template <class G>
glm::dvec3 sphere_integral(int n, Rng& rng, G&& g) {
  return test::stratified_sphere_integral(n, rng, std::forward<G>(g));
}

HairParams with_medulla(float k, glm::vec3 sigma_s, glm::vec3 sigma_a_core = glm::vec3(0.0f),
                        glm::vec3 sigma_a = glm::vec3(0.0f), float beta = 0.3f) {
  HairParams p;
  p.beta_m = p.beta_n = beta;
  p.sigma_a = sigma_a;
  p.medulla_ratio = k;
  p.medulla_sigma_s = sigma_s;
  p.medulla_sigma_a = sigma_a_core;
  return p;
}

std::string describe(const HairParams& p, float h, const glm::vec3& wo) {
  std::ostringstream s;
  s << "k=" << p.medulla_ratio << " sigma_s=" << p.medulla_sigma_s.y << " core sigma_a=" << p.medulla_sigma_a.y
    << " sigma_a=" << p.sigma_a.y << " eta=" << p.eta << " beta=" << p.beta_m << " h=" << h << " wo=(" << wo.x << ","
    << wo.y << "," << wo.z << ")";
  return s.str();
}

// The medulla lobe alone: f with a clear cortex minus f with a cortex so dark that no
// light reaches the core (R, whose A_0 = F the cortex does not touch, is all that is left).
glm::vec3 medulla_lobe_f(HairParams p, float h, const glm::vec3& wo, const glm::vec3& wi) {
  p.sigma_a = glm::vec3(0.0f);
  const glm::vec3 clear = HairBCSDF(p, h).f(wo, wi);
  p.sigma_a = glm::vec3(1e6f);
  return clear - HairBCSDF(p, h).f(wo, wi);
}

}  // namespace

TEST(Medulla, OffIsChiangsFibreToTheBit) {
  // A core of ratio 0, or one that neither scatters nor absorbs, changes nothing:
  // f, pdf and samples equal the clear fibre's exactly.
  Rng rng(33);
  for (int k = 0; k < 20000; ++k) {
    HairParams clear;
    clear.beta_m = float(rng.range(0.05, 1));
    clear.beta_n = float(rng.range(0.05, 1));
    clear.sigma_a = glm::vec3(float(rng.range(0, 3)), float(rng.range(0, 3)), float(rng.range(0, 3)));
    HairParams zero_ratio = clear, clear_core = clear;
    zero_ratio.medulla_sigma_s = glm::vec3(5.0f);
    clear_core.medulla_ratio = 0.7f;
    ASSERT_FALSE(has_medulla(zero_ratio));
    ASSERT_FALSE(has_medulla(clear_core));
    const float h = float(rng.range(-1, 1));
    const glm::vec3 wo = uniform_direction(rng), wi = uniform_direction(rng);
    const glm::vec2 u0(rng.uniformf(), rng.uniformf()), u1(rng.uniformf(), rng.uniformf());
    const HairBCSDF a(clear, h), b(zero_ratio, h), c(clear_core, h);
    for (const HairBCSDF* other : {&b, &c}) {
      ASSERT_EQ(a.f(wo, wi), other->f(wo, wi));
      ASSERT_EQ(a.pdf(wo, wi), other->pdf(wo, wi));
      const auto sa = a.sample(wo, u0, u1), so = other->sample(wo, u0, u1);
      ASSERT_EQ(sa.has_value(), so.has_value());
      if (sa) {
        ASSERT_EQ(sa->wi, so->wi);
        ASSERT_EQ(sa->f, so->f);
      }
    }
  }
}

TEST(Medulla, WhiteFurnace) {
  // Nothing absorbs: what the core does not pass on it scatters, and the five lobes
  // return all the light, by uniform and by importance sampling, for thin and thick,
  // small and large cores.
  Rng rng(34);
  for (float k : {0.3f, 0.7f, 0.95f})
    for (float sigma_s : {0.5f, 5.0f, 200.0f}) {
      const HairParams p = with_medulla(k, glm::vec3(sigma_s), glm::vec3(0.0f), glm::vec3(0.0f), float(rng.range(0.2, 0.8)));
      const float h = float(rng.range(-1, 1));
      const glm::vec3 wo = uniform_direction(rng);
      const HairBCSDF bcsdf(p, h);
      const glm::dvec3 e = sphere_integral(400, rng, [&](const glm::vec3& wi) { return bcsdf.f(wo, wi) * bcsdf_cos(wi); });
      EXPECT_NEAR(e.y, 1.0, 0.01) << describe(p, h, wo);
      double sum = 0.0;
      const int n = 40000;
      for (int i = 0; i < n; ++i) {
        const auto s = bcsdf.sample(wo, {rng.uniformf(), rng.uniformf()}, {rng.uniformf(), rng.uniformf()});
        ASSERT_TRUE(s.has_value()) << describe(p, h, wo);
        const glm::vec3 w = s->f * bcsdf_cos(s->wi) / s->pdf;
        ASSERT_NEAR(w.y, 1.0f, 0.01f) << describe(p, h, wo);  // the pdf is f cos exactly
        sum += w.y;
      }
      EXPECT_NEAR(sum / n, 1.0, 0.01) << describe(p, h, wo);
    }
}

TEST(Medulla, WeakFurnaceNeverCreatesEnergy) {
  // With absorption in the cortex or the core, the light returned is at most what
  // came in, and strictly less; and a darker core or cortex returns less.
  Rng rng(35);
  for (int i = 0; i < 40; ++i) {
    const HairParams p = with_medulla(float(rng.range(0.05, 0.99)), glm::vec3(float(rng.range(0, 100))),
                                      glm::vec3(float(rng.range(0, 5))), glm::vec3(float(rng.range(0, 2))),
                                      float(rng.range(0.1, 1)));
    const float h = float(rng.range(-1, 1));
    const glm::vec3 wo = uniform_direction(rng);
    const HairBCSDF bcsdf(p, h);
    const glm::dvec3 e = sphere_integral(200, rng, [&](const glm::vec3& wi) { return bcsdf.f(wo, wi) * bcsdf_cos(wi); });
    EXPECT_LE(e.y, 1.0 + 0.01) << describe(p, h, wo);
    HairParams darker = p;
    darker.medulla_sigma_a += 2.0f;
    darker.sigma_a += 0.5f;
    const HairBCSDF dark(darker, h);
    const glm::dvec3 d = sphere_integral(200, rng, [&](const glm::vec3& wi) { return dark.f(wo, wi) * bcsdf_cos(wi); });
    EXPECT_LT(d.y, e.y) << describe(p, h, wo);
  }
}

TEST(Medulla, SamplingMatchesPdfChiSquare) {
  // 200k samples against the pdf over 24 x 48 equal-area cells, four cores (one
  // coloured, one absorbing in the cortex), family-wise significance 1 %.
  struct Case {
    float k;
    glm::vec3 sigma_s, sigma_a;
  };
  const Case cases[] = {{0.7f, glm::vec3(20.0f), glm::vec3(0.0f)},
                        {0.95f, glm::vec3(500.0f), glm::vec3(0.0f)},
                        {0.4f, glm::vec3(1.0f, 3.0f, 9.0f), glm::vec3(0.0f)},
                        {0.8f, glm::vec3(4.0f), glm::vec3(0.3f, 0.8f, 1.5f)}};
  const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / 4);
  const int nsamples = 200000;
  Rng rng(36);
  for (const Case& c : cases) {
    const HairParams p = with_medulla(c.k, c.sigma_s, glm::vec3(0.0f), c.sigma_a);
    const float h = float(rng.range(-1, 1));
    const glm::vec3 wo = uniform_direction(rng);
    const HairBCSDF bcsdf(p, h);
    bool sampled = false;
    const test::ChiSquare cs = test::sampler_chi_square(bcsdf, wo, rng, nsamples, &sampled);
    ASSERT_TRUE(sampled);
    EXPECT_NEAR(cs.total_expected / nsamples, 1.0, 2e-3) << describe(p, h, wo);
    EXPECT_GT(cs.pvalue, alpha) << "chi2=" << cs.chi2 << " dof=" << cs.dof << " " << describe(p, h, wo);
  }
}

TEST(Medulla, ThroughputEstimatorIsUnbiased) {
  // sample_throughput's A_p / w_p for the medulla lobe (sampled exactly) against a
  // uniform estimate of the integral of f cos g, g smooth, with absorption.
  Rng rng(37);
  const HairParams p = with_medulla(0.75f, glm::vec3(30.0f), glm::vec3(0.5f), glm::vec3(0.1f, 0.4f, 1.2f));
  for (int c = 0; c < 3; ++c) {
    const float h = float(rng.range(-1, 1));
    const glm::vec3 wo = uniform_direction(rng);
    const HairBCSDF bcsdf(p, h);
    const auto g = [](const glm::vec3& w) { return 1.0f + 0.5f * w.y + 0.25f * w.x * w.z + 0.3f * w.z * w.z; };
    const glm::dvec3 uniform = sphere_integral(400, rng, [&](const glm::vec3& wi) { return bcsdf.f(wo, wi) * bcsdf_cos(wi) * g(wi); });
    glm::dvec3 sum(0.0);
    const int n = 200000;
    for (int k = 0; k < n; ++k)
      if (const auto s = bcsdf.sample_throughput(wo, {rng.uniformf(), rng.uniformf()}, {rng.uniformf(), rng.uniformf()}))
        sum += glm::dvec3(s->weight * g(s->wi));
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(sum[ch] / n / uniform[ch], 1.0, 0.03) << ch << " " << describe(p, h, wo);
  }
}

TEST(Medulla, ScatteredLobeIsReciprocal) {
  // Averaged over the offset h (what a fibre narrower than a pixel shows), the light
  // a thick core sends from wi to wo equals what it sends from wo to wi: its exit
  // shape is its coupling (Kirchhoff). Within 1.5 % where the lobe is not
  // negligible; an exit shape proportional to cos(theta) alone (no Fresnel coupling)
  // misses by up to ~20 % at these angles, which the last check shows.
  const HairParams p = with_medulla(0.9f, glm::vec3(400.0f));
  const int nh = 400;
  const auto averaged = [&](const glm::vec3& wo, const glm::vec3& wi) {
    glm::dvec3 sum(0.0);
    for (int i = 0; i < nh; ++i) sum += glm::dvec3(medulla_lobe_f(p, float(-1.0 + 2.0 * (i + 0.5) / nh), wo, wi));
    return sum / double(nh);
  };
  Rng rng(38);
  double worst_cos_only = 0.0;
  for (int k = 0; k < 30; ++k) {
    const glm::vec3 wo = direction(rng.range(-0.95, 0.95), rng.range(-kPi, kPi));
    const glm::vec3 wi = direction(rng.range(-0.95, 0.95), rng.range(-kPi, kPi));
    const double a = averaged(wo, wi).y, b = averaged(wi, wo).y;
    ASSERT_GT(a, 0.0);
    EXPECT_NEAR(a / b, 1.0, 0.015) << "wo.x=" << wo.x << " wi.x=" << wi.x;
    // The same ratio had the lobe's longitude been cos(theta) alone: it is the ratio
    // of the couplings at the two longitudes.
    const medulla::ExitShape shape(p.eta, p.medulla_ratio);
    const double ga = shape.coupling(wo.x), gb = shape.coupling(wi.x);
    worst_cos_only = std::max(worst_cos_only, std::abs(a / b * gb / ga - 1.0));
  }
  EXPECT_GT(worst_cos_only, 0.05);
}

TEST(Medulla, ScatteredEnergyMatchesTheClosedFormAtEtaOne) {
  // Without refraction (eta = 1: no Fresnel, so no R or TRT) a ray at offset h
  // crosses the core of radius k over the chord 2 sqrt(k^2 - h^2) / cos(theta): the
  // core scatters 1 - exp(-sigma_s times that) of the light, and the diffuse cylinder
  // sends (pi/2 + 2) / 4 = 0.893 of it into the half of azimuths facing the light,
  // where TT (straight through) sends nothing.
  for (float k : {0.5f, 0.9f})
    for (float sigma_s : {0.3f, 2.0f}) {
      HairParams p = with_medulla(k, glm::vec3(sigma_s));
      p.eta = 1.0f;
      for (float h : {0.0f, 0.3f, -0.45f}) {
        const glm::vec3 wo = direction(0.3, 0.4);
        const HairBCSDF bcsdf(p, h);
        const double cos_t = std::sqrt(1.0 - 0.09);
        const double chord = 2.0 * std::sqrt(std::max(0.0, double(k) * k - double(h) * h)) / cos_t;
        const double expected = 1.0 - std::exp(-double(sigma_s) * chord);
        double back = 0.0;
        const int n = 500;
        for (int a = 0; a < n; ++a)
          for (int b = 0; b < n; ++b) {
            const glm::vec3 wi = direction(-1.0 + 2.0 * (a + 0.5) / n, -kPi + 2.0 * kPi * (b + 0.5) / n);
            const double rel = std::remainder(std::atan2(double(wi.y), double(wi.z)) - std::atan2(double(wo.y), double(wo.z)), 2 * kPi);
            if (std::abs(rel) < kPi / 2) back += bcsdf.f(wo, wi).y * bcsdf_cos(wi);
          }
        back *= 4.0 * kPi / (double(n) * n);
        EXPECT_NEAR(back, (kPi / 2 + 2) / 4 * expected, 0.002 + 0.01 * expected)
            << "k=" << k << " sigma_s=" << sigma_s << " h=" << h;
      }
    }
}

TEST(Medulla, DiffuseCylinderAzimuthIsNormalisedAndSampledExactly) {
  double sum = 0.0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double phi = -kPi + 2.0 * kPi * (i + 0.5) / n;
    const double v = medulla::lambertian_azimuth(phi);
    ASSERT_GE(v, 0.0);
    EXPECT_NEAR(v, medulla::lambertian_azimuth(std::cos(phi), std::abs(std::sin(phi))), 1e-12);
    sum += v;
  }
  EXPECT_NEAR(sum * 2.0 * kPi / n, 1.0, 1e-6);
  // A histogram of the psi + chi construction against the density.
  Rng rng(40);
  const int bins = 32, m = 400000;
  std::vector<double> hist(bins, 0.0);
  for (int i = 0; i < m; ++i) {
    const double phi = medulla::sample_lambertian_azimuth(rng.uniform(), rng.uniform());
    hist[std::clamp(int((phi + kPi) / (2 * kPi) * bins), 0, bins - 1)] += 1.0;
  }
  for (int b = 0; b < bins; ++b) {
    double mass = 0.0;
    for (int j = 0; j < 100; ++j) mass += medulla::lambertian_azimuth(-kPi + 2 * kPi * (b + (j + 0.5) / 100) / bins);
    mass *= 2 * kPi / bins / 100;
    EXPECT_NEAR(hist[b] / m, mass, 4.0 * std::sqrt(mass / m) + 1e-4) << "bin " << b;
  }
}

TEST(Medulla, ExitShapeIsADensityItsSamplerInverts) {
  for (double eta : {1.0, 1.55, 2.5})
    for (double k : {0.2, 0.7, 0.99}) {
      const medulla::ExitShape s(eta, k);
      double sum = 0.0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) sum += s.pdf(-1.0 + 2.0 * (i + 0.5) / n);
      EXPECT_NEAR(sum * 2.0 / n, 1.0, 1e-3) << eta << " " << k;
      // The sampler is the inverse of the cumulative mass.
      for (double xi : {0.01, 0.2, 0.5, 0.77, 0.99}) {
        const double u = s.sample(xi);
        double mass = 0.0;
        for (int i = 0; i < n; ++i) {
          const double x = -1.0 + (u + 1.0) * (i + 0.5) / n;
          mass += s.pdf(x);
        }
        EXPECT_NEAR(mass * (u + 1.0) / n, xi, 2e-3) << eta << " " << k << " " << xi;
      }
    }
}

TEST(Medulla, FiniteOverExtremeInputs) {
  // Cores from nothing to nearly the fibre, coefficients up to 1e30, grazing hits,
  // directions along the tangent: f, pdf and samples finite, >= 0, pdf > 0 where f > 0.
  Rng rng(41);
  const int n = std::getenv("PLUMAGE_STRESS") ? 1000000 : 100000;
  for (int i = 0; i < n; ++i) {
    HairParams p;
    p.beta_m = float(std::pow(10.0, rng.range(-3, 0)));
    p.beta_n = float(std::pow(10.0, rng.range(-3, 0)));
    p.eta = i % 3 == 0 ? 1.0f : float(rng.range(1.0, 3.0));
    p.medulla_ratio = i % 5 == 0 ? 0.999999f : float(rng.range(0, 1));
    p.medulla_sigma_s = glm::vec3(float(std::pow(10.0, rng.range(-6, 30))));
    p.medulla_sigma_a = glm::vec3(float(i % 2 ? 0.0 : std::pow(10.0, rng.range(-6, 30))));
    p.sigma_a = glm::vec3(float(i % 4 ? 0.0 : std::pow(10.0, rng.range(-6, 30))));
    const float h = i % 7 == 0 ? (i % 2 ? 1.0f : -1.0f) : float(rng.range(-1, 1));
    glm::vec3 wo = uniform_direction(rng), wi = uniform_direction(rng);
    if (i % 11 == 0) wi = glm::vec3(1, 0, 0);
    if (i % 13 == 0) wo = glm::normalize(glm::vec3(1.0f, 1e-7f, 0.0f));
    const HairBCSDF b(p, h);
    float pdf = 0.0f;
    const glm::vec3 f = b.f_pdf(wo, wi, &pdf);
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(f[c]) && f[c] >= 0.0f) << describe(p, h, wo);
    ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f);
    if (f.x > 0 || f.y > 0 || f.z > 0) {
      ASSERT_GT(pdf, 0.0f) << describe(p, h, wo);
    }
    if (const auto s = b.sample(wo, {rng.uniformf(), rng.uniformf()}, {rng.uniformf(), rng.uniformf()})) {
      ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-4f);
      ASSERT_TRUE(std::isfinite(s->pdf) && s->pdf > 0.0f);
      for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(s->f[c]) && s->f[c] >= 0.0f);
    }
  }
}

TEST(Medulla, InvalidParametersThrowNamingThem) {
  HairParams p;
  p.medulla_ratio = 1.0f;
  EXPECT_THROW(validate(p, "barb"), Error);
  p.medulla_ratio = -0.1f;
  EXPECT_THROW(validate(p, "barb"), Error);
  p.medulla_ratio = 0.5f;
  p.medulla_sigma_s = glm::vec3(1.0f, std::nanf(""), 1.0f);
  try {
    validate(p, "barb");
    FAIL() << "a NaN scattering coefficient was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("medulla_sigma_s[1]"), std::string::npos) << e.what();
  }
  p.medulla_sigma_s = glm::vec3(1.0f);
  p.medulla_sigma_a = glm::vec3(-1.0f);
  EXPECT_THROW(validate(p, "barb"), Error);
}

// The light-pick estimate (f_cos_estimate) with the medulla on: its scattered lobe's
// azimuth is taken from an approximate atan2, so the estimate still follows f cos.
TEST(Medulla, FastEstimateFollowsFCos) {
  Rng rng(33);
  double worst = 0;
  long compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const HairParams p = with_medulla(float(rng.range(0.1, 0.9)), glm::vec3(float(rng.range(0.1, 20))),
                                      glm::vec3(float(rng.range(0, 0.5))), glm::vec3(float(rng.range(0, 0.3))),
                                      float(rng.range(0.1, 0.8)));
    const HairBCSDF bcsdf(p, float(rng.range(-1, 1)));
    const glm::vec3 wo = uniform_direction(rng);
    std::vector<glm::vec3> wi(64), exact(64), fast(64);
    for (glm::vec3& w : wi) w = uniform_direction(rng);
    bcsdf.f_cos(wo, wi, exact);
    bcsdf.f_cos_estimate(wo, wi, fast);
    float peak = 0;
    for (const glm::vec3& e : exact) peak = std::max({peak, e.x, e.y, e.z});
    for (std::size_t k = 0; k < wi.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(fast[k][c]) && fast[k][c] >= 0) << describe(p, bcsdf.h(), wo);
        if (exact[k][c] < 1e-3f * peak) continue;
        ++compared;
        worst = std::max(worst, std::fabs(double(fast[k][c]) / exact[k][c] - 1.0));
      }
  }
  EXPECT_GT(compared, 10000);
  EXPECT_LT(worst, 0.01) << "the estimate strays from f cos";
}
