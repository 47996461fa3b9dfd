// The overlay's label placement (analysis/src/label_placement.h): on a
// dense sheet, labels must not cover each other or the scale bar, and must stay
// inside the image.
#include <gtest/gtest.h>

#include <climits>

#include "analysis/src/label_placement.h"

namespace plumage::analysis {
namespace {

bool inside(const LabelBox& b, int w, int h) {
  return b.x >= 0 && b.y >= 0 && b.x + b.width <= w && b.y + b.height <= h;
}

TEST(LabelPlacement, OverlapAreaOfTouchingNestedAndCrossingBoxes) {
  EXPECT_EQ(overlap_area({0, 0, 10, 10}, {10, 0, 10, 10}), 0);  // touch along an edge
  EXPECT_EQ(overlap_area({0, 0, 10, 10}, {2, 3, 4, 5}), 20);    // nested
  EXPECT_EQ(overlap_area({0, 0, 10, 10}, {5, 5, 10, 10}), 25);  // crossing corners
  EXPECT_EQ(overlap_area({0, 0, 10, 10}, {20, 20, 5, 5}), 0);
  EXPECT_EQ(overlap_area({0, 0, 0, 10}, {0, 0, 10, 10}), 0);    // empty box
}

// Forty labels that all want the same spot first, then a ring of places around
// it: none may cover another while there is room.
TEST(LabelPlacement, CrowdedLabelsTakeFreePlacesInsideTheImage) {
  const int W = 800, H = 600;
  LabelPlacer placer(W, H);
  const LabelBox bar{600, 560, 200, 40};
  placer.reserve(bar);
  std::vector<std::pair<int, int>> ring{{400, 300}};
  for (int r = 1; r <= 12; ++r)
    for (int k = -r; k <= r; ++k)
      for (auto [dx, dy] : {std::pair{k, -r}, {k, r}, {-r, k}, {r, k}}) ring.push_back({400 + 60 * dx, 300 + 24 * dy});
  std::vector<LabelBox> got;
  for (int i = 0; i < 40; ++i) got.push_back(placer.place(55, 20, ring));
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_TRUE(inside(got[i], W, H)) << i;
    EXPECT_EQ(overlap_area(got[i], bar), 0) << i;
    for (std::size_t j = 0; j < i; ++j) EXPECT_EQ(overlap_area(got[i], got[j]), 0) << i << " " << j;
  }
  EXPECT_EQ(got[0].x, 400);  // the first label keeps its first choice
  EXPECT_EQ(got[0].y, 300);
}

// Candidates outside the image are moved in; a label bigger than the image sits
// at the top-left corner; no candidates at all still gives a box inside.
TEST(LabelPlacement, ExtremeCandidatesAndSizesStayInside) {
  LabelPlacer placer(100, 50);
  for (auto [x, y] : {std::pair{-1000, -1000}, {1000, 1000}, {99, 49}, {INT_MIN / 2, INT_MAX / 2}}) {
    const LabelBox b = placer.place(30, 10, {{x, y}});
    EXPECT_TRUE(inside(b, 100, 50)) << x << " " << y;
  }
  const LabelBox huge = placer.place(500, 500, {{40, 20}});
  EXPECT_EQ(huge.x, 0);
  EXPECT_EQ(huge.y, 0);
  const LabelBox none = placer.place(10, 10, {});
  EXPECT_TRUE(inside(none, 100, 50));
  const LabelBox neg = placer.place(-5, -5, {{10, 10}});
  EXPECT_EQ(neg.width, 0);
  EXPECT_EQ(neg.height, 0);
  LabelPlacer empty(0, 0);
  const LabelBox e = empty.place(10, 10, {{5, 5}});
  EXPECT_EQ(e.x, 0);
  EXPECT_EQ(e.y, 0);
}

// When every candidate is covered, the label takes the one covering least, and
// the same calls give the same boxes.
TEST(LabelPlacement, FullImageTakesTheLeastCoveredCandidateDeterministically) {
  auto run = [] {
    LabelPlacer placer(100, 100);
    placer.reserve({0, 0, 100, 60});  // only the bottom 40 rows are free
    std::vector<LabelBox> out;
    out.push_back(placer.place(100, 40, {{0, 0}, {0, 60}}));   // fits exactly below
    out.push_back(placer.place(50, 50, {{0, 0}, {0, 30}, {50, 50}}));
    return out;
  };
  const auto a = run(), b = run();
  EXPECT_EQ(a[0].y, 60);
  // Each candidate covers 2500 px of the reserved box and the first label
  // together: the earliest of the least is taken.
  EXPECT_EQ(a[1].x, 0);
  EXPECT_EQ(a[1].y, 0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
  }
}

}  // namespace
}  // namespace plumage::analysis
