// Samplers: Owen-scrambled Sobol keeps the net structure Burley 2020 relies on,
// both samplers are uniform and deterministic per (pixel, index), and Sobol
// integrates a smooth function with much lower error than independent samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "plumage/renderer/sampler.h"

using namespace plumage;

TEST(RenderSampler, SobolDirectionNumbersGiveKnownPoints) {
  // First points of the Sobol sequence in dimensions 0 and 1 (Joe & Kuo): 0, 1/2, 1/4 & 3/4, ...
  const double k = 0x1p-32;
  EXPECT_EQ(sobol(0, 0), 0u);
  EXPECT_DOUBLE_EQ(sobol(1, 0) * k, 0.5);
  EXPECT_DOUBLE_EQ(sobol(2, 0) * k, 0.25);
  EXPECT_DOUBLE_EQ(sobol(3, 0) * k, 0.75);
  EXPECT_DOUBLE_EQ(sobol(1, 1) * k, 0.5);
  EXPECT_DOUBLE_EQ(sobol(2, 1) * k, 0.75);
  EXPECT_DOUBLE_EQ(sobol(3, 1) * k, 0.25);
}

TEST(RenderSampler, ScrambledSobolPrefixesAreStratifiedNets) {
  // Owen scrambling and Burley's index shuffle keep every power-of-two prefix a
  // (0, m, 2)-net in each pair of the first two dimensions: one point per 16x16 cell.
  for (int px : {0, 3, 17}) {
    PixelSampler s(SamplerKind::Sobol, 1234);
    std::set<int> cells01;
    std::vector<int> strata(256, 0);
    for (std::uint32_t i = 0; i < 256; ++i) {
      s.start(px, 5, i);
      const glm::vec4 u = s.next4();
      cells01.insert(int(u.x * 16) * 16 + int(u.y * 16));
      ++strata[int(u.z * 256)];
      for (int d = 0; d < 4; ++d) ASSERT_TRUE(u[d] >= 0.0f && u[d] < 1.0f);
    }
    EXPECT_EQ(cells01.size(), 256u) << "pixel " << px;
    for (int c : strata) EXPECT_EQ(c, 1);
  }
}

// next4 computes the Sobol pattern with the bit reversals that cancel left out and
// byte tables for the direction numbers; it must give exactly the definition (Burley
// 2020 §4, sampler.h) built from the public pieces, and next2 its first two numbers.
TEST(RenderSampler, SobolPatternsEqualTheirDefinition) {
  const auto to_unit = [](std::uint32_t x) { return float(x >> 8) * 0x1p-24f; };
  std::uint32_t mismatches = 0, compared = 0;
  for (std::uint64_t seed : {0ull, 1ull, 0x123456789abcdefull}) {
    const std::uint32_t s32 = std::uint32_t(seed ^ (seed >> 32));
    PixelSampler s(SamplerKind::Sobol, seed), t(SamplerKind::Sobol, seed);
    for (int px : {0, 5, 4095})
      for (std::uint32_t index : {0u, 1u, 2u, 3u, 255u, 256u, 65535u, 0x80000000u, 0xffffffffu}) {
        s.start(px, 3 * px + 1, index);
        t.start(px, 3 * px + 1, index);
        const std::uint32_t pixel_seed = hash_combine(hash_combine(s32, std::uint32_t(px)), std::uint32_t(3 * px + 1));
        for (std::uint32_t pattern = 0; pattern < 12; ++pattern) {
          const std::uint32_t ps = hash_combine(pixel_seed, pattern);
          const std::uint32_t i = nested_uniform_scramble(index, ps);
          const glm::vec4 u = s.next4();
          const glm::vec2 v = t.next2();
          for (int d = 0; d < 4; ++d) {
            const float want = to_unit(nested_uniform_scramble(sobol(i, d), hash_combine(ps, std::uint32_t(d) + 1)));
            mismatches += u[d] != want;
            if (d < 2) mismatches += v[d] != want;
            ++compared;
          }
        }
      }
  }
  EXPECT_EQ(compared, 3u * 3 * 9 * 12 * 4);
  EXPECT_EQ(mismatches, 0u);
}

TEST(RenderSampler, DeterministicPerPixelAndIndex) {
  for (SamplerKind k : {SamplerKind::Sobol, SamplerKind::Independent}) {
    PixelSampler a(k, 9), b(k, 9), other_seed(k, 10);
    a.start(4, 7, 13);
    const glm::vec4 a1 = a.next4(), a2 = a.next4();
    b.start(100, 100, 2);
    b.next4();
    b.start(4, 7, 13);  // restarting gives the same stream whatever came before
    EXPECT_EQ(b.next4(), a1);
    EXPECT_EQ(b.next4(), a2);
    EXPECT_NE(a1, a2);
    other_seed.start(4, 7, 13);
    EXPECT_NE(other_seed.next4(), a1);
    b.start(5, 7, 13);
    EXPECT_NE(b.next4(), a1);
  }
}

TEST(RenderSampler, UniformMarginals) {
  // Chi-square over 32 bins per dimension for many pixels, both samplers.
  for (SamplerKind k : {SamplerKind::Sobol, SamplerKind::Independent}) {
    PixelSampler s(k, 77);
    std::vector<double> bins(4 * 32 * 3, 0);
    const int n_pix = 2000, spp = 8;
    for (int p = 0; p < n_pix; ++p)
      for (int i = 0; i < spp; ++i) {
        s.start(p % 50, p / 50, std::uint32_t(i));
        for (int g = 0; g < 3; ++g) {
          const glm::vec4 u = s.next4();
          for (int d = 0; d < 4; ++d) bins[(g * 4 + d) * 32 + int(u[d] * 32)] += 1;
        }
      }
    const double expected = double(n_pix) * spp / 32;
    for (int dim = 0; dim < 12; ++dim) {
      double chi2 = 0;
      for (int b = 0; b < 32; ++b) chi2 += std::pow(bins[dim * 32 + b] - expected, 2) / expected;
      // 31 degrees of freedom: p < 1e-4 beyond ~ 70.
      EXPECT_LT(chi2, 70.0) << to_string(k) << " dimension " << dim;
    }
  }
}

TEST(RenderSampler, SobolConvergesFasterOnSmoothIntegrand) {
  // RMSE over pixels of a 2D integral with a known value, 64 samples each.
  auto rmse = [](SamplerKind k) {
    PixelSampler s(k, 5);
    const double exact = (1 - std::cos(1.0)) * (1 - std::cos(1.0));  // int sin(x) sin(y) on [0,1]^2
    double se = 0;
    const int pixels = 400, spp = 64;
    for (int p = 0; p < pixels; ++p) {
      double sum = 0;
      for (int i = 0; i < spp; ++i) {
        s.start(p, 0, std::uint32_t(i));
        s.next4();  // skip the pixel pattern, as the renderer does
        const glm::vec4 u = s.next4();
        sum += std::sin(u.x) * std::sin(u.y);
      }
      se += std::pow(sum / spp - exact, 2);
    }
    return std::sqrt(se / pixels);
  };
  const double e_sobol = rmse(SamplerKind::Sobol), e_indep = rmse(SamplerKind::Independent);
  EXPECT_LT(e_sobol, 0.25 * e_indep) << "sobol " << e_sobol << " independent " << e_indep;
}

TEST(RenderSampler, ParsesKinds) {
  EXPECT_EQ(parse_sampler_kind("sobol"), SamplerKind::Sobol);
  EXPECT_EQ(parse_sampler_kind("independent"), SamplerKind::Independent);
  EXPECT_ANY_THROW(parse_sampler_kind("halton"));
}
