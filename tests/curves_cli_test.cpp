// `plumage info` and `plumage export`, run as a user would: the built binary
// (PLUMAGE_CLI), its exit status (0 ok, 1 bad file, 2 usage error), its output,
// and the promise that a failed export leaves nothing half-written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "feather_samples.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/exporters.h"
#include "plumage/common/image.h"
#include "plumage/renderer/export_scene.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

class CurvesCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("plumage_curves_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    feather_ = samples::sample_feather(6, 5);
    feather_.albedo.texture = "albedo.png";
    feather_.albedo.rect_min = {-20, 0};
    feather_.albedo.rect_max = {20, 70};
    write_fcurves(dir_ / "f.fcurves", feather_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  using Result = test::CliStreams;
  static Result run(const std::string& args) { return test::plumage_cli_streams(args); }
  std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  std::size_t files_in_dir() const {
    std::size_t n = 0;
    for ([[maybe_unused]] auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }

  fs::path dir_;
  Feather feather_;
};

// Each run of the binary costs a process start (a few hundred ms with every
// library loaded), so these tests run it a dozen times in all; the formats
// themselves are checked in-process by exporters_test.cpp.
TEST_F(CurvesCli, ExportWritesTheChosenFormat) {
  // The scene formats take the fibres' absorption from the albedo texture, as a render does.
  write_image(dir_ / "albedo.png", Image(4, 4, 3, 0.3f));
  const struct {
    const char* flag;
    const char* out;
    ExportFormat format;
  } cases[] = {{"--format pbrt-v3", "b.pbrt", ExportFormat::PbrtV3},
               {"--format fcurves", "e.fcurves", ExportFormat::Fcurves},
               {"", "f.obj", ExportFormat::Obj}};  // format from the extension
  for (const auto& c : cases) {
    SCOPED_TRACE(c.out);
    const Result r = run("export " + path("f.fcurves") + " " + c.flag + " -o " + path(c.out));
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.out.find("1 shaft, 6 barbs"), std::string::npos) << r.out;
    // The CLI's defaults: a 512x512 view at 64 spp, every LED, the white card.
    ExportScene scene;
    if (c.format == ExportFormat::PbrtV3) {
      ViewSpec view;
      view.width = view.height = 512;
      view.spp = 64;
      view.base_dir = dir_;
      SceneOptions so;
      so.backdrop = {true, glm::vec3(0.8f)};
      scene = export_scene(feather_, read_dome_rig(std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json"), view, so);
      scene.image_filename = fs::path(c.out).stem().string() + ".exr";
    }
    EXPECT_EQ(read_file(dir_ / c.out), export_text(feather_, c.format, scene));
    if (c.format == ExportFormat::PbrtV3) {
      EXPECT_NE(read_file(dir_ / c.out).find("the albedo texture is not exported"), std::string::npos);
    }
  }
  EXPECT_EQ(read_fcurves(dir_ / "e.fcurves"), feather_);
}

TEST_F(CurvesCli, ExportFailuresExitOneAndLeaveNoPartialOutput) {
  write_file_atomic(dir_ / "old.pbrt", "previous contents\n");
  write_file_atomic(dir_ / "bad.fcurves", "fcurves 1\nunits cm\n");
  const std::size_t before = files_in_dir();

  Result r = run("export " + path("bad.fcurves") + " --format pbrt -o " + path("old.pbrt"));
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find("plumage: error: " + (dir_ / "bad.fcurves").string() + ":2:7: units"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(read_file(dir_ / "old.pbrt"), "previous contents\n");

  r = run("export " + path("f.fcurves") + " --format obj -o " + path("no_such_dir/x.obj"));
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;

  // Nothing new in the directory: no output, no temporary file.
  EXPECT_EQ(files_in_dir(), before);
}

// The view options reach the exported scene: the chosen LEDs, a constant
// environment, the depth, the width override and the mode; a bad LED number is a
// one-line error that leaves no output.
TEST_F(CurvesCli, ExportTakesTheViewOptions) {
  write_image(dir_ / "albedo.png", Image(4, 4, 3, 0.3f));
  Result r = run("export " + path("f.fcurves") + " --format pbrt-v3 -o " + path("v.pbrt") +
                 " --lights 2,4-5 --env 0.5 --max-depth 4 --ribbon-width 0.2 --shading substructure --alpha 3");
  ASSERT_EQ(r.rc, 0) << r.err;
  const std::string text = read_file(dir_ / "v.pbrt");
  std::size_t leds = 0;
  for (std::size_t at = text.find("Shape \"sphere\""); at != std::string::npos; at = text.find("Shape \"sphere\"", at + 1)) ++leds;
  EXPECT_EQ(leds, 3u);
  EXPECT_NE(text.find("LightSource \"infinite\" \"rgb L\" [ 0.5 0.5 0.5 ]"), std::string::npos);
  EXPECT_NE(text.find("\"integer maxdepth\" [ 4 ]"), std::string::npos);
  EXPECT_NE(text.find("\"float alpha\" [ -3 ]"), std::string::npos);
  EXPECT_NE(text.find("\"string type\" [ \"flat\" ]"), std::string::npos);
  EXPECT_NE(text.find("\"float width0\" [ 0.2 ]"), std::string::npos);
  EXPECT_NE(text.find("substructure mode (rami and barbules inside each barb) has no counterpart"), std::string::npos);

  r = run("export " + path("f.fcurves") + " --format mitsuba -o " + path("m.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("m.xml (Mitsuba 3 scene)"), std::string::npos) << r.out;
  EXPECT_NE(read_file(dir_ / "m.xml").find("value=\"m.txt\""), std::string::npos);

  const std::size_t before = files_in_dir();
  r = run("export " + path("f.fcurves") + " --format pbrt -o " + path("bad.pbrt") + " --lights 26");
  EXPECT_EQ(r.rc, 2);  // an LED the rig lacks: a usage error
  EXPECT_EQ(r.err.rfind("plumage: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(files_in_dir(), before);
}

TEST_F(CurvesCli, ExportUsageErrorsExitTwo) {
  EXPECT_EQ(run("export " + path("f.fcurves") + " --format usd -o " + path("x.usd")).rc, 2);
  const Result r = run("export " + path("f.fcurves") + " -o " + path("x.usd"));
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.err.find("--format"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "x.usd"));
  const Result help = run("export --help");
  EXPECT_EQ(help.rc, 0);
  EXPECT_NE(help.out.find("pbrt-v3"), std::string::npos);
  EXPECT_NE(help.out.find("Exit status"), std::string::npos);
}

TEST_F(CurvesCli, InfoSummarisesTheFeather) {
  const Result r = run("info " + path("f.fcurves"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("1 shaft, 6 barbs (3 left, 3 right)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(std::to_string(feather_.num_control_points())), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("test:sample, seed 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("texture \"albedo.png\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("theta_b 42.5 deg"), std::string::npos) << r.out;

  const Result j = run("info --json " + path("f.fcurves"));
  ASSERT_EQ(j.rc, 0) << j.err;
  const auto json = nlohmann::json::parse(j.out);
  EXPECT_EQ(json["curves"]["barbs"], 6);
  EXPECT_EQ(json["control_points"], feather_.num_control_points());
  EXPECT_EQ(json["substructure"]["right"]["elevation"], 42.5);
  EXPECT_EQ(json["albedo"]["color"][0], 0.42);
  EXPECT_EQ(json["medulla"]["ratio"], 0.0);
  EXPECT_NE(r.out.find("medulla        none (clear fibres)"), std::string::npos) << r.out;
  // A feather with a medulla, a shaft colour and a texture scale says them.
  Feather pale = feather_;
  pale.medulla = {0.7f, glm::vec3(4.0f), glm::vec3(0.0f, 0.5f, 0.0f)};
  pale.albedo.shaft = {glm::vec3(0.9f, 0.2f, 0.1f)};
  pale.albedo.scale = 2.0f;
  write_fcurves(dir_ / "pale.fcurves", pale);
  const Result pr = run("info " + path("pale.fcurves"));
  ASSERT_EQ(pr.rc, 0) << pr.err;
  EXPECT_NE(pr.out.find("ratio 0.7, sigma_s 4 4 4, sigma_a 0 0.5 0 per radius"), std::string::npos) << pr.out;
  EXPECT_NE(pr.out.find(", times 2; shaft 0.9 0.2 0.1"), std::string::npos) << pr.out;
  const auto pj = nlohmann::json::parse(run("info --json " + path("pale.fcurves")).out);
  EXPECT_EQ(pj["medulla"]["ratio"], 0.7);
  EXPECT_EQ(pj["medulla"]["sigma_a"][1], 0.5);
  EXPECT_EQ(pj["albedo"]["shaft"][0][0], 0.9);
  EXPECT_EQ(pj["albedo"]["scale"], 2.0);
  // The shaft of the sample runs along +Y: its length is at least the straight
  // distance between the curve's end points and less than its control polygon.
  const auto& s = feather_.curves[0].points;
  const double chord = glm::distance(glm::dvec3(s[0].p + 4.0f * s[1].p + s[2].p) / 6.0,
                                     glm::dvec3(s[9].p + 4.0f * s[10].p + s[11].p) / 6.0);
  double polygon = 0;
  for (std::size_t i = 1; i < s.size(); ++i)
    polygon += glm::distance(glm::dvec3(s[i - 1].p), glm::dvec3(s[i].p));
  EXPECT_GE(json["shaft_length"].get<double>(), chord * (1 - 1e-9));
  EXPECT_LE(json["shaft_length"].get<double>(), polygon);
  EXPECT_LE(json["barb_length"]["min"].get<double>(), json["barb_length"]["mean"].get<double>());
  EXPECT_LE(json["barb_length"]["mean"].get<double>(), json["barb_length"]["max"].get<double>());
  // Centreline bounds lie inside the control points' bounds (convex hull).
  for (int a = 0; a < 3; ++a) {
    float lo = std::numeric_limits<float>::max(), hi = -lo;
    for (const Curve& c : feather_.curves)
      for (const ControlPoint& p : c.points) lo = std::min(lo, p.p[a]), hi = std::max(hi, p.p[a]);
    EXPECT_GE(json["bounds"]["min"][a].get<double>(), lo - 1e-6);
    EXPECT_LE(json["bounds"]["max"][a].get<double>(), hi + 1e-6);
  }
}

TEST_F(CurvesCli, InfoReportsBadFilesAndUsage) {
  write_file_atomic(dir_ / "bad.fcurves", "fcurves 9\n");
  Result r = run("info " + path("bad.fcurves"));
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find(":1:9: format version 9 is newer"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
  r = run("info " + path("missing.fcurves"));
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find("missing.fcurves"), std::string::npos) << r.err;
  EXPECT_EQ(run("info " + path("f.fcurves") + " --bogus").rc, 2);
}

}  // namespace
