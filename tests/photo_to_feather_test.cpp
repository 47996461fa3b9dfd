// `plumage photo-to-feather` end to end on a feather drawn in the test and on a
// real photo when ../shared has it: every artifact, the summary's content, the
// per-stage report, and stages that fail leave none of their files behind.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/image.h"
#include "plumage/pipeline/photo_view.h"
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
      plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --mm-per-px 0.2 --spp 1 --size 90");
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

  // Three panels of the feather's crop, 90 pixels along its longer side, measured.
  const nlohmann::json& fid = s.at("fidelity");
  const int panel_w = fid.at("panel").at("width"), panel_h = fid.at("panel").at("height");
  EXPECT_EQ(std::max(panel_w, panel_h), 90);
  EXPECT_EQ(s.at("render").at("panel_width"), panel_w);
  const Image cmp = read_image(dir_ / "out" / "comparison.png");
  EXPECT_GE(cmp.width, 3 * panel_w);  // label strips may widen a narrow panel, never narrow it
  EXPECT_GT(cmp.height, panel_h);
  for (const char* panel : {"hair", "substructure"})
    for (const char* part : {"feather", "left", "right"}) {
      const double iou = fid.at(panel).at(part).at("silhouette_iou");
      EXPECT_GT(iou, 0.0) << panel << " " << part;
      EXPECT_LE(iou, 1.0) << panel << " " << part;
      EXPECT_GE(fid.at(panel).at(part).at("mean_colour_de2000").get<double>(), 0.0);
    }
  EXPECT_GT(fid.at("hair").at("feather").at("photo_pixels").get<int>(), 100);
  // Each panel's colour calibration (--calibrate 3 by default): at most 3 probes,
  // the first at gain 1, every gain in [1/8, 8].
  for (const char* panel : {"hair", "substructure"}) {
    const nlohmann::json& cal = fid.at(panel).at("calibration");
    const auto& probes = cal.at("probes");
    ASSERT_GE(probes.size(), 1u) << panel;
    EXPECT_LE(probes.size(), 3u) << panel;
    EXPECT_EQ(probes.at(0).at("gain"), nlohmann::json({1.0, 1.0, 1.0})) << panel;
    for (const auto& g : cal.at("gain")) {
      EXPECT_GE(g.get<double>(), 0.125) << panel;
      EXPECT_LE(g.get<double>(), 8.0) << panel;
    }
  }
}

TEST_F(PhotoToFeather, PanelsLargerThanThePhotoAreTracedOnThePhotosGrid) {
  // The synthetic feather spans about 300 photo pixels; panels of 900 pixels are
  // traced on the photo's grid with the panels' samples gathered there.
  const std::string photo = synthetic_photo();
  const CliResult r =
      plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --mm-per-px 0.2 --spp 1 --size 900 --calibrate 0");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("traced at the photo's "), std::string::npos) << r.output;
  const nlohmann::json s = nlohmann::json::parse(read_file(dir_ / "out" / "summary.json"));
  // No calibration asked: no probe, gain 1.
  for (const char* panel : {"hair", "substructure"}) {
    EXPECT_TRUE(s.at("fidelity").at(panel).at("calibration").at("probes").empty()) << panel;
    EXPECT_EQ(s.at("fidelity").at(panel).at("calibration").at("gain"), nlohmann::json({1.0, 1.0, 1.0})) << panel;
  }
  const nlohmann::json& render = s.at("render");
  const int pw = render.at("panel_width"), ph = render.at("panel_height");
  const int tw = render.at("traced_width"), th = render.at("traced_height");
  const double px = s.at("fidelity").at("panel").at("photo_px_per_panel_px");
  ASSERT_LT(px, 0.5);
  // The photo's own pixels over the crop (whole pixels, so up to two more), and the
  // samples a traced pixel needs: spp x (panel / traced pixels), to a power of two,
  // at most kGridSppFactor x spp.
  EXPECT_NEAR(tw, pw * px, 2.0);
  EXPECT_NEAR(th, ph * px, 2.0);
  const double ratio = double(pw) * ph / (double(tw) * th);
  const int spp = render.at("traced_spp");
  EXPECT_EQ(spp & (spp - 1), 0) << spp;
  ASSERT_GT(ratio, kGridSppFactor);  // so the factor is what limits it (--spp 1)
  EXPECT_EQ(spp, kGridSppFactor);
  EXPECT_EQ(s.at("fidelity").at("panel").at("render_grid").at("spp"), spp);
  // Shown at panel size, in the photo's pose.
  const Image cmp = read_image(dir_ / "out" / "comparison.png");
  EXPECT_GE(cmp.width, 3 * pw);
  for (const char* panel : {"hair", "substructure"})
    EXPECT_GT(s.at("fidelity").at(panel).at("feather").at("silhouette_iou").get<double>(), 0.6) << panel;
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
                                  " --mm-per-px 0.2 --spp 1 --size 50");
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
                                   " --mm-per-px 0.2 --spp 1 --size 50 --feather 2");
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

