// Sheets of several feathers: a feather on the border or a blob of touching
// feathers is skipped with a warning (in layout.json and on the overlay) and the
// rest of the sheet is analysed (docs/analysis.md, "Sheets").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sys/wait.h>
#include <unistd.h>

#include "plumage/common/atomic_file.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/analysis/analyze.h"
#include "plumage/layout/layout.h"
#include "row_found.h"
#include "synthetic_feather.h"

using namespace plumage;
using plumage::synthetic::SyntheticFeather;
namespace fs = std::filesystem;

namespace {

fs::path sheet_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("plumage_sheet_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// All the feathers on one light card: the darkest of their pictures.
Image on_one_card(const std::vector<SyntheticFeather>& all) {
  Image A = all.front().draw();
  for (std::size_t k = 1; k < all.size(); ++k) {
    const Image B = all[k].draw();
    for (std::size_t i = 0; i < A.pixels.size(); ++i) A.pixels[i] = std::min(A.pixels[i], B.pixels[i]);
  }
  return A;
}
Image on_one_card(const SyntheticFeather& a, const SyntheticFeather& b) { return on_one_card({a, b}); }

// Why the analysis of a photo whose only region is several feathers refuses it
// (its error), or, when it does not, how many feathers it made of it.
std::string refusal(const fs::path& photo) {
  try {
    const PhotoAnalysis A = analyze_photo(photo, AnalyzeOptions{});
    return "analysed as " + std::to_string(A.layout.feathers.size()) + " feather(s)";
  } catch (const Error& e) {
    return e.what();
  }
}

// A whole feather on the left, an upright one on the right cut by the bottom edge.
Image sheet_with_a_cut_feather() {
  SyntheticFeather whole;
  SyntheticFeather cut;
  cut.calamus = {720, 760};
  cut.dir_deg = -90;
  cut.length = 420;
  cut.w_left = cut.w_right = 40;
  cut.seed = 2;
  return on_one_card(whole, cut);
}

// Strongly red pixels of the overlay (linear RGB) inside a box of photo pixels.
int red_pixels(const Image& overlay, const std::array<int, 4>& box) {
  int n = 0;
  for (int y = std::max(0, box[1]); y < std::min(overlay.height, box[1] + box[3]); ++y)
    for (int x = std::max(0, box[0]); x < std::min(overlay.width, box[0] + box[2]); ++x) {
      const glm::vec3 c = overlay.rgb(x, y);
      n += c.x > 0.7f && c.y < 0.1f && c.z < 0.1f;
    }
  return n;
}

}  // namespace

TEST(AnalysisSheet, FeatherOnTheBorderIsSkippedAndTheRestAnalysed) {
  const fs::path dir = sheet_dir("border");
  write_image(dir / "sheet.png", sheet_with_a_cut_feather());
  const PhotoAnalysis A = analyze_photo(dir / "sheet.png", AnalyzeOptions{});
  const Layout& L = A.layout;
  ASSERT_EQ(L.feathers.size(), 1u);
  EXPECT_EQ(L.feathers[0].id, 1);
  EXPECT_FALSE(L.feathers[0].touches_border);
  EXPECT_NEAR(L.feathers[0].length_mm, 56.0, 0.03 * 56.0);  // 560 px at the default 0.1 mm/px
  ASSERT_EQ(L.skipped.size(), 1u);
  EXPECT_EQ(L.skipped[0].id, 2);  // keeps its place in the left-to-right numbering
  EXPECT_EQ(L.skipped[0].reason, "touches_border");
  EXPECT_GT(L.skipped[0].bbox_px[1] + L.skipped[0].bbox_px[3], 695);
  const bool warned = std::any_of(A.warnings.begin(), A.warnings.end(), [](const std::string& w) {
    return w.find("feather 2 skipped") != std::string::npos && w.find("border") != std::string::npos;
  });
  EXPECT_TRUE(warned);
  // Outlined in red on the overlay.
  EXPECT_GT(red_pixels(A.overlay, L.skipped[0].bbox_px), 200);
  AnalyzeOptions allow;
  allow.allow_border = true;
  const PhotoAnalysis B = analyze_photo(dir / "sheet.png", allow);
  ASSERT_EQ(B.layout.feathers.size(), 2u);
  EXPECT_TRUE(B.layout.skipped.empty());
  EXPECT_TRUE(B.layout.feathers[1].touches_border);
  fs::remove_all(dir);
}

TEST(AnalysisSheet, PickingTheSkippedFeatherIsAnError) {
  const fs::path dir = sheet_dir("pick");
  write_image(dir / "sheet.png", sheet_with_a_cut_feather());
  AnalyzeOptions opt;
  opt.feather = 2;
  try {
    analyze_photo(dir / "sheet.png", opt);
    FAIL() << "feather 2 touches the border";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("touches the image border"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--allow-border"), std::string::npos) << e.what();
  }
  opt.feather = 1;
  EXPECT_EQ(analyze_photo(dir / "sheet.png", opt).layout.feathers.size(), 1u);
  fs::remove_all(dir);
}

TEST(AnalysisSheet, SkippedRegionsAreInLayoutJsonThroughTheCli) {
  const fs::path dir = sheet_dir("cli");
  write_image(dir / "sheet.png", sheet_with_a_cut_feather());
  const std::string cmd = std::string("\"") + PLUMAGE_CLI + "\" -q analyze \"" +
                          (dir / "sheet.png").string() + "\" -o \"" + (dir / "out.json").string() +
                          "\" --overlay \"" + (dir / "ov.png").string() + "\" 2>/dev/null";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const Layout L = read_layout(dir / "out.json");
  ASSERT_EQ(L.feathers.size(), 1u);
  ASSERT_EQ(L.skipped.size(), 1u);
  EXPECT_EQ(L.skipped[0].reason, "touches_border");
  EXPECT_NE(L.skipped[0].message.find("border"), std::string::npos);
  // Without -q: the skip and the unknown scale are said once each (the scale
  // for the photo, not again for every feather, which layout.json still marks),
  // and the summary counts what was skipped and why.
  const std::string loud = std::string("\"") + PLUMAGE_CLI + "\" analyze \"" + (dir / "sheet.png").string() +
                           "\" -o \"" + (dir / "loud.json").string() + "\" 2>\"" + (dir / "err.txt").string() + "\"";
  ASSERT_EQ(std::system(loud.c_str()), 0);
  const std::string err = read_file(dir / "err.txt");
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = err.find(what); at != std::string::npos; at = err.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("mm per pixel"), 1u) << err;
  EXPECT_EQ(count("scale unknown"), 0u) << err;
  EXPECT_EQ(count("skipped: touches the image border"), 1u) << err;
  EXPECT_EQ(count("analyze: 1 feather(s), 1 region(s) skipped (0 several feathers, 1 on the border), 0.1 mm/px"), 1u)
      << err;
  EXPECT_EQ(L.feathers[0].warnings, std::vector<std::string>{"scale unknown (default used)"});
  // A layout without "skipped" (older files) still reads, and a bad reason is named.
  std::string text = read_file(dir / "out.json");
  const auto k = text.find("\"touches_border\",");
  ASSERT_NE(k, std::string::npos);
  std::string bad = text;
  bad.replace(k, std::string("\"touches_border\"").size(), "\"cut\"");
  try {
    parse_layout(bad, "bad.json");
    FAIL() << "a skipped region's reason must be one of the two";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("skipped[0].reason"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(AnalysisSheet, CrossedFeathersAreReportedNotMerged) {
  const fs::path dir = sheet_dir("crossed");
  // One feather laid across another: the blob cannot be cut along a neck, and
  // its shape is no feather's (it fills little of its hull), so it is reported,
  // never invented as one feather.
  SyntheticFeather a, b;
  a.calamus = {330, 660};
  a.dir_deg = -90;
  b.calamus = {80, 380};
  b.dir_deg = 0;
  a.length = b.length = 480;
  a.w_left = a.w_right = b.w_left = b.w_right = 45;
  b.seed = 3;
  write_image(dir / "pair.png", on_one_card(a, b));
  // Alone on the card the blob is the only region: an error naming why.
  const std::string why = refusal(dir / "pair.png");
  EXPECT_NE(why.find("touch or overlap"), std::string::npos) << why;
  // With a separate feather beside it, the pair is skipped and that one analysed.
  SyntheticFeather c;
  c.width = 1400;
  c.calamus = {1150, 640};
  c.dir_deg = -90;
  c.length = 500;
  c.w_left = c.w_right = 50;
  c.seed = 4;
  Image wide = c.draw();
  const Image pair = on_one_card(a, b);
  for (int y = 0; y < pair.height; ++y)
    for (int x = 0; x < pair.width; ++x)
      for (int ch = 0; ch < 3; ++ch) wide.at(x, y)[ch] = std::min(wide.at(x, y)[ch], pair.at(x, y)[ch]);
  write_image(dir / "sheet.png", wide);
  const PhotoAnalysis A = analyze_photo(dir / "sheet.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_EQ(A.layout.feathers[0].id, 2);
  ASSERT_EQ(A.layout.skipped.size(), 1u);
  EXPECT_EQ(A.layout.skipped[0].id, 1);
  EXPECT_EQ(A.layout.skipped[0].reason, "unseparated");
  fs::remove_all(dir);
}

TEST(AnalysisSheet, FeathersSideBySideWithOverlappingVanesAreReportedNotMerged) {
  const fs::path dir = sheet_dir("side_by_side");
  // Two feathers laid side by side, their vanes overlapping along their whole
  // length (the blue-jay sheet's second and third tail feathers): one blob whose
  // core is one piece, so it looks like one wide feather, but two quills leave
  // its base. It is cut into one feather per quill, or reported, never analysed
  // as one invented feather.
  SyntheticFeather a, b;
  a.calamus = {330, 660};
  b.calamus = {430, 655};
  a.dir_deg = -90;
  b.dir_deg = -91;
  a.length = 520;
  b.length = 500;
  a.w_left = a.w_right = b.w_left = b.w_right = 60;
  b.seed = 3;
  write_image(dir / "pair.png", on_one_card(a, b));
  const synthetic::RowOutcome got = synthetic::analyse_row(dir / "pair.png", {a, b});
  if (got.reported) {
    EXPECT_NE(got.message.find("quills"), std::string::npos) << got.message;
  } else {
    EXPECT_EQ(got.found, 2);
  }
  // Each of them alone is one feather.
  for (const SyntheticFeather* t : {&a, &b}) {
    write_image(dir / "one.png", t->draw());
    const PhotoAnalysis A = analyze_photo(dir / "one.png", AnalyzeOptions{});
    EXPECT_EQ(A.layout.feathers.size(), 1u);
    EXPECT_TRUE(A.layout.skipped.empty());
  }
  fs::remove_all(dir);
}

TEST(AnalysisSheet, ARowOfFeathersOnAStringIsReportedNotMerged) {
  const fs::path dir = sheet_dir("row");
  // Seven small feathers mounted side by side on a string, each vane over the
  // next (the robin sheet's rows of coverts): one blob, longest along the string,
  // with a tip for each feather along one side. Its quills cut it into one feather
  // each, or it is reported, never analysed as one long invented feather.
  std::vector<SyntheticFeather> row(7);
  for (int i = 0; i < 7; ++i) {
    SyntheticFeather& f = row[std::size_t(i)];
    f.calamus = {150.0 + 75.0 * i, 520.0};
    f.dir_deg = -80;
    f.length = 220;
    f.w_left = f.w_right = 45;
    f.seed = unsigned(10 + i);
  }
  write_image(dir / "row.png", on_one_card(row));
  const synthetic::RowOutcome got = synthetic::analyse_row(dir / "row.png", row);
  if (got.reported) {
    EXPECT_NE(got.message.find("tips along one side"), std::string::npos) << got.message;
  } else {
    EXPECT_EQ(got.found, 7);
  }
  // One of them alone is one feather.
  write_image(dir / "one.png", row[3].draw());
  const PhotoAnalysis A = analyze_photo(dir / "one.png", AnalyzeOptions{});
  EXPECT_EQ(A.layout.feathers.size(), 1u);
  fs::remove_all(dir);
}

// A row of feathers on a string, each 0.3 of its length wide, packed so close
// that each vane covers most of the next (the robin sheet's rows of downy tufts, Ba and the grey cluster below
// MAd): one blob, its tips merged into one edge, but every feather's rachis and
// edges run across the string. N feathers, `gap` px apart along a string at
// `row_deg`, each pointing `tilt_deg` off the string's normal.
// Their lengths vary by up to a fifth, as the tufts on a string do.
std::vector<SyntheticFeather> packed_row(int n, double gap, double length, double row_deg, double tilt_deg,
                                         glm::dvec2 centre, unsigned seed) {
  const glm::dvec2 along(std::cos(row_deg * kPi / 180), std::sin(row_deg * kPi / 180));
  std::mt19937 rng(seed);
  std::vector<SyntheticFeather> row(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    SyntheticFeather& f = row[std::size_t(i)];
    f.dir_deg = row_deg - 90 + tilt_deg;
    f.length = length * std::uniform_real_distribution<double>(0.8, 1.0)(rng);
    f.w_left = f.w_right = 0.15 * length;
    f.spacing = 3;  // barbs about as far apart as the photo's pixels, as on the sheets
    f.seed = seed + unsigned(i);
    f.calamus = centre + (i - 0.5 * (n - 1)) * gap * along - 0.45 * f.length * f.dir();
  }
  return row;
}

TEST(AnalysisSheet, ARowOfFeathersWhoseTipsMergeIsReportedByItsLines) {
  const fs::path dir = sheet_dir("packed");
  // Sixteen feathers 15 px apart, 48 px wide: no tip stands out, and the rule
  // of tips says nothing; the lines, across the blob's length, do, and so do its
  // quills where they can all be seen.
  const std::vector<SyntheticFeather> row = packed_row(16, 15, 160, 0, -10, {450, 350}, 80);
  write_image(dir / "row.png", on_one_card(row));
  const synthetic::RowOutcome got = synthetic::analyse_row(dir / "row.png", row);
  if (got.reported) {
    EXPECT_TRUE(got.message.find("its lines run across it") != std::string::npos ||
                got.message.find("quills side by side") != std::string::npos) << got.message;
  } else {
    EXPECT_EQ(got.found, 16);
  }
  // One of them alone is one feather.
  write_image(dir / "one.png", row[4].draw());
  EXPECT_EQ(refusal(dir / "one.png"), "analysed as 1 feather(s)");
  fs::remove_all(dir);
}

// Rows of 10-16 feathers 120-180 px long, packed along strings 1.5-2.5 times
// as long in any direction, their feathers tilted up to 12 degrees, are cut into
// one feather per quill or reported as rows (by their tips, their lines or their
// quills), never analysed as one feather; single
// feathers are not (FansAreReportedAndSingleFeathersAreNot draws them).
TEST(AnalysisSheet, PackedRowsInAnyDirectionAreReported) {
  const fs::path dir = sheet_dir("rows");
  std::mt19937 rng(9);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  for (int k = 0; k < 6; ++k) {
    const int n = 10 + int(uniform(0, 7));
    // Longer along the string than across it: 1.5-2.5 times the feathers' length.
    const double length = uniform(120, 180), gap = uniform(1.5, 2.5) * length / n,
                 row_deg = uniform(-180, 180), tilt = uniform(-12, 12);
    const auto row = packed_row(n, gap, length, row_deg, tilt, {450, 350}, unsigned(100 + 20 * k));
    write_image(dir / "row.png", on_one_card(row));
    SCOPED_TRACE(std::to_string(n) + " feathers " + std::to_string(length) + " px long " + std::to_string(gap) +
                 " px apart along " + std::to_string(row_deg) + " deg, tilted " + std::to_string(tilt));
    const synthetic::RowOutcome got = synthetic::analyse_row(dir / "row.png", row);
    if (got.reported) {
      EXPECT_TRUE(got.message.find("is a row of feathers side by side") != std::string::npos ||
                  got.message.find("quills side by side") != std::string::npos) << got.message;
    } else {
      EXPECT_EQ(got.found, n);
    }
  }
  fs::remove_all(dir);
}

TEST(AnalysisSheet, AFanOfOverlappingFeathersIsReportedNotMerged) {
  const fs::path dir = sheet_dir("fan");
  // Nine flight feathers spread like a wing, their quills at one wrist and each
  // vane over the next (the goldfinch sheet's spread wing): one compact, convex
  // blob with one core, whose rachises and edges fan out from the wrist. It is
  // reported, never analysed as one invented feather.
  std::vector<SyntheticFeather> fan(9);
  for (int i = 0; i < 9; ++i) {
    SyntheticFeather& f = fan[std::size_t(i)];
    f.calamus = {640, 600};
    f.dir_deg = -175.0 + 12.0 * i;
    f.length = 480;
    f.w_left = 30;
    f.w_right = 45;
    f.seed = unsigned(20 + i);
  }
  write_image(dir / "fan.png", on_one_card(fan));
  const std::string why = refusal(dir / "fan.png");
  EXPECT_NE(why.find("is a fan of overlapping feathers"), std::string::npos) << why;
  // One of them alone is one feather.
  write_image(dir / "one.png", fan[4].draw());
  const PhotoAnalysis A = analyze_photo(dir / "one.png", AnalyzeOptions{});
  EXPECT_EQ(A.layout.feathers.size(), 1u);
  fs::remove_all(dir);
}

// The fan rule over many drawn feathers: single feathers in any direction, of
// any width and barb angle, are analysed (never a fan), and fans of 5-12
// feathers spread over 60-150 degrees in any direction are reported as fans.
TEST(AnalysisSheet, FansAreReportedAndSingleFeathersAreNot) {
  const fs::path dir = sheet_dir("fans");
  std::mt19937 rng(7);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  for (int k = 0; k < 8; ++k) {
    SyntheticFeather f;
    f.dir_deg = uniform(-180, 180);
    f.length = uniform(300, 480);
    f.w_left = uniform(20, 90);
    f.w_right = uniform(20, 90);
    f.theta_deg = uniform(20, 60);
    f.spacing = uniform(5, 12);
    f.seed = unsigned(40 + k);
    f.calamus = glm::dvec2(450, 350) - 0.5 * f.length * f.dir();
    write_image(dir / "one.png", f.draw());
    const std::string why = refusal(dir / "one.png");
    EXPECT_EQ(why, "analysed as 1 feather(s)") << "feather " << k << " at " << f.dir_deg << " deg";
  }
  for (int k = 0; k < 4; ++k) {
    const int n = 5 + 2 * k + int(uniform(0, 2));
    const double spread = uniform(60, 150), first = uniform(-180, 180), length = uniform(260, 320);
    const double w = uniform(25, 40);
    const double middle = (first + 0.5 * spread) * kPi / 180;
    const glm::dvec2 wrist = glm::dvec2(450, 350) - 0.45 * length * glm::dvec2(std::cos(middle), std::sin(middle));
    std::vector<SyntheticFeather> fan(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      SyntheticFeather& f = fan[std::size_t(i)];
      f.calamus = wrist;
      f.dir_deg = first + spread * i / (n - 1);
      f.length = length;
      f.w_left = 0.7 * w;
      f.w_right = w;
      f.seed = unsigned(60 + 13 * k + i);
    }
    write_image(dir / "fan.png", on_one_card(fan));
    const std::string why = refusal(dir / "fan.png");
    EXPECT_NE(why.find("is a fan of overlapping feathers"), std::string::npos)
        << n << " feathers over " << spread << " deg from " << first << " deg: " << why;
  }
  fs::remove_all(dir);
}

// Where the analysed feather matching a true one starts and ends, in photo
// pixels: the one whose shaft's middle is nearest the true vane's middle.
std::pair<glm::dvec2, glm::dvec2> matching_shaft_ends(const Layout& L, const SyntheticFeather& t) {
  const glm::dvec2 middle = t.calamus + t.dir() * (0.6 * t.length);
  std::pair<glm::dvec2, glm::dvec2> best{};
  double best_d = 1e300;
  for (const FeatherLayout& f : L.feathers) {
    const auto to_image = [&](const glm::dvec2& q) { return f.image_from_feather * glm::dvec3(q, 1.0); };
    const glm::dvec2 c = to_image(f.shaft_mm.eval(0.0)), tip = to_image(f.shaft_mm.eval(1.0));
    const double d = glm::length(0.5 * (c + tip) - middle);
    if (d < best_d) best_d = d, best = {c, tip};
  }
  return best;
}

// How many of the analysis's warnings say a feather was cut out of a pair.
long cut_out_of_pairs(const PhotoAnalysis& A) {
  return std::count_if(A.warnings.begin(), A.warnings.end(), [](const std::string& w) {
    return w.find("cut out of 2 touching feathers") != std::string::npos;
  });
}

TEST(AnalysisSheet, QuillOnTipPairIsSeparatedEachReadTheRightWay) {
  const fs::path dir = sheet_dir("touching");
  // The second feather's quill lies on the first one's tip, as on a sheet where
  // feathers are laid in a row: one blob, two cores, cut at the neck between the
  // second vane and the first. The second feather's quill goes to the first, so
  // the first reads longer and the second shorter by about the quill, but both
  // run from quill to tip, and both are reported as cut out.
  SyntheticFeather a, b;
  a.calamus = {200, 660};
  a.length = b.length = 300;
  a.w_left = b.w_left = 40;
  a.w_right = b.w_right = 60;
  b.calamus = a.tip() - a.dir() * 20.0;
  b.seed = 3;
  write_image(dir / "pair.png", on_one_card(a, b));
  const PhotoAnalysis A = analyze_photo(dir / "pair.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 2u);
  EXPECT_TRUE(A.layout.skipped.empty());
  for (const SyntheticFeather* t : {&a, &b}) {
    const auto [c, tip] = matching_shaft_ends(A.layout, *t);
    EXPECT_GT(glm::dot(glm::normalize(tip - c), t->dir()), std::cos(10.0 * 3.14159265 / 180.0))
        << "read backwards or askew: feather at " << t->calamus.x << "," << t->calamus.y;
    EXPECT_LT(glm::length(c - t->calamus), 0.3 * t->length) << "feather at " << t->calamus.x;
    EXPECT_LT(glm::length(tip - t->tip()), 0.2 * t->length) << "feather at " << t->calamus.x;
  }
  EXPECT_EQ(cut_out_of_pairs(A), 2);
  fs::remove_all(dir);
}

TEST(AnalysisSheet, FeathersTouchingAtAPointAreSeparated) {
  const fs::path dir = sheet_dir("point");
  // The tip of one feather laid against the side of another (as feathers in a
  // row on a sheet may lie): one blob, two cores, a cut only as long as the tip
  // is wide where it touches.
  SyntheticFeather a, b;
  a.calamus = {330, 660};
  a.dir_deg = -90;
  a.length = 520;
  a.w_left = a.w_right = 60;
  b.length = 400;
  b.w_left = b.w_right = 50;
  b.dir_deg = 180;
  b.calamus = {388 + 400, 380};
  b.seed = 3;
  write_image(dir / "pair.png", on_one_card(a, b));
  const PhotoAnalysis A = analyze_photo(dir / "pair.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 2u);
  EXPECT_TRUE(A.layout.skipped.empty());
  for (const SyntheticFeather* t : {&a, &b}) {
    const auto [c, tip] = matching_shaft_ends(A.layout, *t);
    EXPECT_LT(glm::length(c - t->calamus), 0.05 * t->length) << "feather at " << t->calamus.x;
    EXPECT_LT(glm::length(tip - t->tip()), 0.05 * t->length) << "feather at " << t->calamus.x;
  }
  EXPECT_EQ(cut_out_of_pairs(A), 2);
  fs::remove_all(dir);
}

TEST(AnalysisSheet, OneFeatherIsNeverSplit) {
  // The synthetic feathers of the accuracy tests, each alone: never "unseparated".
  for (double theta : {25.0, 38.0, 60.0})
    for (bool dark : {false, true}) {
      SyntheticFeather f;
      f.theta_deg = theta;
      f.dark_background = dark;
      const fs::path dir = sheet_dir("single");
      write_image(dir / "one.png", f.draw());
      const PhotoAnalysis A = analyze_photo(dir / "one.png", AnalyzeOptions{});
      EXPECT_EQ(A.layout.feathers.size(), 1u) << theta << (dark ? " dark" : " light");
      EXPECT_TRUE(A.layout.skipped.empty());
      fs::remove_all(dir);
    }
}

namespace {

// Where a feather's vane edge is, `along` px from its calamus, on its `side`.
glm::dvec2 vane_edge(const SyntheticFeather& f, double along, int side) {
  return f.calamus + f.dir() * along + f.right() * (side * f.half_width(along, side));
}

}  // namespace

// Three feathers, the middle one touched on either side by the tip of another
// (two necks, far apart along it): each neck is judged on its own pair, so all
// three are cut apart. The two cuts together span most of the middle feather.
TEST(AnalysisSheet, ThreeFeathersTouchingAtTwoPointsAreSeparated) {
  const fs::path dir = sheet_dir("three");
  SyntheticFeather mid, top, bottom;
  mid.calamus = {80, 350};
  mid.dir_deg = 0;
  mid.length = 560;
  mid.w_left = mid.w_right = 45;
  for (SyntheticFeather* f : {&top, &bottom}) {
    f->length = 260;
    f->w_left = f->w_right = 40;
  }
  // The tips lie on the middle feather's edges, above at 220 px along it,
  // below at 400.
  const glm::dvec2 above = vane_edge(mid, 220, -1), below = vane_edge(mid, 400, 1);
  ASSERT_LT(above.y, mid.calamus.y);
  top.dir_deg = 90, top.calamus = above - top.dir() * top.length, top.seed = 3;
  bottom.dir_deg = -90, bottom.calamus = below - bottom.dir() * bottom.length, bottom.seed = 4;
  write_image(dir / "three.png", on_one_card({mid, top, bottom}));
  const PhotoAnalysis A = analyze_photo(dir / "three.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 3u);
  EXPECT_TRUE(A.layout.skipped.empty());
  for (const SyntheticFeather* t : {&mid, &top, &bottom}) {
    const auto [c, tip] = matching_shaft_ends(A.layout, *t);
    EXPECT_LT(glm::length(c - t->calamus), 0.1 * t->length) << "feather at " << t->calamus.x;
    EXPECT_LT(glm::length(tip - t->tip()), 0.1 * t->length) << "feather at " << t->calamus.x;
  }
  EXPECT_EQ(std::count_if(A.warnings.begin(), A.warnings.end(),
                          [](const std::string& w) { return w.find("cut out of 3 touching") != std::string::npos; }),
            3);
  fs::remove_all(dir);
}

// A long narrow feather with a round tuft at its tip, a little wider than the
// vane: the deepest part of the blob, so its core is a piece of its own (0.6
// of the largest distance to the background is 12 px, the vane's half-width
// 14 px), but the tuft takes about a tenth of the blob, under what a second
// feather must (15 % of the largest piece): a lobe of one feather, analysed,
// not reported as touching.
TEST(AnalysisSheet, AFeatherWithALobeIsOneFeather) {
  const fs::path dir = sheet_dir("lobe");
  SyntheticFeather f;
  f.calamus = {100, 350};
  f.dir_deg = 0;
  f.length = 700;
  f.w_left = f.w_right = 14;
  Image img = f.draw();
  const double radius = 20;
  const glm::dvec2 centre = f.tip();
  const glm::vec3 vane(srgb_to_linear(0.80f), srgb_to_linear(0.50f), srgb_to_linear(0.48f));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (glm::length(glm::dvec2(x + 0.5, y + 0.5) - centre) <= radius) img.set_rgb(x, y, vane);
  write_image(dir / "lobe.png", img);
  const PhotoAnalysis A = analyze_photo(dir / "lobe.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_TRUE(A.layout.skipped.empty());
  fs::remove_all(dir);
}

// Small feathers in a row beside a larger one stand like a word (short, about
// its height, each within 1.5 heights of the next), but their vanes are not
// pen strokes: found. A line of letters drawn 5 px thick under them is text.
TEST(AnalysisSheet, SmallFeathersInARowAreNotText) {
  const fs::path dir = sheet_dir("row");
  SyntheticFeather big, a, b;
  big.calamus = {40, 330}, big.dir_deg = 0, big.length = 430, big.w_left = big.w_right = 30;
  a.calamus = {500, 330}, a.dir_deg = 0, a.length = 130, a.w_left = a.w_right = 16, a.seed = 3;
  b.calamus = {660, 330}, b.dir_deg = 0, b.length = 120, b.w_left = b.w_right = 15, b.seed = 4;
  Image img = on_one_card({big, a, b});
  // Five rings 28 px across and a bar as tall ("ooooo l"), dark ink.
  const float ink = srgb_to_linear(0.12f);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 p(x + 0.5, y + 0.5);
      bool on = std::fabs(p.x - 300) <= 2.5 && std::fabs(p.y - 600) <= 14;
      for (int k = 0; k < 5; ++k) {
        const double r = glm::length(p - glm::dvec2(100 + 40 * k, 600));
        on = on || (r <= 14 && r >= 9);
      }
      if (on) img.set_rgb(x, y, glm::vec3(ink));
    }
  write_image(dir / "row.png", img);
  const PhotoAnalysis A = analyze_photo(dir / "row.png", AnalyzeOptions{});
  EXPECT_EQ(A.layout.feathers.size(), 3u);
  EXPECT_TRUE(A.layout.skipped.empty());
  for (const SyntheticFeather* t : {&a, &b}) {
    const auto [c, tip] = matching_shaft_ends(A.layout, *t);
    EXPECT_LT(glm::length(tip - t->tip()), 0.15 * t->length) << "feather at " << t->calamus.x;
  }
  for (const FeatherLayout& f : A.layout.feathers)
    for (const glm::dvec2& p : f.outline_px) EXPECT_LT(p.y, 560) << "feather " << f.id << " reaches the letters";
  fs::remove_all(dir);
}

// A region near the smallest kept is judged by its pixel count (the polygon through
// its boundary pixels' centres leaves out half of each, a fifth of a region a few
// pixels wide): on a 520 x 500 photo (floor 0.03 %, 78 px) a compact dark blob is a
// feather, a ring of ink drawn 1-2 px thick with as many pixels inside its outline is
// print (its strokes do not survive an opening 3 px across).
TEST(AnalysisSheet, SmallestFeathersCountByPixelsAndThinPrintIsNot) {
  const fs::path dir = sheet_dir("smallest");
  SyntheticFeather big;
  big.width = 520, big.height = 500;  // floor 78 px
  big.calamus = {40, 200}, big.dir_deg = 0, big.length = 300, big.w_left = big.w_right = 22;
  Image img = big.draw();
  const glm::vec3 brown(srgb_to_linear(0.25f), srgb_to_linear(0.18f), srgb_to_linear(0.12f));
  const glm::dvec2 blob(420, 80), ring(420, 320);
  // Both have a 73 px polygon and 88 px inside it, under and over the floor.
  const double kRingOut = 4.4, kRingIn = 3.1;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec2 p(x + 0.5, y + 0.5);
      const glm::dvec2 e = (p - blob) / glm::dvec2(5.6, 3.4);
      const double r = glm::length(p - ring);
      if (glm::dot(e, e) <= 1.0) img.set_rgb(x, y, brown);
      if (r <= kRingOut && r >= kRingIn) img.set_rgb(x, y, glm::vec3(srgb_to_linear(0.05f)));
    }
  write_image(dir / "smallest.png", img);
  const PhotoAnalysis A = analyze_photo(dir / "smallest.png", AnalyzeOptions{});
  const auto holds = [](const FeatherLayout& f, const glm::dvec2& p) {
    const auto& b = f.bbox_px;
    return p.x >= b[0] && p.x <= b[0] + b[2] && p.y >= b[1] && p.y <= b[1] + b[3];
  };
  int blobs = 0, rings = 0;
  for (const FeatherLayout& f : A.layout.feathers) blobs += holds(f, blob), rings += holds(f, ring);
  EXPECT_EQ(A.layout.feathers.size(), 2u);
  EXPECT_EQ(blobs, 1) << "the blob is a feather";
  EXPECT_EQ(rings, 0) << "the thin ring is print";
  fs::remove_all(dir);
}
