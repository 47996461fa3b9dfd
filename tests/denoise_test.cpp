// Non-local-means denoising by the render's own variance (renderer/denoise.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "plumage/common/error.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/denoise.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/error_ladder.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/render.h"
#include "render_test_feather.h"
#include "plumage/renderer/scene.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

// A clean picture: a dark half with a gentle ramp, a step to a light half, and a
// one-pixel light line in the dark half; RGB of different levels.
Image clean_picture(int W, int H) {
  Image img(W, H, 3);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      float v = x < W / 2 ? 0.2f + 0.1f * float(y) / float(H) : 0.8f;
      if (x == W / 4) v += 0.4f;
      img.set_rgb(x, y, {v, 0.8f * v, 0.6f * v});
    }
  return img;
}

}  // namespace

TEST(Denoise, NoiseGoesAndTheEdgesStay) {
  // Gaussian noise of a known standard deviation (0.05, the variance of each
  // pixel's mean told to the filter; RMS 0.050 -> 0.007): the filtered picture is
  // at least 2.5 times closer to the clean one than the noisy one (RMS), the step keeps its height
  // (the columns beside it within 0.03 of their clean values, where a box blur of the
  // window would move them by 0.3) and the one-pixel line keeps most of its height.
  constexpr int W = 96, H = 64;
  constexpr float kSigma = 0.05f;
  const Image clean = clean_picture(W, H);
  Image noisy = clean, variance(W, H, 3, kSigma * kSigma);
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, kSigma);
  for (float& v : noisy.pixels) v += noise(rng);
  const Image out = denoise(noisy, variance);
  const double before = rmse(noisy, clean), after = rmse(out, clean);
  EXPECT_LT(after, before / 2.5) << before << " -> " << after;
  for (int x : {W / 2 - 1, W / 2}) {
    double m = 0, c = 0;
    for (int y = 0; y < H; ++y) {
      m += out.at(x, y)[0];
      c += clean.at(x, y)[0];
    }
    EXPECT_NEAR(m / H, c / H, 0.03) << "column " << x;
  }
  double line = 0, beside = 0;
  for (int y = 0; y < H; ++y) {
    line += out.at(W / 4, y)[0];
    beside += out.at(W / 4 + 3, y)[0];
  }
  EXPECT_GT((line - beside) / H, 0.3) << "the line's height over its neighbours (clean: 0.4)";
}

TEST(Denoise, WithoutNoiseTheImageIsReturnedAsItIs) {
  // Variance 0 everywhere (a converged render, or one sample a pixel): only equal
  // patches mix, so every value comes back bit for bit.
  const Image clean = clean_picture(40, 24);
  const Image out = denoise(clean, Image(40, 24, 3, 0.0f));
  ASSERT_EQ(out.pixels.size(), clean.pixels.size());
  for (std::size_t i = 0; i < out.pixels.size(); ++i) ASSERT_EQ(out.pixels[i], clean.pixels[i]) << i;
  // A zero window (radius 0) is the identity too, whatever the variance.
  DenoiseSettings none;
  none.radius = 0;
  const Image same = denoise(clean, Image(40, 24, 3, 1.0f), none);
  for (std::size_t i = 0; i < same.pixels.size(); ++i) ASSERT_EQ(same.pixels[i], clean.pixels[i]) << i;
}

TEST(Denoise, ExtremeAndNonFiniteInputsGiveFiniteOutput) {
  // 10^4 random pictures of random sizes (1x1 up to 9x7), values and variances
  // from 0 to 1e38 of either sign, some NaN or infinite: every pixel whose colour
  // was finite comes back finite and within the range of the finite colours, and a
  // pixel with a non-finite colour or variance comes back as it was.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const auto value = [&] {
    const float r = u(rng);
    if (r < 0.03f) return std::numeric_limits<float>::quiet_NaN();
    if (r < 0.06f) return (u(rng) < 0.5f ? -1.0f : 1.0f) * std::numeric_limits<float>::infinity();
    return (u(rng) < 0.2f ? -1.0f : 1.0f) * std::pow(10.0f, -38.0f + 76.0f * u(rng));
  };
  for (int trial = 0; trial < 10000; ++trial) {
    const int W = 1 + int(u(rng) * 9), H = 1 + int(u(rng) * 7);
    Image c(W, H, 3), v(W, H, 3);
    for (float& x : c.pixels) x = value();
    for (float& x : v.pixels) x = std::fabs(value());
    float lo = INFINITY, hi = -INFINITY;
    for (float x : c.pixels)
      if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
    DenoiseSettings s;
    s.radius = 1 + trial % 3;
    s.threads = 1;
    const Image out = denoise(c, v, s);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const float* a = c.at(x, y);
        const float* b = out.at(x, y);
        const float* va = v.at(x, y);
        const bool usable = std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]) &&
                            std::isfinite(va[0]) && std::isfinite(va[1]) && std::isfinite(va[2]);
        for (int ch = 0; ch < 3; ++ch) {
          if (!usable) {
            ASSERT_TRUE(std::isnan(a[ch]) ? std::isnan(b[ch]) : b[ch] == a[ch]) << trial;
            continue;
          }
          ASSERT_TRUE(std::isfinite(b[ch])) << "trial " << trial << " pixel " << x << "," << y;
          ASSERT_GE(b[ch], lo * (lo < 0 ? 1.0001f : 0.9999f)) << trial;
          ASSERT_LE(b[ch], hi * (hi > 0 ? 1.0001f : 0.9999f)) << trial;
        }
      }
  }
}

