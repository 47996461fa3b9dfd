// `plumage compare`: the side-by-side of the rock-dove preset, hair and
// substructure, against a stored reference (data/golden/compare_rock_dove.exr)
// with a tolerance; the panel layout and labels; and the command's errors.
// After an intended change to the substructure technique, the renderer or the
// preset, regenerate the reference with
//   PLUMAGE_UPDATE_GOLDEN=1 build/plumage_tests --gtest_filter='CompareGolden.*'
// and look at it before committing.
#include <unistd.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/label_font.h"
#include "plumage/renderer/panel_layout.h"
#include "cli_run.h"
#include "render_test_feather.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

const Feather& rock_dove() {
  static const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  return f;
}

Image side_by_side_of(const Feather& feather, std::uint64_t seed) {
  const DomeRig rig = read_dome_rig(fs::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  ViewSpec view;
  view.width = 32;
  view.height = 64;
  view.spp = 48;
  view.seed = seed;
  view.max_depth = 8;
  view.exposure = 3;
  // On the vanes' middle, where barbules make the difference.
  view.camera.position = glm::vec3(0.0f, 60.0f, 70.0f);
  view.camera.look_at = glm::vec3(0.0f, 60.0f, 0.0f);
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.03f)};
  std::vector<Panel> panels;
  for (ShadingMode m : {ShadingMode::Hair, ShadingMode::Substructure}) {
    so.mode = m;
    const Scene scene(feather, so);
    panels.push_back({render_view(scene, rig, view), to_string(m)});
  }
  return side_by_side(panels, 1);
}

// Values clamped to 1 as the PNG a person looks at is (glints on the fibres are
// fireflies at this sample count), 8x8 box averages (Monte Carlo noise averages
// out, changes in the picture do not), then the mean absolute difference relative
// to the reference's mean, below the label strip (the same in every image), from
// column x0 on.
double rel_mae(const Image& a, const Image& b, int x0 = 0) {
  double diff = 0, ref = 0;
  for (int y = 16; y + 8 <= b.height; y += 8)
    for (int x = x0; x + 8 <= b.width; x += 8)
      for (int c = 0; c < 3; ++c) {
        double sa = 0, sb = 0;
        for (int j = 0; j < 8; ++j)
          for (int i = 0; i < 8; ++i) {
            sa += std::fmin(a.at(x + i, y + j)[c], 1.0f);
            sb += std::fmin(b.at(x + i, y + j)[c], 1.0f);
          }
        diff += std::fabs(sa - sb);
        ref += sb;
      }
  return diff / std::fmax(ref, 1e-12);
}

const fs::path kGolden = fs::path(PLUMAGE_DATA_DIR) / "golden/compare_rock_dove.exr";
constexpr double kMaxRelMae = 0.06;

}  // namespace

TEST(CompareGolden, RockDoveSideBySideMatchesReference) {
  const Image img = side_by_side_of(rock_dove(), 1);
  if (std::getenv("PLUMAGE_UPDATE_GOLDEN")) {
    write_image(kGolden, img);
    GTEST_SKIP() << "wrote " << kGolden;
  }
  const Image ref = read_image(kGolden);
  ASSERT_EQ(ref.width, img.width);
  ASSERT_EQ(ref.height, img.height);
  const double same = rel_mae(img, ref), reseeded = rel_mae(side_by_side_of(rock_dove(), 2), ref);
  std::printf("relative MAE: same seed %.4f, another seed %.4f (limit %.2f)\n", same, reseeded, kMaxRelMae);
  EXPECT_LT(same, kMaxRelMae);
  // The tolerance admits Monte Carlo noise: another seed passes too.
  EXPECT_LT(reseeded, kMaxRelMae);
}

