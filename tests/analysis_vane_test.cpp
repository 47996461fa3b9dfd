// Vane measurements (analysis/src/vane.cpp). Widths: a side counts as
// present at a station where the photo's mask reaches past the rachis there. The
// rachis narrows toward the tip, so a vane narrower than the quill is still
// measured, with confidence, where the rachis beside it is thin. The downy base:
// stations from the base whose texture at the barb scale is faint. Plumes: both
// vanes open, the card between loose barbs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <unistd.h>

#include "plumage/common/image.h"
#include "plumage/analysis/analyze.h"
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

namespace {

PhotoAnalysis analyse_drawn(const SyntheticFeather& F, double mm_per_px) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_downy_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_image(dir / "feather.png", F.draw());
  AnalyzeOptions opt;
  opt.mm_per_px = mm_per_px;
  PhotoAnalysis A = analyze_photo(dir / "feather.png", opt);
  fs::remove_all(dir);
  return A;
}

}  // namespace

// A vane whose barbs are soft and faint over its base on one side is reported
// as that side's downy base, ending where the drawing's does within a station
// and a half; the other side, and the same feather drawn without down, have none.
TEST(AnalysisVane, ADownyBaseIsFoundOnItsSideOnly) {
  for (int side : {-1, +1}) {
    SyntheticFeather F;
    F.downy_to = 0.2;
    F.downy_side = side;
    const PhotoAnalysis A = analyse_drawn(F, 0.1);
    ASSERT_EQ(A.layout.feathers.size(), 1u);
    const FeatherLayout& f = A.layout.feathers[0];
    // The drawn down ends at this fraction of the shaft (the analysed calamus is the drawn one).
    const double drawn_t = (F.vane_start() + F.downy_to * (F.length - F.vane_start())) / F.length;
    const double station = 1.0 / f.stations_t.size();
    const VaneProfile& downy = side < 0 ? f.left : f.right;
    const VaneProfile& plain = side < 0 ? f.right : f.left;
    EXPECT_NEAR(downy.afterfeather_to_t, drawn_t, 1.5 * station) << "side " << side;
    EXPECT_EQ(plain.afterfeather_to_t, 0.0) << "side " << side;
  }
  SyntheticFeather plain;
  const PhotoAnalysis A = analyse_drawn(plain, 0.1);
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_EQ(A.layout.feathers[0].left.afterfeather_to_t, 0.0);
  EXPECT_EQ(A.layout.feathers[0].right.afterfeather_to_t, 0.0);
}

// Down is told from vane only where the photo resolves barbs: at a scale where the
// drawn period is 8 mm, far more than any feather's barb spacing (a period of
// texture, docs/analysis.md "Barb density"), the same faint base is not down.
TEST(AnalysisVane, NoDownyBaseWhereThePhotoDoesNotResolveBarbs) {
  SyntheticFeather F;
  F.downy_to = 0.2;
  const PhotoAnalysis A = analyse_drawn(F, 0.9);
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_EQ(A.layout.feathers[0].left.afterfeather_to_t, 0.0);
  EXPECT_EQ(A.layout.feathers[0].right.afterfeather_to_t, 0.0);
  // ... while at 0.1 mm/px both sides have one.
  const PhotoAnalysis B = analyse_drawn(F, 0.1);
  ASSERT_EQ(B.layout.feathers.size(), 1u);
  EXPECT_GT(B.layout.feathers[0].left.afterfeather_to_t, 0.0);
  EXPECT_GT(B.layout.feathers[0].right.afterfeather_to_t, 0.0);
}

// A plume (docs/analysis.md, "Plumes: an open vane"): loose, curling barbs with the
// card between them over most of the vane, on a light and on a dark card, is
// downy from base to tip on both sides; the same feather drawn closed, or with
// barbs that leave only a tenth of the vane open, is not.
TEST(AnalysisVane, APlumeIsDownyFromBaseToTipAndAClosedVaneIsNot) {
  for (const bool dark : {false, true}) {
    SCOPED_TRACE(dark ? "dark card" : "light card");
    for (const double open : {0.0, 0.1, 0.8}) {
      SyntheticFeather F;
      F.dark_background = dark;
      F.plume_open = open;
      F.spacing = 16;  // loose barbs lie farther apart than a vane's (1.6 mm here)
      const PhotoAnalysis A = analyse_drawn(F, 0.1);
      ASSERT_EQ(A.layout.feathers.size(), 1u) << "open " << open;
      const FeatherLayout& f = A.layout.feathers[0];
      std::cerr << "  open " << open << ": open share " << f.left.open_share << " / " << f.right.open_share << "\n";
      if (open >= 0.5) {
        EXPECT_GE(std::min(f.left.open_share, f.right.open_share), 0.4) << "open " << open;  // kPlumeOpenShare
        EXPECT_EQ(f.left.afterfeather_to_t, 1.0) << "open " << open;
        EXPECT_EQ(f.right.afterfeather_to_t, 1.0) << "open " << open;
      } else {
        EXPECT_LT(std::max(f.left.open_share, f.right.open_share), 0.3) << "open " << open;
        EXPECT_LT(f.left.afterfeather_to_t, 1.0) << "open " << open;
        EXPECT_LT(f.right.afterfeather_to_t, 1.0) << "open " << open;
      }
    }
  }
}
