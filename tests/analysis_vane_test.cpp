// Vane widths (generator/src/analysis/vane.cpp): a side counts as present at a
// station where the photo's mask reaches past the rachis there. The rachis narrows
// toward the tip, so a vane narrower than the quill is still measured, with
// confidence, where the rachis beside it is thin.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "plumage/common/image.h"
#include "plumage/generator/analysis/analyze.h"
#include "synthetic_feather.h"

using namespace plumage;
using plumage::synthetic::SyntheticFeather;
namespace fs = std::filesystem;

TEST(AnalysisVane, ANarrowVaneBesideAThickQuillIsMeasuredTowardTheTip) {
  SyntheticFeather F;
  F.dir_deg = -80;
  F.shaft_width = 14;  // the quill: half of it plus a pixel is wider than the narrow vane near the tip
  F.w_left = 7;
  F.w_right = 90;
  const fs::path dir = fs::temp_directory_path() / ("plumage_vane_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_image(dir / "feather.png", F.draw());
  AnalyzeOptions opt;
  opt.mm_per_px = 0.1;
  const PhotoAnalysis A = analyze_photo(dir / "feather.png", opt);
  fs::remove_all(dir);
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  const FeatherLayout& f = A.layout.feathers[0];
  int checked = 0;
  for (std::size_t k = 0; k < f.stations_t.size(); ++k) {
    const double t = f.stations_t[k];
    if (t < 0.5 || t > 0.85) continue;
    const double drawn_px = F.half_width(t * F.length, -1);
    ASSERT_LT(drawn_px, 0.5 * F.shaft_width + 1) << "the case needs a vane narrower than half the quill";
    EXPECT_GE(f.left.width_confidence[k], 0.9) << "t " << t << ": drawn " << drawn_px << " px";
    // The mask reaches into the drawn edge's blur: widths read 1-3 px over the drawn.
    EXPECT_NEAR(f.left.width_mm[k] / *opt.mm_per_px, drawn_px + 1.5, 2.0) << "t " << t;
    ++checked;
  }
  EXPECT_GE(checked, 6);
}
