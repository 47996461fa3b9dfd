// Barb angles read off barbs, not off colour bars across the vane (blue-jay and
// peregrine feathers): a synthetic feather with dark bars whose edges run across
// the vane (they would read as barbs at about 90 degrees) and a bright highlight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <unistd.h>

#include "plumage/common/median.h"
#include "plumage/common/image.h"
#include "plumage/analysis/analyze.h"
#include "plumage/generator/layout_to_params.h"
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

// Chevron bars: dark bands whose edges leave the shaft toward the tip at
// `bar_deg` on both vanes (as on barred tail feathers), every `period` px along
// the shaft, `bar` px long, darkened to `dark` of the brightness.
Image chevron_barred(const SyntheticFeather& F, double bar_deg, double period, double bar, float dark) {
  Image img = F.draw();
  const double cot = 1.0 / std::tan(bar_deg * kPi / 180.0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 p(x + 0.5, y + 0.5);
      if (!F.inside(p)) continue;
      const double along = glm::dot(p - F.calamus, F.dir()), across = glm::dot(p - F.calamus, F.right());
      const double phase = along - std::fabs(across) * cot;
      if (std::fabs(across) < F.shaft_width || std::fmod(phase + 10 * period, period) >= bar) continue;
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] *= dark;
    }
  return img;
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

// Bars slanted like barbs (edges at 75 degrees, under 90, so not rejected as
// pointing back), dense (11 px dark in every 26 px) and far stronger than the
// faint barbs, as on barred tail feathers: without telling step edges from
// barbs, the orientation mode read the bars (62-70 degrees at confidences
// 0.45-0.68 on the light card). The smoothed profile and the generated vane
// still get the drawn barb angle (38 degrees) within 4 degrees everywhere.
TEST(AnalysisBarring, SlantedBarsDoNotSetTheBarbAngle) {
  for (bool dark_background : {false, true}) {
    SyntheticFeather F;
    F.dark_background = dark_background;
    F.theta_deg = 38;
    F.barb_contrast = 0.1;  // faint barbs, bars 7 times their contrast
    const std::string tag = dark_background ? " dark" : " light";
    const fs::path photo = fs::temp_directory_path() /
                           ("plumage_chevrons_" + std::to_string(dark_background) + "_" + std::to_string(::getpid()) + ".png");
    write_image(photo, chevron_barred(F, 75.0, 26.0, 11.0, 0.3f));
    AnalyzeOptions opt;
    opt.mm_per_px = 0.1;
    const PhotoAnalysis A = analyze_photo(photo, opt);
    fs::remove(photo);
    ASSERT_EQ(A.layout.feathers.size(), 1u);
    const FeatherLayout& f = A.layout.feathers[0];
    const LayoutParams lp = layout_to_params(f, "chevrons.json");
    const double calamus_t = lp.params.shaft.calamus_length / lp.params.shaft.length;
    for (const VaneProfile* v : {&f.left, &f.right}) {
      const std::string side = v == &f.left ? "left" : "right";
      std::ostringstream read;
      for (std::size_t k = 0; k < v->barb_angle_deg.size(); ++k)
        read << " " << std::lround(v->barb_angle_deg[k]) << "@" << std::lround(100 * v->barb_angle_confidence[k]);
      // Every station, smoothed, within 4 degrees of the drawn angle.
      const BarbAngleFit fit = barb_angles_along_shaft(f.stations_t, v->barb_angle_deg, v->barb_angle_confidence, calamus_t);
      EXPECT_FALSE(fit.from_prior) << side << tag;
      double worst = 0;
      for (double a : fit.angle_deg) worst = std::max(worst, std::fabs(a - F.theta_deg));
      EXPECT_LT(worst, 4.0) << side << tag << "; read (deg@conf%):" << read.str();
      // And so does the generated vane, past its base (where it widens faster
      // than barbs at 38 degrees can follow and the angle is raised).
      const Profile& a = (v == &f.left ? lp.params.left : lp.params.right).angle_deg;
      worst = 0;
      for (double x = 0.3; x <= 0.95; x += 0.05) worst = std::max(worst, std::fabs(a(x) - F.theta_deg));
      EXPECT_LT(worst, 4.0) << side << tag << " (generated vane)";
    }
  }
}
