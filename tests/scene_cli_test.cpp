// `plumage render` and `plumage info` on a .fscene end to end: the scene renders
// with every placement in view and its mirrored placement mirrored, the scene's
// camera and lights yield to flags, `info --json` counts placements, distinct
// feathers and barbs over all placements, and a bad scene fails with one line at
// FILE:LINE:COL and leaves no image.
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include <string>

#include <nlohmann/json.hpp>

#include "plumage/common/curve_format.h"
#include "plumage/layout/layout.h"
#include "plumage/common/image.h"
#include "cli_run.h"
#include "drawn_layout.h"
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

TEST(SceneCli, CompareShowsTheSceneInBothModes) {
  const fs::path dir = scene_dir();
  const std::string scene = (dir / "pair.fscene").string();
  const auto r = test::plumage_cli("-q compare " + scene + " -o " + (dir / "cmp.png").string() +
                                   " --spp 2 --resolution 40x24 --lights all");
  ASSERT_EQ(r.rc, 0) << r.output;
  const Image im = read_image(dir / "cmp.png");
  EXPECT_GE(im.width, 80);  // two panels of 40
  EXPECT_EQ(test::plumage_cli("-q compare " + scene + " -o " + (dir / "seq.png").string() + " --light-sequence").rc, 2);
}

// Each target gets the one distinct feather once and both placements: pbrt an
// object and two instances whose Transform is the placement's matrix column by
// column, Mitsuba a shapegroup loading the feather's own curves file and two
// instances (row by row), Blender one feather and two placements, OBJ both
// placements' control points carried into the scene; fcurves is refused.
TEST(SceneCli, ExportWritesEachFeatherOnceAndEveryPlacement) {
  const fs::path dir = scene_dir();
  const std::string scene = (dir / "pair.fscene").string();
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  const auto read = [](const fs::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  ASSERT_EQ(test::plumage_cli("-q export " + scene + " -o " + (dir / "w.pbrt").string()).rc, 0);
  const std::string pbrt = read(dir / "w.pbrt");
  EXPECT_EQ(count(pbrt, "ObjectBegin \"v\""), 1u);
  EXPECT_EQ(count(pbrt, "ObjectInstance \"v\""), 2u);
  EXPECT_NE(pbrt.find("Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 4 0 0 1 ]"), std::string::npos) << pbrt.substr(0, 4000);
  EXPECT_NE(pbrt.find("Transform [ -1 0 0 0 0 1 0 0 0 0 1 0 -4 0 0 1 ]"), std::string::npos);
  EXPECT_EQ(count(pbrt, "Shape \"curve\""), read_fcurves(dir / "feathers" / "vane.fcurves").curves.size());

  ASSERT_EQ(test::plumage_cli("-q export " + scene + " --format mitsuba -o " + (dir / "m.txt").string()).rc, 0);
  const std::string xml = read(dir / "m.xml");
  EXPECT_EQ(count(xml, "<shape type=\"shapegroup\" id=\"feather_v\">"), 1u);
  EXPECT_EQ(count(xml, "<ref id=\"feather_v\"/>"), 2u);
  EXPECT_NE(xml.find("value=\"m.v.txt\""), std::string::npos);
  EXPECT_NE(xml.find("<matrix value=\"-1 0 0 -4 0 1 0 0 0 0 1 0 0 0 0 1\"/>"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "m.v.txt"));
  EXPECT_FALSE(fs::exists(dir / "m.txt"));

  ASSERT_EQ(test::plumage_cli("-q export " + scene + " -o " + (dir / "b.py").string()).rc, 0);
  const std::string py = read(dir / "b.py");
  EXPECT_EQ(count(py, "    (\"v\", ("), 1u);
  EXPECT_NE(py.find("    (0, ((-1, 0, 0, -4), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))),"),
            std::string::npos) << py.substr(py.find("PLACEMENTS"), 300);

  ASSERT_EQ(test::plumage_cli("-q export " + scene + " -o " + (dir / "o.obj").string()).rc, 0);
  const Feather vane = read_fcurves(dir / "feathers" / "vane.fcurves");
  const std::string obj = read(dir / "o.obj");
  std::istringstream in(obj);
  std::vector<glm::vec3> v;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("v ", 0) == 0) {
      std::istringstream l(line.substr(2));
      glm::vec3 p;
      l >> p.x >> p.y >> p.z;
      v.push_back(p);
    }
  const std::size_t n = vane.num_control_points();
  ASSERT_EQ(v.size(), 2 * n);
  std::size_t k = 0;
  for (const Curve& c : vane.curves)
    for (const ControlPoint& cp : c.points) {
      EXPECT_NEAR(glm::length(v[k] - (cp.p + glm::vec3(4, 0, 0))), 0.0f, 1e-4f);
      EXPECT_NEAR(glm::length(v[n + k] - (glm::vec3(-cp.p.x, cp.p.y, cp.p.z) + glm::vec3(-4, 0, 0))), 0.0f, 1e-4f);
      ++k;
    }
  EXPECT_NE(obj.find("o p1_v_barb_right_0"), std::string::npos);

  const auto e = test::plumage_cli("-q export " + scene + " -o " + (dir / "x.fcurves").string());
  EXPECT_EQ(e.rc, 2);
  EXPECT_NE(e.output.find("feathers are .fcurves files already"), std::string::npos) << e.output;
  EXPECT_FALSE(fs::exists(dir / "x.fcurves"));
}

