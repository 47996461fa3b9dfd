// Shingled rows: feathers laid over each other like roof tiles, every quill
// visible at the base (a Feather Atlas row of primaries or tail feathers). Each
// quill is one feather: every feather is found from its own calamus, or the row
// is reported; never one analysed feather across two quills (docs/analysis.md,
// "Shingled rows").
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <unistd.h>

#include "plumage/analysis/analyze.h"
#include "plumage/common/error.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/image.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/layout/layout.h"
#include "plumage/common/constants.h"
#include "row_found.h"
#include "synthetic_feather.h"

using namespace plumage;
using plumage::synthetic::SyntheticFeather;
namespace fs = std::filesystem;

namespace {

// A row of n feathers side by side at a random angle, each over the one before,
// their vanes overlapping by a random share, their quills bare below the vanes.
std::vector<SyntheticFeather> shingled_row(int n, unsigned seed) {
  std::mt19937 rng(seed);
  auto U = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const double row_deg = U(0, 360), length = U(280, 360);
  const double overlap = U(0.3, 0.65);
  const double wl = U(30, 45), wr = U(45, 65), step = (1 - overlap) * (wl + wr);
  const glm::dvec2 along_row(std::cos(row_deg * kPi / 180), std::sin(row_deg * kPi / 180));
  const double feather_deg = row_deg - 90;
  const glm::dvec2 up(std::cos(feather_deg * kPi / 180), std::sin(feather_deg * kPi / 180));
  const glm::dvec2 centre(450, 450);
  const glm::dvec2 first = centre - 0.5 * (n - 1) * step * along_row - 0.5 * length * up;
  std::vector<SyntheticFeather> row;
  for (int k = 0; k < n; ++k) {
    SyntheticFeather f;
    f.width = f.height = 900;
    f.length = length * U(0.94, 1.06);
    f.dir_deg = feather_deg + U(-6, 6);
    f.calamus = first + k * step * along_row + U(-0.03, 0.03) * length * up;
    f.w_left = wl * U(0.9, 1.1);
    f.w_right = wr * U(0.9, 1.1);
    f.theta_deg = U(30, 45);
    f.spacing = U(6, 9);
    f.seed = seed * 100 + unsigned(k);
    row.push_back(f);
  }
  return row;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("plumage_shingled_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

glm::dvec2 calamus_px(const FeatherLayout& f) { return synthetic::shaft_px(f, 0.0); }
glm::dvec2 tip_px(const FeatherLayout& f) { return synthetic::shaft_px(f, 1.0); }

}  // namespace

// Rows of 4-10 feathers at random overlaps (30-65 % of a vane's width) and angles
// (the row at any angle, each feather tilted up to 6 degrees): every feather is
// found from its own quill (row_found.h: its calamus within 3 % of its length,
// its shaft nearer its own rachis than any other's), or the row is reported as
// one region that holds several quills; never one analysed feather across two
// quills. Stations where a neighbour covers a side are marked hidden.
TEST(AnalysisShingled, EveryQuillIsAFeatherOrTheRowIsReported) {
  const fs::path dir = scratch("rows");
  int split_rows = 0;
  for (int n = 4; n <= 10; ++n) {
    const unsigned seed = unsigned(n) * 7 + 3;
    const auto row = shingled_row(n, seed);
    const fs::path photo = dir / ("row" + std::to_string(n) + ".png");
    write_image(photo, synthetic::draw_overlapping(row));
    SCOPED_TRACE("row of " + std::to_string(n) + ", seed " + std::to_string(seed));
    const synthetic::RowOutcome got = synthetic::analyse_row(photo, row);
    const Layout& L = got.layout;
    // Each region is a row cut into its feathers, or reported as several feathers
    // that hold quills side by side (a wide gap in the row makes two regions).
    if (got.reported) {
      EXPECT_NE(got.message.find("quills"), std::string::npos) << got.message;
    }
    int hidden_sides = 0;
    for (const FeatherLayout& f : L.feathers) {
      // Cut from a region listed as a split row, under an id after the regions'.
      EXPECT_TRUE(std::any_of(L.skipped.begin(), L.skipped.end(), [&](const SkippedRegion& r) {
        return r.id == f.row.region && r.reason == "split_row" && r.id < f.id;
      })) << "feather " << f.id;
      EXPECT_GE(f.row.feathers, 2);
      // Where the tips overlap, which feather a tip belongs to is a guess: the
      // length is held to 30 % (its own feather: the drawn one nearest its calamus).
      const SyntheticFeather& t = *std::min_element(row.begin(), row.end(), [&](const auto& a, const auto& b) {
        return glm::length(a.calamus - calamus_px(f)) < glm::length(b.calamus - calamus_px(f));
      });
      EXPECT_NEAR(glm::length(tip_px(f) - calamus_px(f)), t.length, 0.3 * t.length) << "feather " << f.id;
      for (const VaneProfile* v : {&f.left, &f.right}) {
        ASSERT_EQ(v->width_hidden.size(), f.stations_t.size());
        bool any = false;
        for (std::size_t i = 0; i < v->width_hidden.size(); ++i) {
          if (v->width_hidden[i] > 0) {
            EXPECT_EQ(v->width_confidence[i], 0.0);
          }
          any = any || v->width_hidden[i] > 0;
        }
        hidden_sides += any;
      }
    }
    const bool reported = got.reported;
    const std::vector<int>& matched = got.matched;
    if (reported) continue;
    ++split_rows;
    EXPECT_EQ(L.feathers.size(), std::size_t(n));
    for (int j = 0; j < n; ++j) EXPECT_EQ(matched[std::size_t(j)], 1) << "true feather " << j;
    // Neighbours overlap: each pair hides at least one side, where they meet.
    EXPECT_GE(hidden_sides, n - 1);
  }
  // The rows are followed, not merely reported.
  EXPECT_GE(split_rows, 6);
  fs::remove_all(dir);
}

// One feather has one quill: a feather of its own is not split, and its layout
// has no row and no hidden stations.
TEST(AnalysisShingled, ASingleFeatherIsNoRow) {
  const fs::path dir = scratch("single");
  SyntheticFeather f;
  write_image(dir / "one.png", f.draw());
  const PhotoAnalysis A = analyze_photo(dir / "one.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_TRUE(A.layout.skipped.empty());
  EXPECT_EQ(A.layout.feathers[0].row.feathers, 0);
  EXPECT_TRUE(A.layout.feathers[0].left.width_hidden.empty());
  EXPECT_LT(glm::length(calamus_px(A.layout.feathers[0]) - f.calamus), 0.03 * f.length);
  fs::remove_all(dir);
}

// --feather picks one feather of a split row by its id; the row's own id is refused
// with the ids to pick from.
TEST(AnalysisShingled, FeatherPicksOneOfARowAndTheRowItselfIsRefused) {
  const fs::path dir = scratch("pick");
  const auto row = shingled_row(5, 38);
  write_image(dir / "row.png", synthetic::draw_overlapping(row));
  AnalyzeOptions opt;
  opt.feather = 1;
  try {
    analyze_photo(dir / "row.png", opt);
    FAIL() << "region 1 is a row";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("feathers 2-6"), std::string::npos) << e.what();
  }
  opt.feather = 4;
  const PhotoAnalysis A = analyze_photo(dir / "row.png", opt);
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_EQ(A.layout.feathers[0].id, 4);
  EXPECT_EQ(A.layout.feathers[0].row.feathers, 5);
  fs::remove_all(dir);
}

// A split row's layout.json says which region each feather came from and which
// stations it could not see, reads back to the same text, and refuses a row of
// one feather or a hidden flag outside 0..1.
TEST(AnalysisShingled, TheRowAndItsHiddenStationsRoundTripThroughLayoutJson) {
  const fs::path dir = scratch("json");
  write_image(dir / "row.png", synthetic::draw_overlapping(shingled_row(4, 31)));
  PhotoAnalysis A = analyze_photo(dir / "row.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 4u);
  write_analysis(A, dir / "row.json");
  const std::string text = read_file(dir / "row.json");
  const Layout L = parse_layout(text, "row.json");
  // Read back, written again, read again: the same text (s_ness is recomputed
  // from the control points as written, so the first pass may move its last digit).
  EXPECT_EQ(layout_to_json(parse_layout(layout_to_json(L), "again.json")), layout_to_json(L));
  EXPECT_EQ(L.feathers[1].row.region, 1);
  EXPECT_EQ(L.feathers[1].row.feathers, 4);
  EXPECT_EQ(L.feathers[1].left.width_hidden, A.layout.feathers[1].left.width_hidden);
  ASSERT_EQ(L.skipped.size(), 1u);
  EXPECT_EQ(L.skipped[0].reason, "split_row");
  // The generator builds a side hidden at half its stations or more from its prior,
  // and says so; a side that shows is built from what shows.
  for (const FeatherLayout& f : L.feathers) {
    const LayoutParams P = layout_to_params(f);
    for (const auto& [name, v] : {std::pair{"left", &f.left}, std::pair{"right", &f.right}}) {
      const auto n = std::count(v->width_hidden.begin(), v->width_hidden.end(), 1.0);
      const bool warned = std::any_of(P.warnings.begin(), P.warnings.end(), [&](const std::string& w) {
        return w.rfind(std::string(name) + " vane width: hidden", 0) == 0;
      });
      EXPECT_EQ(warned, 2 * std::size_t(n) >= v->width_hidden.size()) << "feather " << f.id << " " << name;
    }
  }
  auto fails_with = [&](const std::string& from, const std::string& to, const std::string& needle) {
    std::string t = text;
    const auto k = t.find(from);
    ASSERT_NE(k, std::string::npos) << from;
    try {
      parse_layout(t.replace(k, from.size(), to), "bad.json");
      ADD_FAILURE() << "accepted: " << to;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  fails_with("\"feathers\": 4", "\"feathers\": 1", "shingled_row.feathers");
  fails_with("\"width_hidden\": [", "\"width_hidden\": [2, ", "width_hidden");
  fails_with("\"reason\": \"split_row\"", "\"reason\": \"split\"", "reason");
  fs::remove_all(dir);
}