TEST_F(PhotoToFeather, ABadRigFailsBeforeAnyStage) {
  // The rig is read before OUTDIR is touched: no stage runs, an existing folder stays as it was.
  const std::string photo = synthetic_photo();
  fs::create_directories(dir_ / "out");
  write_file_atomic(dir_ / "out" / "mine.txt", "x");
  const CliResult r = plumage_cli("photo-to-feather " + photo + " -o " + path("out") +
                                  " --spp 1 --size 32 --rig " + path("no-such-rig.json"));
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("no-such-rig.json"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("stage"), std::string::npos) << r.output;
  EXPECT_EQ(files_in(dir_ / "out"), std::set<std::string>{"mine.txt"});
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
  // Every option is checked before OUTDIR is made: a missing rig, LEDs it does not have.
  const CliResult rig = plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --rig " + path("none.json"));
  EXPECT_NE(rig.rc, 0);
  EXPECT_NE(rig.output.find("none.json"), std::string::npos) << rig.output;
  const CliResult leds = plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --lights 99");
  EXPECT_NE(leds.rc, 0);
  EXPECT_EQ(plumage_cli("photo-to-feather " + photo + " -o " + path("out") + " --size 8").rc, 2);
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(PhotoToFeather, PinkContourFeather) {
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "pink-contour-feather.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  const CliResult r = plumage_cli("photo-to-feather " + photo.string() + " -o " + path("pink") +
                                  " --spp 1 --size 120 --fidelity-image");
  ASSERT_EQ(r.rc, 0) << r.output;
  std::set<std::string> with_fidelity = kArtifacts;
  with_fidelity.insert("fidelity.png");
  EXPECT_EQ(files_in(dir_ / "pink"), with_fidelity);
  const nlohmann::json s = nlohmann::json::parse(read_file(dir_ / "pink" / "summary.json"));
  EXPECT_EQ(s.at("feathers_found"), 1);
  EXPECT_GT(s.at("counts").at("barbs_left").get<int>(), 20);
  EXPECT_GT(s.at("counts").at("barbs_right").get<int>(), 20);
  // The panels are the feather's crop (bounding box and margin), not the whole 1920x623 photo.
  const nlohmann::json& panel = s.at("fidelity").at("panel");
  EXPECT_EQ(panel.at("width"), 120);
  EXPECT_LT(panel.at("photo_px_per_panel_px").get<double>() * 120, 1920.0);
  // The photo holds more pixels than the panel: traced on the panel's grid as asked.
  EXPECT_EQ(s.at("render").at("traced_width"), 120);
  EXPECT_EQ(s.at("render").at("traced_spp"), 1);
  const Image cmp = read_image(dir_ / "pink" / "comparison.png");
  EXPECT_GE(cmp.width, 3 * 120);
  const Image fid = read_image(dir_ / "pink" / "fidelity.png");
  EXPECT_GE(fid.width, 2 * 120);
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

namespace {
// Every regular file under `dir` (recursively) and its bytes; folders by name.
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    files[rel] = e.is_regular_file() ? read_file(e.path()) : std::string("<folder>");
  }
  return files;
}
}  // namespace

// OUTDIR is all-or-nothing (docs/robustness.md): a run that fails after its
// analyze and generate stages have written leaves a previous run's results as they
// were, byte for byte, with no hidden folder left; a run that succeeds leaves
// exactly its own artifacts (a previous run's fidelity.png goes).
TEST_F(PhotoToFeather, AFailedRunLeavesAPreviousRunsResultsAsTheyWere) {
  const std::string photo = synthetic_photo();
  const std::string out = path("out");
  const std::string run = "-q photo-to-feather " + photo + " -o " + out + " --mm-per-px 0.2 --spp 1 --size 48";
  ASSERT_EQ(plumage_cli(run + " --seed 1 --fidelity-image").rc, 0);
  // The next run fails at its compare stage: fidelity.png cannot be replaced.
  fs::remove(dir_ / "out" / "fidelity.png");
  fs::create_directory(dir_ / "out" / "fidelity.png");
  write_file_atomic(dir_ / "out" / "mine.txt", "the user's own file");
  const auto before = contents(dir_ / "out");
  const CliResult r = plumage_cli(run + " --seed 2 --fidelity-image");
  EXPECT_EQ(r.rc, 1) << r.output;
  EXPECT_NE(r.output.find("stage 'compare' failed"), std::string::npos) << r.output;
  const auto after = contents(dir_ / "out");
  for (const auto& [name, bytes] : before)
    EXPECT_TRUE(after.count(name) && after.at(name) == bytes) << name << " was changed or removed by a failed run";
  for (const auto& [name, bytes] : after) EXPECT_TRUE(before.count(name)) << name << " was left by a failed run";

  // A run that succeeds: its own artifacts, the user's file, and nothing stale.
  fs::remove(dir_ / "out" / "fidelity.png");
  write_file_atomic(dir_ / "out" / "fidelity.png", "a previous run's fidelity image");
  write_file_atomic(dir_ / "out" / "layout.feather7.albedo.png", "a previous sheet's seventh feather");
  ASSERT_EQ(plumage_cli(run + " --seed 2").rc, 0);
  std::set<std::string> expected = kArtifacts;
  expected.insert("mine.txt");
  EXPECT_EQ(files_in(dir_ / "out"), expected);
  const auto summary = nlohmann::json::parse(read_file(dir_ / "out" / "summary.json"));
  std::set<std::string> listed(summary["files"].begin(), summary["files"].end());
  EXPECT_EQ(listed, kArtifacts);
}
