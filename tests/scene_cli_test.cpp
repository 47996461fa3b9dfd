// `plumage render` and `plumage info` on a .fscene end to end: the scene renders
// with every placement in view and its mirrored placement mirrored, the scene's
// camera and lights yield to flags, `info --json` counts placements, distinct
// feathers and barbs over all placements, and a bad scene fails with one line at
// FILE:LINE:COL and leaves no image.
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "plumage/common/curve_format.h"
#include "plumage/common/image.h"
#include "cli_run.h"
#include "render_test_feather.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

fs::path scene_dir() {
  const fs::path dir = fs::temp_directory_path() / ("plumage_scene_cli_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "feathers");
  Feather f = test::make_test_feather(20.0f, 0.25f, 0.1f);  // a dense vane: dark where it lies
  std::erase_if(f.curves, [](const Curve& c) { return c.side == VaneSide::Left; });  // one vane: mirroring shows
  f.albedo.color = {0.1f, 0.08f, 0.06f};
  for (SubstructureParams* p : {&f.left, &f.right})  // for the substructure panel of compare
    *p = SubstructureParams{24, 0.02f, 0.004f, 40.0f, 10.0f, 0.2f, 0.3f};
  write_fcurves(dir / "feathers" / "vane.fcurves", f);
  std::ofstream(dir / "pair.fscene") << "fscene 1\n"
                                        "feather v fcurves \"feathers/vane.fcurves\"\n"
                                        "lights none\n"
                                        "place v translate 4 0 0\n"
                                        "place v mirror x translate -4 0 0\n"
                                        "end\n";
  return dir;
}

// Mean luminance of the columns [x0, x1) of an image.
double column_mean(const Image& im, int x0, int x1) {
  double s = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = x0; x < x1; ++x) s += luminance(glm::vec3(im.at(x, y)[0], im.at(x, y)[1], im.at(x, y)[2]));
  return s / (double(im.height) * (x1 - x0));
}

}  // namespace

TEST(SceneCli, RendersEveryPlacementAndLetsFlagsOverrideTheScenesLights) {
  const fs::path dir = scene_dir();
  const std::string scene = (dir / "pair.fscene").string();
  // The scene turns every LED off: black but for --env.
  const auto dark = test::plumage_cli("-q render " + scene + " -o " + (dir / "dark.exr").string() +
                                      " --spp 2 --resolution 40x24 --backdrop none");
  ASSERT_EQ(dark.rc, 0) << dark.output;
  EXPECT_NE(dark.output.find("no light is on"), std::string::npos) << dark.output;
  EXPECT_LT(column_mean(read_image(dir / "dark.exr"), 0, 40), 1e-6);
  // --lights on the command line wins over the scene's 'lights none'.
  const auto lit = test::plumage_cli("-q render " + scene + " -o " + (dir / "lit.exr").string() +
                                     " --spp 4 --resolution 40x24 --lights all --backdrop white --env 0.3");
  ASSERT_EQ(lit.rc, 0) << lit.output;
  const Image im = read_image(dir / "lit.exr");
  // The two vanes face away from each other (columns 12-15 and 25-28 hold vane),
  // the card shows between the two shafts; both halves alike.
  const double left = column_mean(im, 12, 15), right = column_mean(im, 25, 28), mid = column_mean(im, 18, 22);
  EXPECT_LT(left, 0.9 * mid);
  EXPECT_LT(right, 0.9 * mid);
  EXPECT_NEAR(left, right, 0.1 * (left + right));
}

TEST(SceneCli, InfoCountsPlacementsDistinctFeathersAndBarbs) {
  const fs::path dir = scene_dir();
  const auto r = test::plumage_cli_streams("info " + (dir / "pair.fscene").string() + " --json");
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const std::size_t barbs = read_fcurves(dir / "feathers" / "vane.fcurves").count(CurveKind::Barb);
  EXPECT_EQ(j.at("placements").get<int>(), 2);
  EXPECT_EQ(j.at("distinct_feathers").get<int>(), 1);
  EXPECT_EQ(j.at("barbs").get<std::size_t>(), 2 * barbs);
  EXPECT_EQ(j.at("mirrored_placements").get<int>(), 1);
  EXPECT_EQ(j.at("feathers").at(0).at("placements").get<int>(), 2);
}

