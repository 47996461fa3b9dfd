// `plumage photo-to-feather` end to end on a feather drawn in the test and on a
// real photo when ../shared has it: every artifact, the summary's content, the
// per-stage report, and stages that fail leave none of their files behind.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/image.h"
#include "synthetic_feather.h"

#include "cli_run.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

using test::CliResult;
using test::plumage_cli;

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  if (!fs::exists(dir)) return names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

class PhotoToFeather : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("plumage_p2f_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // A small synthetic feather photo (light background).
  std::string synthetic_photo() const {
    synthetic::SyntheticFeather sf;
    sf.width = 450, sf.height = 350, sf.calamus = {125, 320}, sf.length = 280;
    sf.w_left = 30, sf.w_right = 48, sf.spacing = 6;
    write_image(path("photo.png"), sf.draw());
    return path("photo.png");
  }
  fs::path dir_;
};

const std::set<std::string> kArtifacts = {"layout.json",     "overlay.png",        "layout.feather1.albedo.png",
                                          "feather.fcurves", "feather.albedo.png", "preview.png",
                                          "comparison.png",  "summary.json"};

}  // namespace

TEST_F(PhotoToFeather, SyntheticPhotoGivesEveryArtifactAndASummary) {
  const std::string photo = synthetic_photo();
  const CliResult r =
      plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --mm-per-px 0.2 --spp 1 --height 70");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(files_in(dir_ / "out"), kArtifacts);
  // One line per stage, starting with its name.
  for (const std::string stage : {"analyze", "generate", "compare", "summary"}) {
    const std::string text = "\n" + r.output;
    EXPECT_NE(text.find("\n" + stage + " "), std::string::npos) << stage << " line missing:\n" << r.output;
  }

  const nlohmann::json s = nlohmann::json::parse(read_file(dir_ / "out" / "summary.json"));
  EXPECT_EQ(s.at("feathers_found"), 1);
  EXPECT_EQ(s.at("feather"), 1);
  EXPECT_DOUBLE_EQ(s.at("scale").at("mm_per_px").get<double>(), 0.2);
  EXPECT_EQ(s.at("scale").at("source"), "given");
  // 280 px shaft at 0.2 mm/px.
  EXPECT_NEAR(s.at("length_mm").get<double>(), 56.0, 0.05 * 56.0);
  // Synthetic barbs one every 6 px = 1.2 mm along the shaft over 80% of it.
  const double barbs = 0.8 * 56.0 / 1.2;
  EXPECT_NEAR(s.at("counts").at("barbs_left").get<double>(), barbs, 0.25 * barbs);
  EXPECT_NEAR(s.at("counts").at("barbs_right").get<double>(), barbs, 0.25 * barbs);
  // The stages before the summary was written, with their times.
  ASSERT_EQ(s.at("stages").size(), 3u);
  const char* names[] = {"analyze", "generate", "compare"};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(s.at("stages")[i].at("stage"), names[i]);
    EXPECT_GE(s.at("stages")[i].at("seconds").get<double>(), 0.0);
  }
  std::set<std::string> listed;
  for (const auto& f : s.at("files")) listed.insert(f.get<std::string>());
  EXPECT_EQ(listed, kArtifacts);

  // Three panels, each as wide as the photo's aspect at the panel height.
  const Image cmp = read_image(dir_ / "out" / "comparison.png");
  const int panel_w = int(std::lround(70.0 * 450 / 350));
  EXPECT_GE(cmp.width, 3 * panel_w);
  // (label strips may widen a narrow panel, never narrow it)
  EXPECT_GT(cmp.height, 70);
}

TEST_F(PhotoToFeather, SheetOfTwoSaysWhichFeatherItUsesAndHowToPick) {
  // Two synthetic feathers side by side: the small one left, the large one right.
  synthetic::SyntheticFeather a, b;
  a.width = b.width = 300, a.height = b.height = 350;
  a.calamus = b.calamus = {150, 320};
  a.dir_deg = b.dir_deg = -90;
  a.length = 200, a.w_left = a.w_right = 25, a.spacing = 6;
  b.length = 280, b.w_left = 30, b.w_right = 45, b.spacing = 6, b.seed = 7;
  const Image ia = a.draw(), ib = b.draw();
  Image sheet(600, 350, 3);
  for (int y = 0; y < 350; ++y)
    for (int x = 0; x < 600; ++x) sheet.set_rgb(x, y, x < 300 ? ia.rgb(x, y) : ib.rgb(x - 300, y));
  write_image(path("sheet.png"), sheet);

  const CliResult r = plumage_cli("photo-to-feather " + path("sheet.png") + " -o " + path("out") +
                                  " --mm-per-px 0.2 --spp 1 --height 40");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("2 feathers found; using feather 1 (the leftmost); pick another with --feather K "
                          "(K in 1..2"),
            std::string::npos)
      << r.output;
  nlohmann::json s = nlohmann::json::parse(read_file(dir_ / "out" / "summary.json"));
  EXPECT_EQ(s.at("feathers_found"), 2);
  EXPECT_EQ(s.at("feather"), 1);
  EXPECT_NEAR(s.at("length_mm").get<double>(), 0.2 * a.length, 0.05 * 0.2 * a.length);

  // Picking one explicitly: no note, and the right-hand feather is used.
  const CliResult r2 = plumage_cli("photo-to-feather " + path("sheet.png") + " -o " + path("out2") +
                                   " --mm-per-px 0.2 --spp 1 --height 40 --feather 2");
  ASSERT_EQ(r2.rc, 0) << r2.output;
  EXPECT_EQ(r2.output.find("feathers found"), std::string::npos) << r2.output;
  s = nlohmann::json::parse(read_file(dir_ / "out2" / "summary.json"));
  EXPECT_EQ(s.at("feather"), 2);
  EXPECT_NEAR(s.at("length_mm").get<double>(), 0.2 * b.length, 0.05 * 0.2 * b.length);
}

