// Barb angles read off barbs, not off colour bars across the vane (blue-jay and
// peregrine feathers): a synthetic feather with dark bars whose edges run across
// the vane (they would read as barbs at about 90 degrees) and a bright highlight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "plumage/common/image.h"
#include "plumage/generator/analysis/analyze.h"
#include "synthetic_feather.h"

using namespace plumage;
using plumage::synthetic::SyntheticFeather;
namespace fs = std::filesystem;

namespace {

// The photo of `F` with every `period` px along the shaft a bar `bar` px long
// darkened to `dark` of its brightness, and a highlight (brightened) near the tip.
Image barred(const SyntheticFeather& F, double period, double bar, float dark) {
  Image img = F.draw();
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 p(x + 0.5, y + 0.5);
      if (!F.inside(p)) continue;
      const double along = glm::dot(p - F.calamus, F.dir());
      const double across = glm::dot(p - F.calamus, F.right());
      float k = std::fmod(along, period) < bar ? dark : 1.0f;
      if (along > 0.75 * F.length && along < 0.85 * F.length && across > 10 && across < 40) k = 1.8f;
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] = std::min(1.0f, img.at(x, y)[c] * k);
    }
  return img;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST(AnalysisBarring, BarsAcrossTheVaneAreNotBarbs) {
  for (bool dark_background : {false, true}) {
    SyntheticFeather F;
    F.dark_background = dark_background;
    F.theta_deg = 38;
    const fs::path photo = fs::temp_directory_path() /
                           ("plumage_barred_" + std::to_string(dark_background) + "_" + std::to_string(::getpid()) + ".png");
    write_image(photo, barred(F, 60.0, 22.0, 0.3f));
    AnalyzeOptions opt;
    opt.mm_per_px = 0.1;
    const PhotoAnalysis A = analyze_photo(photo, opt);
    fs::remove(photo);
    ASSERT_EQ(A.layout.feathers.size(), 1u);
    const FeatherLayout& f = A.layout.feathers[0];
    for (const VaneProfile* v : {&f.left, &f.right}) {
      std::vector<double> sure;
      for (std::size_t k = 0; k < v->barb_angle_deg.size(); ++k) {
        if (v->barb_angle_confidence[k] < 0.5) continue;
        sure.push_back(v->barb_angle_deg[k]);
        // No confident station reads the bars' edges (about 90 degrees).
        EXPECT_LT(std::fabs(v->barb_angle_deg[k] - F.theta_deg), 10.0)
            << (v == &f.left ? "left" : "right") << " station " << k << (dark_background ? " dark" : " light");
      }
      ASSERT_GE(sure.size(), 6u);
      EXPECT_NEAR(median(sure), F.theta_deg, 3.0) << (dark_background ? "dark" : "light");
    }
  }
}
