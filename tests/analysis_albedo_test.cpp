// The albedo texture (analysis/src/albedo.cpp): the photo over its
// paper, with the rachis painted out from the vane beside it. A narrow vane beside
// a thick quill keeps its own colour: the painted band narrows toward the tip as the
// built rachis does, and only texels wholly inside the feather fill it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "plumage/common/image.h"
#include "plumage/analysis/analyze.h"
#include "synthetic_feather.h"

using namespace plumage;
using plumage::synthetic::SyntheticFeather;
namespace fs = std::filesystem;

namespace {

struct NarrowVaneCase {
  bool narrow_left;
  double dir_deg;
};

class AnalysisAlbedo : public ::testing::TestWithParam<NarrowVaneCase> {};

// The drawn feather, written as a PNG and analysed at 0.1 mm per pixel.
PhotoAnalysis analyze_drawn(const SyntheticFeather& F) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_albedo_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path photo = dir / "feather.png";
  write_image(photo, F.draw());
  AnalyzeOptions opt;
  opt.mm_per_px = 0.1;
  PhotoAnalysis A = analyze_photo(photo, opt);
  fs::remove_all(dir);
  return A;
}

}  // namespace

TEST_P(AnalysisAlbedo, ANarrowVaneBesideAThickQuillKeepsItsColour) {
  const NarrowVaneCase c = GetParam();
  SyntheticFeather F;
  F.dir_deg = c.dir_deg;
  F.shaft_width = 12;  // the quill, at the calamus; the rachis narrows to half at the tip
  F.w_left = c.narrow_left ? 16 : 90;
  F.w_right = c.narrow_left ? 90 : 16;
  F.barb_contrast = 0;  // a uniform vane: every vane texel should read the same
  F.noise = 0.005;
  const PhotoAnalysis A = analyze_drawn(F);
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  ASSERT_EQ(A.albedo.size(), 1u);
  const FeatherLayout& f = A.layout.feathers[0];
  const Image& tex = A.albedo[0];
  // The drawn vane over the drawn paper, per channel (linear): what a vane texel says.
  const glm::vec3 expect(srgb_to_linear(0.80f) / srgb_to_linear(0.96f), srgb_to_linear(0.50f) / srgb_to_linear(0.96f),
                         srgb_to_linear(0.48f) / srgb_to_linear(0.96f));
  const int side = c.narrow_left ? -1 : 1;
  double sum = 0, worst = 0;
  int n = 0;
  for (double y = 0.35 * F.length; y <= 0.85 * F.length; y += 2.0) {
    // Between the drawn rachis and the narrow vane's edge, 3 px clear of both: of the
    // photo's blur and of a texel grid turned against the pixels.
    const double x0 = 0.5 * F.shaft_width * (1.0 - 0.5 * y / F.length) + 3, x1 = F.half_width(y, side) - 3;
    for (double x = x0; x <= x1; x += 1.0) {
      const glm::dvec2 p = F.calamus + F.dir() * y + F.right() * (side * x);
      const glm::dvec2 q = apply(f.feather_from_image, p);
      const int i = int(std::floor((q.x - f.albedo.origin_mm.x) / f.albedo.mm_per_texel));
      const int j = int(std::floor((f.albedo.origin_mm.y - q.y) / f.albedo.mm_per_texel));
      ASSERT_TRUE(i >= 0 && j >= 0 && i < tex.width && j < tex.height);
      const float g = tex.at(i, j)[1];
      sum += g;
      worst = std::max(worst, std::fabs(g / expect.y - 1.0));
      ++n;
    }
  }
  ASSERT_GT(n, 100);
  const double mean = sum / n;
  std::printf("  narrow vane: %d texels, green %.3f for %.3f, worst %.1f %%\n", n, mean, expect.y, 100 * worst);
  EXPECT_NEAR(mean / expect.y, 1.0, 0.03);
  EXPECT_LT(worst, 0.12);
}

TEST(AnalysisShaftColour, TheRachisKeepsItsOwnColour) {
  // A red-brown rachis on a pink vane over white paper: the layout's shaft_rgb is the
  // rachis's colour over the paper (within 0.06 per channel: blur and noise), not the
  // vane's painted over it; with the rachis drawn in the vane's colour it is the vane's.
  for (double contrast : {1.0, 0.0}) {
    SyntheticFeather F;
    F.shaft_width = 14;
    F.rachis_contrast = contrast;
    F.noise = 0.005;
    const PhotoAnalysis A = analyze_drawn(F);
    ASSERT_EQ(A.layout.feathers.size(), 1u);
    const auto& rgb = A.layout.feathers[0].albedo.shaft_rgb;
    ASSERT_EQ(rgb.size(), 16u) << "contrast " << contrast;
    const glm::vec3 vane(0.80f, 0.50f, 0.48f), drawn = glm::mix(vane, glm::vec3(0.55f, 0.18f, 0.10f), float(contrast));
    // Every station but the last two, where the drawn rachis tapers to a line a
    // pixel or two wide and the vane's colour blurs into it.
    for (std::size_t k = 0; k + 2 < rgb.size(); ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(rgb[k][c], srgb_to_linear(drawn[c]) / srgb_to_linear(0.96f), 0.06)
            << "contrast " << contrast << " station " << k << " channel " << c;
  }
}

TEST(AnalysisShaftColour, AWhiteQuillBelowADarkRachisKeepsBoth) {
  // As on the peregrine sheet: the bare quill is pale, the rachis along the vane
  // dark. The stations below the vane (a fifth of the shaft) hold the quill's
  // colour, those along the vane the rachis's (linear, absolute on a dark card).
  SyntheticFeather F;
  F.dark_background = true;
  F.shaft_width = 14;
  F.noise = 0.005;
  F.calamus_colour = glm::vec3(0.92f, 0.90f, 0.84f);
  const PhotoAnalysis A = analyze_drawn(F);
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  const auto& rgb = A.layout.feathers[0].albedo.shaft_rgb;
  ASSERT_EQ(rgb.size(), 16u);
  const glm::vec3 rachis(0.55f, 0.18f, 0.10f);
  for (std::size_t k : {0u, 1u, 2u})
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(rgb[k][c], srgb_to_linear((*F.calamus_colour)[c]), 0.08) << "station " << k << " channel " << c;
  for (std::size_t k : {5u, 8u, 11u})
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(rgb[k][c], srgb_to_linear(rachis[c]), 0.06) << "station " << k << " channel " << c;
}

INSTANTIATE_TEST_SUITE_P(BothSides, AnalysisAlbedo,
                         ::testing::Values(NarrowVaneCase{true, -90}, NarrowVaneCase{false, -70}));