// --shading auto: the pair seen whole at 40x24 covers many barbule periods per
// pixel, so both placements are shaded in farfield mode; --stats says so.
TEST(SceneCli, AutoShadingCountsThePlacementsPerLevel) {
  const fs::path dir = scene_dir();
  const auto r = test::plumage_cli("--stats render " + (dir / "pair.fscene").string() + " -o " +
                                   (dir / "auto.exr").string() + " --spp 1 --resolution 40x24 --shading auto");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("Placements shaded farfield"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Placements shaded substructure"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "auto.exr"));
  EXPECT_EQ(test::plumage_cli("-q render " + (dir / "pair.fscene").string() + " -o " + (dir / "s.exr").string() +
                              " --shading auto --aov structure").rc, 2);
}

// `feather NAME layout "FILE" feather ID seed N` is the feather `plumage generate
// --layout FILE --feather ID --seed N` builds (the same barbs), coloured by the
// mean of its albedo texture; an id the layout does not hold fails at the scene's
// line.
TEST(SceneCli, ALayoutFeatherIsTheFeatherGenerateBuilds) {
  const fs::path dir = scene_dir();
  fs::create_directories(dir / "sheet");
  const Layout layout = test::drawn_layout(3);
  write_layout(dir / "sheet" / "layout.json", layout);
  Image albedo(20, 60, 4);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 20; ++x) {
      float* p = albedo.at(x, y);
      p[0] = 0.6f, p[1] = 0.3f, p[2] = 0.1f, p[3] = 1.0f;
    }
  write_image(dir / "sheet" / "layout.feather3.albedo.png", albedo);
  std::ofstream(dir / "sheet.fscene") << "fscene 1\nfeather s layout \"sheet/layout.json\" feather 3 seed 4\nplace s\nend\n";

  const auto g = test::plumage_cli("-q generate --layout " + (dir / "sheet" / "layout.json").string() +
                                   " --feather 3 --seed 4 -o " + (dir / "g.fcurves").string());
  ASSERT_EQ(g.rc, 0) << g.output;
  const Feather built = read_fcurves(dir / "g.fcurves");
  const auto info = test::plumage_cli("info " + (dir / "sheet.fscene").string() + " --json");
  ASSERT_EQ(info.rc, 0) << info.output;
  const auto j = nlohmann::json::parse(info.output);
  EXPECT_EQ(j["barbs"].get<std::size_t>(), built.count(CurveKind::Barb));
  EXPECT_GT(built.count(CurveKind::Barb), 20u);
  const auto r = test::plumage_cli("-q render " + (dir / "sheet.fscene").string() + " -o " + (dir / "s.exr").string() +
                                   " --spp 1 --resolution 24x40");
  EXPECT_EQ(r.rc, 0) << r.output;

  std::ofstream(dir / "missing.fscene") << "fscene 1\nfeather s layout \"sheet/layout.json\" feather 9 seed 4\nplace s\nend\n";
  const auto m = test::plumage_cli("-q info " + (dir / "missing.fscene").string());
  EXPECT_EQ(m.rc, 1);
  EXPECT_NE(m.output.find("missing.fscene:2:"), std::string::npos) << m.output;
}
