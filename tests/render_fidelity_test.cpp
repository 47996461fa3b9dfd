// Photo fidelity of photo-to-feather's renders on the pink feather (when ../shared
// has the photo): the renders are exposed like the photo (its white card renders
// white, not grey) and the hair panel's feather keeps the photo's pink
// (chromaticity), instead of the grey haze of Chiang's dense-hair albedo mapping.
// Numbers before/after: docs/perf/render.md, "Photo fidelity".
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_run.h"
#include "panel_fidelity.h"
#include "plumage/common/image.h"

using namespace plumage;
namespace fs = std::filesystem;

TEST(RenderFidelity, PinkFeatherRendersPinkOnAWhiteCard) {
  const fs::path photo = fs::path(PLUMAGE_SOURCE_DIR) / ".." / "shared" / "photos" / "pink-contour-feather.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  const fs::path out = fs::temp_directory_path() / ("plumage_render_fidelity_test_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const auto r = test::plumage_cli("-q photo-to-feather " + photo.string() + " -o " + out.string() +
                                   " --size 336 --spp 8 --threads 2");
  ASSERT_EQ(r.rc, 0) << r.output;
  const std::vector<Image> panels = test::split_panels(read_image(out / "comparison.png"));
  ASSERT_EQ(panels.size(), 3u) << "photo | hair | substructure";
  ASSERT_EQ(panels[1].width, panels[0].width);
  const test::Fidelity hair = test::measure_fidelity(panels[0], panels[1]);
  const test::Fidelity sub = test::measure_fidelity(panels[0], panels[2]);
  ASSERT_GT(hair.feather_pixels, 500);
  ASSERT_GT(hair.card_pixels, 500);
  // The card: the photo's paper is white; the renders develop theirs to its level
  // (before: 0.67 against 1.0).
  const float card = test::luminance(hair.photo.card);
  EXPECT_NEAR(test::luminance(hair.render.card), card, 0.06f * card);
  EXPECT_NEAR(test::luminance(sub.render.card), card, 0.06f * card);
  // The feather's colour: rg chromaticity within 0.09 of the photo's (before: 0.167, grey).
  const float dist = glm::length(test::chromaticity(hair.render.feather) - test::chromaticity(hair.photo.feather));
  EXPECT_LT(dist, 0.09f) << "render rg " << test::chromaticity(hair.render.feather).x << ", "
                         << test::chromaticity(hair.render.feather).y;
  // Redder than green, as the photo is, by a clear margin.
  EXPECT_GT(hair.render.feather.x, 1.2f * hair.render.feather.y);
  fs::remove_all(out);
}