TEST(Denoise, BadSettingsAndSizesAreRefused) {
  const Image c(4, 4, 3), v(4, 4, 3);
  DenoiseSettings s;
  s.radius = 17;
  EXPECT_THROW(denoise(c, v, s), Error);
  s = {};
  s.patch = -1;
  EXPECT_THROW(denoise(c, v, s), Error);
  s = {};
  s.k = 0;
  EXPECT_THROW(denoise(c, v, s), Error);
  s = {};
  s.alpha = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(denoise(c, v, s), Error);
  EXPECT_THROW(denoise(c, Image(4, 3, 3)), Error);
  EXPECT_THROW(denoise(Image(4, 4, 1), Image(4, 4, 1)), Error);
  EXPECT_NO_THROW(denoise(Image(0, 0, 3), Image(0, 0, 3)));
}

TEST(Denoise, TheFilmsVarianceIsTheNoiseBetweenSeeds) {
  // What the filter is told: with keep_variance the film holds each pixel's
  // variance of its mean. Two renders of seeds 1 and 2 differ by noise alone, so
  // the mean over pixels of (a - b)^2 / 2 estimates the mean variance; the films'
  // mean variance matches it within 10 % per channel (independent samples, uniform
  // allocation, 16 spp, 48x40 pixels; Owen-scrambled Sobol samples differ between
  // seeds by less than their spread suggests, 16 % less here, so the filter is told
  // a little more noise than there is), and a film made without variance refuses
  // to give one.
  const test::LitTestFeather lit;
  const PathIntegrator& integrator = lit.integrator;
  const Camera camera(CameraSpec{}, 48, 40, lit.scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 16;
  rs.progress = false;
  rs.allocation = SampleAllocation::Uniform;
  rs.keep_variance = true;
  rs.sampler = SamplerKind::Independent;
  rs.seed = 1;
  const Film a = render(camera, integrator, rs);
  rs.seed = 2;
  const Film b = render(camera, integrator, rs);
  const Image ia = a.developed(0), ib = b.developed(0), va = a.developed_variance(0), vb = b.developed_variance(0);
  for (int c = 0; c < 3; ++c) {
    double between = 0, told = 0;
    for (int y = 0; y < ia.height; ++y)
      for (int x = 0; x < ia.width; ++x) {
        const double d = double(ia.at(x, y)[c]) - ib.at(x, y)[c];
        between += d * d / 2;
        told += 0.5 * (double(va.at(x, y)[c]) + vb.at(x, y)[c]);
      }
    ASSERT_GT(between, 0.0) << c;
    EXPECT_NEAR(told / between, 1.0, 0.1) << "channel " << c;
  }
  rs.keep_variance = false;
  EXPECT_THROW(render(camera, integrator, rs).developed_variance(0), Error);
}

TEST(Denoise, ARenderComesCloserToItsReference) {
  // The rock dove under the dome in both shading modes, 48x48 at 8 spp, with and
  // without the filter, against the same view at 128 spp (another seed): the
  // filtered render is at least 1.6 times closer (RMS; 0.19 -> 0.10 in hair mode,
  // 0.32 -> 0.14 in substructure mode), and its mean within 1 % of
  // the reference's (what it blurs, it keeps).
  const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  const DomeRig rig = read_dome_rig(fs::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  ViewSpec view;
  view.width = 48;
  view.height = 48;
  view.max_depth = 8;
  view.exposure = 3;
  view.camera.position = glm::vec3(0.0f, 60.0f, 40.0f);
  view.camera.look_at = glm::vec3(0.0f, 60.0f, 0.0f);
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.5f)};
  for (ShadingMode m : {ShadingMode::Hair, ShadingMode::Substructure}) {
    so.mode = m;
    const Scene scene(f, so);
    ViewSpec ref = view;
    ref.spp = 128;
    ref.seed = 99;
    const Image reference = render_view(scene, rig, ref);
    ViewSpec v = view;
    v.spp = 8;
    v.seed = 1;
    const Image raw = render_view(scene, rig, v);
    v.denoise = true;
    const Image filtered = render_view(scene, rig, v);
    const double e_raw = rmse(raw, reference), e_filtered = rmse(filtered, reference);
    EXPECT_LT(e_filtered * 1.6, e_raw) << to_string(m) << ": " << e_raw << " -> " << e_filtered;
    double mean_f = 0, mean_r = 0;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
      mean_f += filtered.pixels[i];
      mean_r += reference.pixels[i];
    }
    EXPECT_NEAR(mean_f / mean_r, 1.0, 0.01) << to_string(m);
    // A part of a split render has no neighbours beyond its rows to filter with.
    v.tile_count = 2;
    EXPECT_THROW(render_view(scene, rig, v), Error);
  }
}
