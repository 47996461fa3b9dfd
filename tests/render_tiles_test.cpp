// Split renders (render.h: RenderSettings::tile_index/tile_count, merge_tiles):
// 1, 2, 3 and 8 parts merge to the single render's pixels bit for bit, with uniform
// and variance allocation and adaptive sampling; the bands cover every row once
// for any height and count; merge refuses parts that do not fit; and the CLI's
// `render --tile` and `merge` do the same for a scene of placed feathers.
#include <unistd.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/renderer/render.h"
#include "cli_run.h"
#include "render_test_feather.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

bool same_pixels(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

}  // namespace

TEST(RenderTiles, PartsMergeToTheSingleRenderBitForBit) {
  const test::LitTestFeather lit;
  const PathIntegrator& integrator = lit.integrator;
  const Camera camera(CameraSpec{}, 37, 29, lit.scene.feather_bounds());  // sizes no band count divides
  for (const char* how : {"uniform", "variance", "adaptive"}) {
    RenderSettings rs;
    rs.spp = 16;
    rs.seed = 3;
    rs.progress = false;
    rs.allocation = std::string(how) == "uniform" ? SampleAllocation::Uniform : SampleAllocation::Variance;
    rs.adaptive = std::string(how) == "adaptive";
    rs.min_spp = 4;
    rs.check_every = 4;
    const Image whole = render(camera, integrator, rs).developed(0);
    for (int n : {1, 2, 3, 8}) {
      std::vector<Image> parts;
      for (int k = 0; k < n; ++k) {
        RenderSettings part = rs;
        part.tile_index = k;
        part.tile_count = n;
        part.threads = 1 + k % 2;  // the thread count changes nothing either
        parts.push_back(render(camera, integrator, part).developed(0));
      }
      EXPECT_TRUE(same_pixels(merge_tiles(parts), whole)) << how << ", " << n << " parts";
    }
  }
}

TEST(RenderTiles, BandsCoverEveryRowOnceForAnyHeightAndCount) {
  for (int h = 1; h <= 300; h += 7)
    for (int n = 1; n <= 64; ++n) {
      int next = 0;
      for (int k = 0; k < n; ++k) {
        const TileRows r = tile_rows(h, k, n);
        ASSERT_EQ(r.first, next) << h << " " << n << " " << k;
        ASSERT_LE(r.first, r.last);
        ASSERT_LE(r.last - r.first, (h + n - 1) / n);  // as even as integers allow
        next = r.last;
      }
      ASSERT_EQ(next, h);
    }
  const TileRows huge = tile_rows(16384, 4095, 4096);
  EXPECT_EQ(huge.last, 16384);
}

TEST(RenderTiles, MergeRefusesPartsThatDoNotFit) {
  EXPECT_THROW(merge_tiles({}), Error);
  Image a(8, 6, 3, 0.0f), b(8, 6, 3, 0.0f), c(8, 5, 3, 0.0f);
  a.at(0, 0)[0] = 1;  // row 1: part 1 of 2's band
  b.at(0, 5)[1] = 1;  // row 6: part 2 of 2's band
  EXPECT_NO_THROW(merge_tiles({a, b}));
  EXPECT_THROW(merge_tiles({b, a}), Error);  // out of order
  EXPECT_THROW(merge_tiles({a, c}), Error);  // another size
  EXPECT_THROW(merge_tiles({a, b, b}), Error);  // another N
  try {
    merge_tiles({b, a});
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("part 1 of 2 has a pixel at row 6, outside its rows 1-3"), std::string::npos) << e.what();
  }
}

TEST(RenderTiles, CliPartsOfASceneMergeToTheSingleRun) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_tiles_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_fcurves(dir / "f.fcurves", test::make_test_feather(20.0f, 0.8f, 0.05f));
  std::ofstream(dir / "s.fscene") << "fscene 1\nfeather f fcurves \"f.fcurves\"\nplace f\nplace f mirror x rotate 0 0 15 translate -6 2 1\nend\n";
  const std::string common = (dir / "s.fscene").string() + " --spp 8 --resolution 40x30 --lights 2,9,14 ";
  ASSERT_EQ(test::plumage_cli("-q render " + common + "-o " + (dir / "whole.exr").string()).rc, 0);
  std::string parts;
  for (int k = 1; k <= 3; ++k) {
    const fs::path p = dir / ("part" + std::to_string(k) + ".exr");
    const auto r = test::plumage_cli("-q render " + common + "--tile " + std::to_string(k) + "/3 -o " + p.string());
    ASSERT_EQ(r.rc, 0) << r.output;
    parts += p.string() + " ";
  }
  ASSERT_EQ(test::plumage_cli("-q merge " + parts + "-o " + (dir / "merged.exr").string()).rc, 0);
  EXPECT_TRUE(same_pixels(read_image(dir / "merged.exr"), read_image(dir / "whole.exr")));
  // Usage errors: a part that is not an .exr, a tile that is not I/N, merge of a PNG.
  EXPECT_EQ(test::plumage_cli("-q render " + common + "--tile 1/3 -o " + (dir / "p.png").string()).rc, 2);
  for (const char* bad : {"0/3", "4/3", "3", "a/b", "1/0", "1/99999"})
    EXPECT_EQ(test::plumage_cli("-q render " + common + "--tile " + bad + " -o " + (dir / "p.exr").string()).rc, 2) << bad;
  EXPECT_EQ(test::plumage_cli("-q merge " + (dir / "x.png").string() + " -o " + (dir / "m.exr").string()).rc, 2);
  // Out of order: exit 1, nothing written.
  const auto swapped = test::plumage_cli("-q merge " + (dir / "part2.exr").string() + " " + (dir / "part1.exr").string() +
                                         " " + (dir / "part3.exr").string() + " -o " + (dir / "swapped.exr").string());
  EXPECT_EQ(swapped.rc, 1);
  EXPECT_FALSE(fs::exists(dir / "swapped.exr"));
  fs::remove_all(dir);
}
