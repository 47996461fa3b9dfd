// `plumage render` end to end: it writes the image it is asked for, and bad input
// (missing files, absurd flags) gives a one-line error and a non-zero exit without
// leaving a file behind.
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "plumage/common/curve_format.h"
#include "plumage/common/image.h"
#include "cli_run.h"
#include "render_test_feather.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

using CliRun = test::CliStreams;

CliRun plumage_render(const std::string& args) { return test::plumage_cli_streams("-q render " + args); }

fs::path setup_dir() {
  const fs::path dir = fs::temp_directory_path() / ("plumage_render_cli_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_fcurves(dir / "feather.fcurves", test::make_test_feather(20.0f, 1.0f, 0.05f));
  return dir;
}

}  // namespace

TEST(RenderCli, WritesPngAndExr) {
  const fs::path dir = setup_dir();
  const std::string in = (dir / "feather.fcurves").string();
  {
    const fs::path out = dir / "out.exr";
    const CliRun r = plumage_render(in + " -o " + out.string() + " --spp 2 --resolution 24x16 --lights 1,5,12 --threads 2");
    ASSERT_EQ(r.rc, 0) << r.err;
    const Image img = read_image(out);
    EXPECT_EQ(img.width, 24);
    EXPECT_EQ(img.height, 16);
  }
  // An environment, a directional light and an orthographic look-at camera.
  const CliRun r = plumage_render(in + " -o " + (dir / "env.png").string() +
                               " --spp 1 --resolution 8x8 --lights none --env 0.5,0.6,0.7 --directional 0,0,1,2"
                               " --projection orthographic --camera-pos 0,10,50 --look-at 0,10,0 --backdrop black");
  EXPECT_EQ(r.rc, 0) << r.err;
}

TEST(RenderCli, BadInputFailsWithOneLineNamingTheProblem) {
  const fs::path dir = setup_dir();
  const std::string in = (dir / "feather.fcurves").string();
  const std::string out = (dir / "bad.png").string();
  struct Case {
    std::string args, must_mention;
  };
  const Case cases[] = {
      {in + " -o " + out + " --env " + (dir / "missing_env.exr").string(), "missing_env.exr"},
      {(dir / "missing.fcurves").string() + " -o " + out, "missing.fcurves"},
      {in + " -o " + out + " --lights 26", "--lights"},
      {in + " -o " + out + " --resolution 12by8", "--resolution"},
      {in + " -o " + out + " --light-pick nearest", "--light-pick"},
  };
  for (const Case& c : cases) {
    const CliRun r = plumage_render(c.args + " --resolution 8x8 --spp 1");
    EXPECT_NE(r.rc, 0) << c.args;
    EXPECT_NE(r.err.find(c.must_mention), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

// --light-pick reaches the renderer (the images differ) and only changes the
// estimator, not what it estimates (the image means agree).
TEST(RenderCli, LightPickChangesTheNoiseNotTheImage) {
  const fs::path dir = setup_dir();
  const std::string in = (dir / "feather.fcurves").string();
  double mean[3] = {};
  Image img[3];
  const char* picks[3] = {"uniform", "estimate", "all"};
  for (int i = 0; i < 3; ++i) {
    const fs::path out = dir / (std::string(picks[i]) + ".exr");
    const CliRun r = plumage_render(in + " -o " + out.string() + " --spp 64 --resolution 24x16 --threads 2 --light-pick " + picks[i]);
    ASSERT_EQ(r.rc, 0) << r.err;
    img[i] = read_image(out);
    for (float v : img[i].pixels) mean[i] += v;
    mean[i] /= double(img[i].pixels.size());
  }
  EXPECT_NE(img[0].pixels, img[2].pixels);
  for (int i = 1; i < 3; ++i) EXPECT_NEAR(mean[i], mean[0], 0.05 * mean[0]) << picks[i];
}
