// The `generate --preview` top view: paper background, dark shaft, left vane blue
// and right vane orange, tip up.
#include <gtest/gtest.h>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/preview.h"

using namespace plumage;

TEST(Preview, ShowsShaftAndBothVanesInTheirColours) {
  FeatherParams p = default_feather_params();
  p.left.barbs = p.right.barbs = 300;
  const Feather f = build_feather(p, 1);
  const Image img = render_preview(f, {512, true});
  ASSERT_EQ(img.channels, 3);
  EXPECT_EQ(std::max(img.width, img.height), 512);
  EXPECT_GT(img.height, img.width);  // the feather is longer than wide, tip up

  // Corners are background paper.
  for (auto [x, y] : {std::pair{0, 0}, {img.width - 1, 0}, {img.width - 1, img.height - 1}}) {
    const glm::vec3 ratio = img.rgb(x, y) / PreviewPalette::background;  // a faint gradient, nothing else
    EXPECT_GT(glm::min(ratio.x, glm::min(ratio.y, ratio.z)), 0.9f) << x << "," << y;
    EXPECT_LT(glm::max(ratio.x, glm::max(ratio.y, ratio.z)), 1.001f) << x << "," << y;
  }

  // Across the middle of the vane: the darkest pixel is the shaft, blue to its
  // left, orange to its right.
  const int y = img.height / 2;
  int shaft_x = 0;
  for (int x = 0; x < img.width; ++x)
    if (luminance(img.rgb(x, y)) < luminance(img.rgb(shaft_x, y))) shaft_x = x;
  EXPECT_LT(glm::length(img.rgb(shaft_x, y) - PreviewPalette::shaft), 0.05f);
  int blue_left = 0, orange_left = 0, blue_right = 0, orange_right = 0;
  for (int x = 0; x < img.width; ++x) {
    const glm::vec3 c = img.rgb(x, y);
    const bool blue = c.z > c.x + 0.1f, orange = c.x > c.z + 0.1f;
    (x < shaft_x ? blue_left : blue_right) += blue;
    (x < shaft_x ? orange_left : orange_right) += orange;
  }
  EXPECT_GT(blue_left, 20);
  EXPECT_GT(orange_right, 20);
  EXPECT_EQ(orange_left, 0);
  EXPECT_EQ(blue_right, 0);

  // The tip is at the top: the top rows of the drawing hold the shaft's end, the
  // bottom ones the calamus (no barbs below the vane).
  int coloured_bottom = 0;
  for (int yy = int(img.height * 0.85); yy < int(img.height * 0.9); ++yy)
    for (int x = 0; x < img.width; ++x) {
      const glm::vec3 c = img.rgb(x, yy);
      coloured_bottom += std::abs(c.x - c.z) > 0.2f;
    }
  EXPECT_EQ(coloured_bottom, 0);
}

TEST(Preview, RejectsEmptyFeathersAndAbsurdSizes) {
  EXPECT_THROW(render_preview(Feather{}), Error);
  const Feather f = build_feather(default_feather_params(), 1);
  EXPECT_THROW(render_preview(f, {8, true}), Error);
  EXPECT_THROW(render_preview(f, {100000, true}), Error);
  Feather bad = f;
  bad.curves[0].points[2].p.x = NAN;
  EXPECT_THROW(render_preview(bad), Error);
}