TEST(CompareGolden, ComparisonCatchesAChangedSubstructure) {
  if (std::getenv("PLUMAGE_UPDATE_GOLDEN")) GTEST_SKIP();
  const Image ref = read_image(kGolden);
  // Rami without barbules: the substructure panel must change enough to fail.
  Feather sparse = rock_dove();
  sparse.left.barbules_per_side = sparse.right.barbules_per_side = 0;
  const Image img = side_by_side_of(sparse, 1);
  ASSERT_EQ(ref.width, img.width);
  // Only the right half, the substructure panel: the hair panel is the same image,
  // and with absorbing fibres (layer albedo mapping) averaging it in would dilute
  // the change below the noise limit.
  const double changed = rel_mae(img, ref, ref.width / 2);
  std::printf("relative MAE without barbules: %.4f (limit %.2f)\n", changed, kMaxRelMae);
  EXPECT_GT(changed, kMaxRelMae);
}

TEST(PanelLayout, PanelsShareHeightAndCarryLabels) {
  Image a(20, 40, 3, 0.5f), photo(100, 50, 3, 1.0f);
  const Image out = side_by_side({{photo, "photo"}, {a, "hair"}});
  // The render is scaled to the tallest panel's height: 25 x 50 (the label is wider).
  EXPECT_EQ(out.width, 6 + 100 + 6 + std::max(25, text_width("hair", 2)) + 6);
  EXPECT_GT(out.height, 40);
  // Label ink is white on the dark strip; the panels are below it.
  int ink = 0;
  for (int y = 0; y < text_height(2) + 8; ++y)
    for (int x = 0; x < out.width; ++x) ink += out.rgb(x, y).x > 0.9f;
  EXPECT_GT(ink, 20);
  EXPECT_NEAR(out.rgb(6 + 50, out.height - 10).x, 1.0f, 1e-6f);  // photo
  EXPECT_NEAR(out.rgb(6 + 100 + 6 + 5, out.height - 10).x, 0.5f, 1e-6f);  // render
  EXPECT_THROW(side_by_side({}), Error);
  EXPECT_THROW(scale_to_height(Image(), 10), Error);
}

TEST(PanelLayout, TextIsClippedNotWrittenOutOfBounds) {
  Image img(10, 5, 3);
  draw_text(img, -7, -3, "SUBSTRUCTURE 0123456789 (x/y) #%", glm::vec3(1), 3);
  draw_text(img, 8, 4, "AB", glm::vec3(1), 1);
  EXPECT_EQ(img.pixels.size(), 150u);
  // Different letters draw different pixels.
  Image a(6, 7, 3), b(6, 7, 3);
  draw_text(a, 0, 0, "H", glm::vec3(1), 1);
  draw_text(b, 0, 0, "S", glm::vec3(1), 1);
  EXPECT_NE(a.pixels, b.pixels);
  EXPECT_EQ(text_width("AB", 2), (2 * kGlyphAdvance - 1) * 2);
}

TEST(PanelLayout, ContactSheetGrid) {
  std::vector<Panel> tiles;
  for (int i = 0; i < 7; ++i) tiles.push_back({Image(30, 20, 3, float(i) / 10), "LED " + std::to_string(i + 1)});
  const Image sheet = contact_sheet(tiles, 3, "hair: one LED at a time");
  // 3 columns, 3 rows of tiles.
  EXPECT_GE(sheet.width, 3 * 30);
  EXPECT_GE(sheet.height, 3 * 20);
  EXPECT_THROW(contact_sheet(tiles, 0, "x"), Error);
}

namespace {
using CliRun = test::CliStreams;
CliRun run_cli(const std::string& args) { return test::plumage_cli_streams("-q " + args); }

// The test feather with substructure parameters, so both shading modes can render it.
Feather feather_with_substructure(float length) {
  Feather f = test::make_test_feather(length, 1.0f, 0.05f);
  SubstructureParams p;
  p.barbules_per_side = 40;
  p.ramus_radius = 0.04f;
  p.barbule_radius = 0.01f;
  p.ribbon_width = 0.3f;
  f.left = f.right = p;
  return f;
}
}  // namespace