TEST(SceneCli, BadScenesFailAtTheirPlaceAndWriteNothing) {
  const fs::path dir = scene_dir();
  const std::pair<std::string, std::string> cases[] = {
      {"fscene 1\nfeather v fcurves \"feathers/none.fcurves\"\nplace v\nend\n", "bad.fscene:2:1: feather 'v': "},
      {"fscene 1\nfeather v fcurves \"feathers/vane.fcurves\"\nplace v scale 1 2\nend\n", "bad.fscene:3:17: place: unknown operation '2'"},
      {"fscene 1\nfeather v preset no-such-bird seed 1\nplace v\nend\n", "unknown preset 'no-such-bird'"},
      {"fscene 1\nfeather v fcurves \"feathers/vane.fcurves\"\nlights 99\nplace v\nend\n", "lights"},
  };
  for (const auto& [text, expected] : cases) {
    std::ofstream(dir / "bad.fscene") << text;
    const fs::path out = dir / "bad.png";
    const auto r = test::plumage_cli_streams("-q render " + (dir / "bad.fscene").string() + " -o " + out.string() + " --spp 1 --resolution 8x8");
    EXPECT_EQ(r.rc, 1) << text;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  EXPECT_EQ(test::plumage_cli("-q render " + (dir / "pair.fscene").string() + " -o " + (dir / "x.png").string() + " --aov structure --shading substructure").rc, 2);
}

TEST(SceneCli, TheScenesCameraIsTheFlagsCameraAndFlagsWin) {
  const fs::path dir = scene_dir();
  std::ofstream(dir / "cam.fscene") << "fscene 1\nfeather v fcurves \"feathers/vane.fcurves\"\n"
                                       "camera position 3 5 120 look_at 3 8 0 fov 12\nlights 2,9\nplace v\nend\n";
  std::ofstream(dir / "nocam.fscene") << "fscene 1\nfeather v fcurves \"feathers/vane.fcurves\"\nplace v\nend\n";
  const std::string common = " --spp 2 --resolution 32x24 -o ";
  ASSERT_EQ(test::plumage_cli("-q render " + (dir / "cam.fscene").string() + common + (dir / "a.exr").string()).rc, 0);
  ASSERT_EQ(test::plumage_cli("-q render " + (dir / "nocam.fscene").string() + common + (dir / "b.exr").string() +
                              " --camera-pos 3,5,120 --look-at 3,8,0 --fov 12 --lights 2,9").rc, 0);
  ASSERT_EQ(test::plumage_cli("-q render " + (dir / "cam.fscene").string() + common + (dir / "c.exr").string() + " --fov 40").rc, 0);
  const Image a = read_image(dir / "a.exr"), b = read_image(dir / "b.exr"), c = read_image(dir / "c.exr");
  EXPECT_EQ(a.pixels, b.pixels);  // the scene's records are the flags
  EXPECT_NE(a.pixels, c.pixels);  // and --fov wins over the scene's
}

TEST(SceneCli, CompareShowsTheSceneInBothModesAndExportSaysItCannot) {
  const fs::path dir = scene_dir();
  const std::string scene = (dir / "pair.fscene").string();
  const auto r = test::plumage_cli("-q compare " + scene + " -o " + (dir / "cmp.png").string() +
                                   " --spp 2 --resolution 40x24 --lights all");
  ASSERT_EQ(r.rc, 0) << r.output;
  const Image im = read_image(dir / "cmp.png");
  EXPECT_GE(im.width, 80);  // two panels of 40
  EXPECT_EQ(test::plumage_cli("-q compare " + scene + " -o " + (dir / "seq.png").string() + " --light-sequence").rc, 2);
  const auto e = test::plumage_cli("-q export " + scene + " -o " + (dir / "x.obj").string());
  EXPECT_EQ(e.rc, 2);
  EXPECT_NE(e.output.find("export writes one feather"), std::string::npos) << e.output;
}