TEST_F(PhotoToFeather, UniformImageFailsInAnalyzeAndLeavesNothing) {
  Image flat(200, 150, 3);
  for (float& v : flat.pixels) v = 0.9f;
  write_image(path("flat.png"), flat);
  const CliResult r = plumage_cli("photo-to-feather " + path("flat.png") + " -o " + path("out") + " --spp 1");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.output.find("stage 'analyze' failed"), std::string::npos) << r.output;
  EXPECT_TRUE(files_in(dir_ / "out").empty());
  // An existing folder is kept, and stays as it was.
  fs::create_directories(dir_ / "keep");
  write_file_atomic(dir_ / "keep" / "mine.txt", "x");
  EXPECT_NE(plumage_cli("photo-to-feather " + path("flat.png") + " -o " + path("keep")).rc, 0);
  EXPECT_EQ(files_in(dir_ / "keep"), std::set<std::string>{"mine.txt"});
}

TEST_F(PhotoToFeather, FailingCompareKeepsEarlierStagesOnly) {
  const std::string photo = synthetic_photo();
  const CliResult r = plumage_cli("photo-to-feather " + photo + " -o " + path("out") +
                                  " --spp 1 --height 32 --rig " + path("no-such-rig.json"));
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.output.find("stage 'compare' failed"), std::string::npos) << r.output;
  EXPECT_EQ(files_in(dir_ / "out"), (std::set<std::string>{"layout.json", "overlay.png", "layout.feather1.albedo.png",
                                                           "feather.fcurves", "feather.albedo.png", "preview.png"}));
}

TEST_F(PhotoToFeather, BadArgumentsAreRefused) {
  EXPECT_NE(plumage_cli("photo-to-feather " + path("none.jpg") + " -o " + path("out")).rc, 0);
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  write_file_atomic(dir_ / "file", "x");
  const std::string photo = synthetic_photo();
  const CliResult r = plumage_cli("photo-to-feather " + photo + " -o " + path("file"));
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.output.find("not a folder"), std::string::npos) << r.output;
  EXPECT_NE(plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --spp 0").rc, 0);
}

TEST_F(PhotoToFeather, PinkContourFeather) {
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "pink-contour-feather.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  const CliResult r = plumage_cli("photo-to-feather " + photo.string() + " -o " + path("pink") +
                                  " --spp 1 --height 40");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(files_in(dir_ / "pink"), kArtifacts);
  const nlohmann::json s = nlohmann::json::parse(read_file(dir_ / "pink" / "summary.json"));
  EXPECT_EQ(s.at("feathers_found"), 1);
  EXPECT_GT(s.at("counts").at("barbs_left").get<int>(), 20);
  EXPECT_GT(s.at("counts").at("barbs_right").get<int>(), 20);
  // The photo is 1920x623: the panels keep that aspect.
  const Image cmp = read_image(dir_ / "pink" / "comparison.png");
  EXPECT_GE(cmp.width, 3 * int(40 * 1920 / 623));
}

TEST_F(PhotoToFeather, GenerateFromTheLayoutItWrote) {
  const std::string photo = synthetic_photo();
  ASSERT_EQ(plumage_cli("-q analyze " + photo + " -o " + path("layout.json") + " --mm-per-px 0.2").rc, 0);
  fs::create_directories(dir_ / "curves");
  const CliResult r = plumage_cli("generate --layout " + path("layout.json") + " --feather 1 -o " +
                                  path("curves/f.fcurves") + " --preview " + path("curves/f.png"));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(files_in(dir_ / "curves"), (std::set<std::string>{"f.fcurves", "f.albedo.png", "f.png"}));
  EXPECT_NE(read_file(dir_ / "curves" / "f.fcurves").find("\"f.albedo.png\""), std::string::npos);
  const CliResult bad = plumage_cli("generate --layout " + path("layout.json") + " --feather 2 -o " + path("g.fcurves"));
  EXPECT_EQ(bad.rc, 1);
  EXPECT_NE(bad.output.find("no such feather; the layout has 1"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "g.fcurves"));
}