TEST(CompareCli, WritesSideBySideAndLightSequenceAndRejectsBadInput) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_compare_cli_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string in = (dir / "f.fcurves").string();
  write_fcurves(in, feather_with_substructure(12.0f));
  write_image(dir / "photo.png", Image(40, 80, 3, 0.3f));

  CliRun r = run_cli("compare " + in + " --photo " + (dir / "photo.png").string() + " -o " +
                     (dir / "side.png").string() + " --spp 1 --resolution 16x24");
  ASSERT_EQ(r.rc, 0) << r.err;
  const Image side = read_image(dir / "side.png");
  EXPECT_GT(side.width, 3 * 16);

  r = run_cli("compare " + in + " --light-sequence --lights 1-3 -o " + (dir / "seq.png").string() +
              " --spp 1 --resolution 8x12");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "seq_hair.png"));
  EXPECT_TRUE(fs::exists(dir / "seq_substructure.png"));

  r = run_cli("compare " + in + " --photo " + (dir / "missing.jpg").string() + " -o " + (dir / "x.png").string());
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("missing.jpg"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));

  r = run_cli("compare " + in + " --barbule-elevation 0 -o " + (dir / "x.png").string());
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("--barbule-elevation"), std::string::npos) << r.err;

  // The structure AOV needs substructure shading, and works with it.
  r = run_cli("render " + in + " --aov structure -o " + (dir / "aov.png").string());
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("--shading substructure"), std::string::npos) << r.err;
  r = run_cli("render " + in + " --shading substructure --aov structure --resolution 16x16 -o " +
              (dir / "aov.png").string() + " --barbules 20 --ramus-radius 0.05");
  EXPECT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "aov.png"));
}

namespace {
// The number `--stats` prints after `name` (the value ends the line), or -1.
double stat_value(const std::string& out, const std::string& name) {
  const auto at = out.find("    " + name + " ");
  if (at == std::string::npos) return -1;
  const auto end = out.find('\n', at);
  return std::stod(out.substr(out.find_last_of(' ', end) + 1, end - out.find_last_of(' ', end) - 1));
}
}  // namespace

// `compare --cull` goes through the same view path as `render --cull`: a zoomed
// view over the vane leaves curves out of both scenes, and with direct light only
// (the shadows it keeps are all there is) the panels look as they do without it.
TEST(CompareCli, CullLeavesOutWhatAZoomedViewCannotShow) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_compare_cull_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string in = (dir / "f.fcurves").string();
  write_fcurves(in, feather_with_substructure(40.0f));
  const std::string args = "--stats compare " + in +
                           " --camera-pos 3,12,4 --look-at 3,12,0 --max-depth 1 --spp 2 --resolution 12x12 -o ";
  const std::string culled_name = "Curves culled (outside the view and its shadow reach)";

  CliRun r = run_cli(args + (dir / "all.exr").string());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(stat_value(r.err, culled_name), 0) << r.err;
  r = run_cli(args + (dir / "culled.exr").string() + " --cull");
  ASSERT_EQ(r.rc, 0) << r.err;
  const double culled = stat_value(r.err, culled_name);
  EXPECT_GT(culled, 0) << r.err;

  const Image all = read_image(dir / "all.exr"), part = read_image(dir / "culled.exr");
  ASSERT_EQ(all.pixels.size(), part.pixels.size());
  double diff = 0, sum = 0;
  for (std::size_t i = 0; i < all.pixels.size(); ++i) {
    diff += std::abs(all.pixels[i] - part.pixels[i]);
    sum += all.pixels[i];
  }
  ASSERT_GT(sum, 0);
  std::printf("compare --cull: %.0f curves culled, relative difference %.2g\n", culled, diff / sum);
  EXPECT_LT(diff / sum, 1e-3);
  fs::remove_all(dir);
}
