// `plumage generate` end to end: files, determinism, previews, and errors that
// name the problem and exit non-zero without leaving damaged files.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/common/bspline.h"
#include "plumage/layout/layout.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/generator/presets.h"

#include "cli_run.h"
#include "drawn_layout.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

using test::CliResult;
using test::plumage_cli;

class GenerateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("plumage_generate_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

}  // namespace

TEST_F(GenerateCli, SameSeedSameFileAndTheFileIsTheBuiltFeather) {
  const std::string preset = "osprey-wing-covert";
  CliResult r = plumage_cli("generate --preset " + preset + " --seed 5 -o " + path("a.fcurves") + " --preview " +
                      path("a.png") + " --preview-size 300");
  ASSERT_EQ(r.rc, 0) << r.output;
  r = plumage_cli("-q generate --preset " + preset + " --seed 5 -o " + path("b.fcurves"));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(r.output, "");  // --quiet
  r = plumage_cli("generate --preset " + preset + " --seed 6 -o " + path("c.fcurves"));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(read_file(path("a.fcurves")), read_file(path("b.fcurves")));
  EXPECT_NE(read_file(path("a.fcurves")), read_file(path("c.fcurves")));
  EXPECT_EQ(read_fcurves(path("a.fcurves")), build_feather(load_preset(preset), 5, "preset:" + preset));

  const Image img = read_image(path("a.png"));
  EXPECT_EQ(std::max(img.width, img.height), 300);
}

TEST_F(GenerateCli, ParamsFileAndPrintParamsAgree) {
  CliResult r = plumage_cli("generate --preset rock-dove-wing --print-params > " + path("p.json"));
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(read_params(path("p.json")), load_preset("rock-dove-wing"));
  r = plumage_cli("generate --params " + path("p.json") + " --seed 2 -o " + path("p.fcurves"));
  ASSERT_EQ(r.rc, 0) << r.output;
  const Feather f = read_fcurves(path("p.fcurves"));
  EXPECT_EQ(f.provenance.source, "params:" + path("p.json"));
  EXPECT_EQ(f.curves, build_feather(load_preset("rock-dove-wing"), 2).curves);
}

// With --layout, --print-params prints what layout -> params made of the
// feather (smoothed angles, repairs), and the same file builds the same feather.
TEST_F(GenerateCli, PrintParamsFromALayout) {
  const Layout layout = test::drawn_layout(1, 5);
  write_layout(path("layout.json"), layout);
  CliResult r = plumage_cli("generate --layout " + path("layout.json") + " --print-params > " + path("p.json"));
  ASSERT_EQ(r.rc, 0) << read_file(path("p.json"));
  EXPECT_FALSE(fs::exists(path("x.fcurves")));
  const FeatherParams p = read_params(path("p.json"));
  const Layout read = read_layout(path("layout.json"));  // as the file holds it
  EXPECT_EQ(params_to_json(p).dump(1),
            params_to_json(layout_to_params(read.feathers.at(0), path("layout.json")).params).dump(1));
  EXPECT_GT(p.left.angle_deg(0.4), 30.0);  // station 5 (120 degrees) took its neighbours' value
  EXPECT_LT(p.left.angle_deg(0.4), 50.0);
}

TEST_F(GenerateCli, ListsPresets) {
  const CliResult r = plumage_cli("generate --list-presets");
  ASSERT_EQ(r.rc, 0) << r.output;
  for (const char* name : {"osprey-wing-covert", "turkey-vulture-back-covert", "rock-dove-wing"})
    EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
}

TEST_F(GenerateCli, BadInputNamesTheProblemAndLeavesNoFile) {
  // Each run costs a process start, so only the command's own checks go through
  // the CLI; bad params files are covered in feather_params_test.cpp.
  write_file_atomic(path("bad.json"), "{\n  \"shaft\": {\"length\": -3}\n}\n");
  write_file_atomic(path("keep.fcurves"), "old");
  const struct {
    std::string args, expect;
    int rc;  // 2: a usage error, found before any file is read
  } cases[] = {
      {"generate -o " + path("x.fcurves"), "give --preset NAME (--list-presets names them), --params FILE or --layout", 2},
      {"generate --preset rock-dove-wing", "no output file", 2},
      {"generate --layout " + path("layout.json") + " -o " + path("x.fcurves"), path("layout.json"), 1},  // missing file
      {"generate --params " + path("bad.json") + " -o " + path("keep.fcurves"),
       path("bad.json") + ": shaft.length: value -3 is out of range; allowed [1, 2000] mm", 1},
  };
  for (const auto& c : cases) {
    const CliResult r = plumage_cli(c.args);
    EXPECT_EQ(r.rc, c.rc) << c.args;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n-> " << r.output;
  }
  EXPECT_FALSE(fs::exists(path("x.fcurves")));
  EXPECT_EQ(read_file(path("keep.fcurves")), "old");  // a failed run damages nothing
}

TEST(GenerateErrors, PresetsAndOutputsNameTheProblem) {
  try {
    load_preset("emu");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown preset 'emu'; known presets: "), std::string::npos) << e.what();
  }
  try {
    read_params("/nonexistent/missing.json");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, "/nonexistent/missing.json");
  }
  const Feather f = build_feather(load_preset("rock-dove-wing"), 1);
  EXPECT_NO_THROW(validate_feather(f));  // what the .fcurves reader accepts
  try {
    write_fcurves("/nonexistent/dir/x.fcurves", f);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}
