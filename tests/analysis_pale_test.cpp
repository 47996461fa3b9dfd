// Pale parts on a mid-grey card (docs/analysis.md, "Pale parts"): a white tip
// is part of its feather's outline and its shaft, a white downy feather is a
// feather of its own, and a card with noise and a scanner's gradient has no
// pale parts; nor do white or black cards, where nothing is paler than the card
// or than the feather's own colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <numbers>
#include <random>
#include <unistd.h>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/analysis/analyze.h"
#include "plumage/layout/layout.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

fs::path pale_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("plumage_pale_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// An upright feather (tip up) drawn from its outline: a bare quill `quill` px
// long and 4 px wide, then the vane, full half-width `half` within 6 px, held
// to where the tip begins, then tapering straight to a point over `taper` px.
// The vane above `white_from` (distance from the calamus) is white, below it
// dark blue-grey; barbs slant toward the tip at 40 degrees, one every 7 px.
struct UprightFeather {
  double cx = 300, calamus_y = 600, length = 440, quill = 22, half = 46, taper = 150;
  double white_from = 1e9;
  glm::vec3 dark{0.17f, 0.21f, 0.29f}, white{0.94f, 0.93f, 0.90f}, rachis{0.08f};
  glm::dvec2 calamus() const { return {cx, calamus_y}; }
  glm::dvec2 tip() const { return {cx, calamus_y - length}; }
  double half_width(double s) const {
    if (s < 0 || s > length) return -1;
    if (s < quill) return 2;
    const double base = std::min(1.0, (s - quill) / 6.0), top = std::min(1.0, (length - s) / taper);
    return std::max(2.0, half * std::min(base, top));
  }
  // Colour at (x, y), or false outside.
  bool paint(double x, double y, glm::vec3& c) const {
    const double s = calamus_y - y, d = x - cx, hw = half_width(s);
    if (hw < 0 || std::fabs(d) > hw) return false;
    const bool pale = s >= white_from;
    if (std::fabs(d) <= 1.6) {  // rachis, and the bare quill
      c = pale ? glm::vec3(0.82f, 0.80f, 0.76f) : rachis;
      return true;
    }
    const double phase = (s - std::fabs(d) / std::tan(40.0 * std::numbers::pi / 180.0)) / 7.0;
    const float shade = float(0.85 + 0.15 * std::cos(2 * std::numbers::pi * phase));
    c = (pale ? white : dark) * (pale ? 0.5f + 0.5f * shade : shade);
    return true;
  }
};

// A card of colour `card` (sRGB), `gradient` darker toward the left edge (a
// scanner's), with what `paint` draws on it, 3x3 supersampled, blurred and with
// Gaussian noise of sigma `noise`.
using Paint = std::function<bool(double, double, glm::vec3&)>;
Image draw_card(int w, int h, float card, float gradient, float noise, const std::vector<Paint>& paints,
                unsigned seed = 1) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec3 acc(0.f);
      for (int sy = 0; sy < 3; ++sy)
        for (int sx = 0; sx < 3; ++sx) {
          const double px = x + (sx + 0.5) / 3.0, py = y + (sy + 0.5) / 3.0;
          glm::vec3 c(card - gradient * float(1.0 - px / w));
          for (const Paint& p : paints) p(px, py, c);
          acc += c;
        }
      img.set_rgb(x, y, acc / 9.0f);
    }
  Image out(w, h, 3);
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.f, noise);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec3 s(0.f);
      float wsum = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          const float k = float((2 - std::abs(dx)) * (2 - std::abs(dy)));
          s += img.rgb(xx, yy) * k, wsum += k;
        }
      s /= wsum;
      for (int k = 0; k < 3; ++k) out.at(x, y)[k] = srgb_to_linear(std::clamp(s[k] + n(rng), 0.f, 1.f));
    }
  return out;
}

Paint paint_of(const UprightFeather& f) {
  return [f](double x, double y, glm::vec3& c) { return f.paint(x, y, c); };
}

glm::dvec2 shaft_end(const FeatherLayout& f, double t) {
  return f.image_from_feather * glm::dvec3(f.shaft_mm.eval(t), 1.0);
}

double outline_top(const FeatherLayout& f) {
  double top = 1e300;
  for (const glm::dvec2& p : f.outline_px) top = std::min(top, p.y);
  return top;
}

// The feather whose shaft middle is nearest (x, y).
const FeatherLayout* nearest(const Layout& L, glm::dvec2 at) {
  const FeatherLayout* best = nullptr;
  double d = 1e300;
  for (const FeatherLayout& f : L.feathers) {
    const double e = glm::length(0.5 * (shaft_end(f, 0) + shaft_end(f, 1)) - at);
    if (e < d) d = e, best = &f;
  }
  return best;
}


// Faint down on a light card (the AnalysisPale.Faint* tests): levels below the
// card (8-bit) of the fluff, of its patches over the threshold, and of a
// darker feather that sets the threshold beside them.
constexpr float kFaintCard = 0.90f, kFluff = 45.f / 255, kPatch = 80.f / 255, kDarker = 110.f / 255;

// An UprightFeather in the darker feather's colours.
UprightFeather darker_feather() {
  UprightFeather f;
  f.dark = glm::vec3(kFaintCard - kDarker), f.rachis = glm::vec3(kFaintCard - 1.5f * kDarker);
  return f;
}

bool in_ellipse(double a, double b, double ra, double rb) { return (a / ra) * (a / ra) + (b / rb) * (b / rb) <= 1; }

// A faint plume: an ellipse from `base` along the unit `dir` for `length`,
// `half` wide, in fluff, with patches (ellipses 0.65 half by 0.13 length) at
// the given fractions of the length from its middle toward its tip.
struct FaintPlume {
  glm::dvec2 base, dir;
  double length, half;
  std::vector<double> patches;
};

// Faint plumes, and with `band` the glue band they stand on: from beyond the
// first base to beyond the last, 5 px below the bases to 20 px above them.
Paint faint_plumes(const std::vector<FaintPlume>& plumes, bool band) {
  return [=](double x, double y, glm::vec3& c) {
    const glm::dvec2 p(x, y);
    for (const FaintPlume& f : plumes) {
      const glm::dvec2 across(-f.dir.y, f.dir.x), middle = f.base + 0.5 * f.length * f.dir;
      const double a = glm::dot(p - middle, across), b = glm::dot(p - middle, f.dir);
      if (!in_ellipse(a, b, f.half, 0.5 * f.length)) continue;
      c = glm::vec3(kFaintCard - kFluff);
      for (double at : f.patches)
        if (in_ellipse(a, b - at * f.length, 0.65 * f.half, 0.13 * f.length)) c = glm::vec3(kFaintCard - kPatch);
      return true;
    }
    if (!band || plumes.empty()) return false;
    const FaintPlume &first = plumes.front(), &last = plumes.back();
    const glm::dvec2 across(-first.dir.y, first.dir.x), middle = 0.5 * (first.base + last.base);
    const double a = glm::dot(p - middle, across), b = glm::dot(p - first.base, first.dir);
    const double reach = 0.5 * glm::length(last.base - first.base) + first.half + 10;
    if (std::fabs(a) > reach || b < -5 || b > 20) return false;
    c = glm::vec3(kFaintCard - kFluff);
    return true;
  };
}

// A scan's edge: the frame a percent of the photo's short side deep (where the
// border's colour and spread are taken), striped in thirds 20 levels lighter,
// the card's own, and 20 levels darker: after the photo's blur a spread of
// about 16 levels, so the hysteresis level (4 sigma, about 63) is above the
// fluff's 45 and half the threshold (about 33) below it.
Paint striped_frame(int w, int h) {
  const int deep = std::min(w, h) / 100;
  return [=](double x, double y, glm::vec3& c) {
    const int ix = int(x), iy = int(y);
    if (ix >= deep && iy >= deep && ix < w - deep && iy < h - deep) return false;
    c += glm::vec3(float(((ix + iy) / 4) % 3 - 1) * 20.f / 255);
    return true;
  };
}

}  // namespace

// A dark feather with a white tip that tapers to a point, on a mid-grey card
// 25 levels darker at the left edge. The tip differs from the card by less than
// the card's own range over the photo, so by colour alone the outline ends
// where the white begins. Measured against the card near it, the tip is part
// of the outline, the shaft runs into it, and the calamus is the quill: the
// pointed tip has more rows under 30 % of the widest width (0.3 x 150 = 45)
// than the quill (22), so only the quill test (rows under 10 %) reads it the
// right way round.
TEST(AnalysisPale, WhiteTipIsInTheOutlineAndTheShaftAndTheQuillIsTheCalamus) {
  const fs::path dir = pale_dir("tip");
  UprightFeather f;
  f.white_from = 0.68 * f.length;
  write_image(dir / "tip.png", draw_card(700, 700, 0.64f, 0.10f, 0.015f, {paint_of(f)}));
  const PhotoAnalysis A = analyze_photo(dir / "tip.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_TRUE(A.layout.skipped.empty());
  const FeatherLayout& F = A.layout.feathers[0];
  // The outline reaches the tip's point (within 3 % of the length), not the
  // start of the white part, 140 px below it.
  EXPECT_LT(outline_top(F), f.tip().y + 0.03 * f.length);
  const glm::dvec2 c = shaft_end(F, 0), tip = shaft_end(F, 1);
  EXPECT_LT(glm::length(c - f.calamus()), 0.04 * f.length) << "calamus at " << c.x << "," << c.y;
  EXPECT_LT(glm::length(tip - f.tip()), 0.08 * f.length) << "tip at " << tip.x << "," << tip.y;
  fs::remove_all(dir);
}

// A white downy feather (white vane, pale quill, no part that stands out by
// colour) beside a dark feather on the same grey card: two feathers, the white
// one read from its quill to its tip.
TEST(AnalysisPale, WhiteDownyFeatherIsAFeatherOfItsOwn) {
  const fs::path dir = pale_dir("downy");
  UprightFeather dark;
  dark.cx = 220;
  UprightFeather down;
  down.cx = 520, down.length = 300, down.calamus_y = 560, down.half = 60, down.taper = 110;
  down.white_from = 0;  // white throughout
  write_image(dir / "downy.png", draw_card(760, 700, 0.62f, 0.08f, 0.015f, {paint_of(dark), paint_of(down)}));
  const PhotoAnalysis A = analyze_photo(dir / "downy.png", AnalyzeOptions{});
  ASSERT_EQ(A.layout.feathers.size(), 2u);
  EXPECT_TRUE(A.layout.skipped.empty());
  const FeatherLayout* W = nearest(A.layout, {down.cx, down.calamus_y - 0.5 * down.length});
  ASSERT_NE(W, nullptr);
  EXPECT_LT(glm::length(shaft_end(*W, 0) - down.calamus()), 0.06 * down.length);
  EXPECT_LT(glm::length(shaft_end(*W, 1) - down.tip()), 0.1 * down.length);
  fs::remove_all(dir);
}

// Nothing is pale on a plain card with noise: on mid-grey with a scanner's
// gradient, on white and on black, one feather with no pale part is found as
// exactly itself (its outline within a few pixels of the drawn one), and a
// card without a feather has none.
TEST(AnalysisPale, NoPalePartsOnPlainCardsWithNoise) {
  const fs::path dir = pale_dir("plain");
  struct Card {
    const char* name;
    float colour, gradient;
    glm::vec3 vane, rachis;
  };
  for (const Card& k : {Card{"grey", 0.64f, 0.12f, {0.17f, 0.21f, 0.29f}, glm::vec3(0.08f)},
                        Card{"white", 0.96f, 0.0f, {0.45f, 0.30f, 0.25f}, glm::vec3(0.08f)},
                        Card{"black", 0.04f, 0.0f, {0.80f, 0.70f, 0.62f}, glm::vec3(0.95f)}}) {
    UprightFeather f;
    f.dark = k.vane, f.rachis = k.rachis;
    const fs::path photo = dir / (std::string(k.name) + ".png");
    write_image(photo, draw_card(700, 700, k.colour, k.gradient, 0.03f, {paint_of(f)}, 7));
    const PhotoAnalysis A = analyze_photo(photo, AnalyzeOptions{});
    ASSERT_EQ(A.layout.feathers.size(), 1u) << k.name;
    EXPECT_TRUE(A.layout.skipped.empty()) << k.name;
    // The outline's box is the drawn feather's, within 6 px each way.
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const glm::dvec2& p : A.layout.feathers[0].outline_px)
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    EXPECT_NEAR(x0, f.cx - f.half, 6) << k.name;
    EXPECT_NEAR(x1, f.cx + f.half, 6) << k.name;
    EXPECT_NEAR(y0, f.tip().y, 6) << k.name;
    EXPECT_NEAR(y1, f.calamus_y, 6) << k.name;
    // The card alone: no feather at all.
    const fs::path empty = dir / (std::string(k.name) + "_empty.png");
    write_image(empty, draw_card(700, 700, k.colour, k.gradient, 0.03f, {}, 8));
    EXPECT_THROW(analyze_photo(empty, AnalyzeOptions{}), std::exception) << k.name;
  }
  fs::remove_all(dir);
}

// Card a little lighter than the card around it (as card beside translucent
// grey fluff reads, the fluff darkening the card's average near it) is no
// feather: a patch 20 grey levels above a mid-grey card, where the level is
// 15, is pale, no feather lies along it, and it is nowhere white (twice the
// level); the dark feather beside it is the only feather. The same patch
// white (80 levels above) is a feather of its own.
TEST(AnalysisPale, CardJustLighterThanTheCardIsNoFeather) {
  const fs::path dir = pale_dir("patch");
  UprightFeather dark;
  dark.cx = 220;
  for (const float lift : {20.f / 255.f, 80.f / 255.f}) {
    const Paint patch = [lift](double x, double y, glm::vec3& c) {
      const double dx = (x - 540) / 70, dy = (y - 380) / 45;
      if (dx * dx + dy * dy > 1) return false;
      c += glm::vec3(lift);
      return true;
    };
    const fs::path photo = dir / ("patch" + std::to_string(int(lift * 255)) + ".png");
    write_image(photo, draw_card(760, 700, 0.62f, 0.0f, 0.015f, {paint_of(dark), patch}));
    const PhotoAnalysis A = analyze_photo(photo, AnalyzeOptions{});
    const std::size_t regions = A.layout.feathers.size() + A.layout.skipped.size();
    EXPECT_EQ(regions, lift < 0.2f ? 1u : 2u) << "patch " << lift * 255 << " levels lighter";
    const FeatherLayout* D = nearest(A.layout, {dark.cx, dark.calamus_y - 0.5 * dark.length});
    ASSERT_NE(D, nullptr);
    EXPECT_LT(glm::length(shaft_end(*D, 0) - dark.calamus()), 0.05 * dark.length);
  }
  fs::remove_all(dir);
}

// A buff feather with two dark spots on a mid-grey card, the buff lighter than the
// card by less than it stands out by colour, the spots joined only by the dark
// rachis between them: by colour two cores at a neck that no cut separates, with
// its pale parts one solid oval. One spotted feather (the peregrine sheet's body
// feathers), not two that touch (it is reported as such without the rule).
TEST(AnalysisPale, SpottedFeatherIsOneFeather) {
  const fs::path dir = pale_dir("spotted");
  // An oval 300 x 90 px; spots 80 x 50 px, their centres 70 px either side of its
  // middle; a rachis 3 px wide between them.
  const double cx = 300, cy = 300, along = 150, across = 45, spot_a = 40, spot_b = 25, gap = 70;
  const Paint spotted = [=](double x, double y, glm::vec3& c) {
    const double u = (x - cx) / across, v = (y - cy) / along;
    if (u * u + v * v > 1) return false;
    c = glm::vec3(0.71f, 0.70f, 0.67f);  // buff, a little lighter than the card
    for (double sy : {cy - gap, cy + gap}) {
      const double p = (x - cx) / spot_b, q = (y - sy) / spot_a;
      if (p * p + q * q <= 1) c = glm::vec3(0.22f, 0.17f, 0.12f);
    }
    if (std::fabs(x - cx) <= 1.6 && std::fabs(y - cy) <= gap) c = glm::vec3(0.22f, 0.17f, 0.12f);
    return true;
  };
  write_image(dir / "spotted.png", draw_card(600, 600, 0.62f, 0.05f, 0.015f, {spotted}));
  const PhotoAnalysis A = analyze_photo(dir / "spotted.png", AnalyzeOptions{});
  EXPECT_EQ(A.layout.feathers.size(), 1u);
  EXPECT_TRUE(A.layout.skipped.empty());
  fs::remove_all(dir);
}

// Faint feathers (grey down on a grey card, the blue-jay sheet's two rows of
// grey downy feathers): a feather a little darker than the card whose colour
// clears the threshold only in patches. The card's frame is striped, as a
// scan's edge is, so the border's spread sets the threshold and the hysteresis
// level (4 sigma, above half the threshold). A row of three such plumes on one
// glue band, each in two patches over the threshold, is three feathers, each
// read from the band up; a lone plume in one patch is a feather; a lone plume in
// two patches (one above the other, so the cut between them would run across
// it) is reported, not made two feathers; the dark feather beside them is one.
TEST(AnalysisPale, FaintFeathersInARowAreToldApartAndTheRestReported) {
  const fs::path dir = pale_dir("faint");
  const int w = 900, h = 600;
  UprightFeather dark = darker_feather();
  dark.cx = 120, dark.calamus_y = 560;
  const double top = 210, base = 450;  // each plume's ends
  auto plume = [=](double x, std::vector<double> patches) {
    return FaintPlume{{x, base}, {0, -1}, base - top, 24, std::move(patches)};
  };
  const std::vector<double> row{330, 430, 530};
  const std::vector<double> two{0.23, -0.23};  // 55 px above and below the middle
  write_image(dir / "faint.png",
              draw_card(w, h, kFaintCard, 0.f, 0.01f,
                        {paint_of(dark), faint_plumes({plume(row[0], two), plume(row[1], two), plume(row[2], two)}, true),
                         faint_plumes({plume(680, {0})}, false), faint_plumes({plume(800, two)}, false),
                         striped_frame(w, h)}));
  const PhotoAnalysis A = analyze_photo(dir / "faint.png", AnalyzeOptions{});
  // The lone plume in two patches, reported.
  ASSERT_EQ(A.layout.skipped.size(), 1u);
  const auto& S = A.layout.skipped[0];
  EXPECT_EQ(S.reason, "unseparated");
  EXPECT_NE(S.message.find("faint"), std::string::npos) << S.message;
  EXPECT_NEAR(S.bbox_px[0] + 0.5 * S.bbox_px[2], 800, 10);
  EXPECT_GT(S.bbox_px[3], 0.8 * (base - top));  // the whole plume, both patches
  // The dark feather, the row's three and the lone plume in one patch.
  ASSERT_EQ(A.layout.feathers.size(), 5u);
  for (double x : {dark.cx, row[0], row[1], row[2], 680.0}) {
    const FeatherLayout* F = nearest(A.layout, {x, x == dark.cx ? dark.calamus_y - 0.5 * dark.length : 330.0});
    ASSERT_NE(F, nullptr);
    const glm::dvec2 c = shaft_end(*F, 0), tip = shaft_end(*F, 1);
    EXPECT_NEAR(tip.x, x, 25) << x;
    if (x == dark.cx || x == 680.0) continue;
    // Read from the band up: the calamus within a fifth of the length of it
    // (anywhere along the piece of band cut with the plume).
    EXPECT_GT(c.y, base - 0.2 * (base - top)) << x << ": calamus at " << c.y;
    EXPECT_LT(tip.y, top + 0.3 * (base - top)) << x << ": tip at " << tip.y;
  }
  if (HasFailure()) std::cerr << "photo kept: " << (dir / "faint.png") << "\n";
  else fs::remove_all(dir);
}

// Rows of faint plumes in any direction: 2-5 plumes of random length, width and
// gap, each in two patches, on a band at their bases, the row turned by a random
// angle, on the striped-frame card of the test above. Every plume is one
// feather, read from the band: its calamus near its base, its tip near its tip.
TEST(AnalysisPale, FaintRowsInAnyDirectionAreToldApart) {
  const fs::path dir = pale_dir("faint_rows");
  const int w = 900, h = 900;
  UprightFeather dark = darker_feather();
  dark.cx = 80, dark.calamus_y = 860, dark.length = 280, dark.half = 40, dark.taper = 100;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0, 1);
  for (int row = 0; row < 6; ++row) {
    const int n = 2 + int(U(rng) * 4);
    const double L = 180 + 80 * U(rng), hw = 18 + 10 * U(rng), spacing = 2 * hw + 16 * U(rng);
    const double angle = 2 * std::numbers::pi * U(rng);
    const glm::dvec2 d(std::cos(angle), std::sin(angle)), r(-d.y, d.x), C(450, 430);
    std::vector<glm::dvec2> base(n), tip(n);
    std::vector<FaintPlume> plumes;
    for (int k = 0; k < n; ++k) {
      base[k] = C + (k - 0.5 * (n - 1)) * spacing * r - 0.5 * L * d;
      tip[k] = base[k] + L * d;
      plumes.push_back({base[k], d, L, hw, {-0.2, 0.2}});
    }
    const fs::path photo = dir / ("row" + std::to_string(row) + ".png");
    write_image(photo, draw_card(w, h, kFaintCard, 0.f, 0.01f, {paint_of(dark), faint_plumes(plumes, true), striped_frame(w, h)},
                                 unsigned(row + 1)));
    const PhotoAnalysis A = analyze_photo(photo, AnalyzeOptions{});
    const std::string what = "row " + std::to_string(row) + ": " + std::to_string(n) + " plumes, length " +
                             std::to_string(int(L)) + ", turned " + std::to_string(int(angle * 180 / std::numbers::pi)) +
                             " deg";
    EXPECT_TRUE(A.layout.skipped.empty()) << what;
    EXPECT_EQ(A.layout.feathers.size(), std::size_t(n + 1)) << what;
    for (int k = 0; k < n; ++k) {
      const FeatherLayout* F = nearest(A.layout, 0.5 * (base[k] + tip[k]));
      ASSERT_NE(F, nullptr) << what;
      EXPECT_LT(glm::length(shaft_end(*F, 0) - base[k]), 0.25 * L) << what << ", plume " << k << ": calamus";
      EXPECT_LT(glm::length(shaft_end(*F, 1) - tip[k]), 0.2 * L) << what << ", plume " << k << ": tip";
    }
    if (!HasFailure()) fs::remove(photo);
  }
  if (HasFailure()) std::cerr << "photos kept in " << dir << "\n";
  else fs::remove_all(dir);
}

// A white feather on a grey card, one half in its own shadow: where the shadowed
// half's colour is the card's (card 0.45 and 0.55 with the half at 0.55 and 0.70 of
// white; IoU 0.51 by colour alone, one half left out), its barbs' texture, which
// the card does not have, still outlines it (grow_into_texture, docs/analysis.md
// "Low-contrast outlines"): the outline's IoU with the drawn feather is at least 0.9
// on every card from dark to light grey, shadowed or not.
TEST(AnalysisPale, AWhiteFeatherOnAGreyCardIsOutlinedWholeShadowedHalfAndAll) {
  const fs::path dir = pale_dir("white_on_grey");
  for (const auto& [card, shadow] : {std::pair{0.45f, 0.55f}, std::pair{0.55f, 0.70f}, std::pair{0.55f, 1.0f},
                                      std::pair{0.75f, 0.55f}}) {
    UprightFeather f;
    f.white_from = 0;
    const Paint p = [f, shadow = shadow](double x, double y, glm::vec3& c) {
      if (!f.paint(x, y, c)) return false;
      if (x < f.cx) c *= shadow;
      return true;
    };
    write_image(dir / "w.png", draw_card(600, 700, card, 0.0f, 0.01f, {p}));
    const PhotoAnalysis A = analyze_photo(dir / "w.png", AnalyzeOptions{});
    ASSERT_EQ(A.layout.feathers.size(), 1u) << "card " << card << ", shadow " << shadow;
    // IoU of the analysis's mask (as the closed-loop study takes it) and the drawn
    // feather, over the pixel centres.
    const Image& M = A.masks.at(0);
    const int bx = A.layout.feathers[0].bbox_px[0], by = A.layout.feathers[0].bbox_px[1];
    double inter = 0, uni = 0;
    for (int y = 0; y < 700; ++y)
      for (int x = 0; x < 600; ++x) {
        const double hw = f.half_width(f.calamus_y - (y + 0.5));
        const bool truth = hw >= 0 && std::fabs(x + 0.5 - f.cx) <= hw;
        const bool got = x >= bx && y >= by && x < bx + M.width && y < by + M.height && M.at(x - bx, y - by)[0] > 0.5f;
        inter += truth && got;
        uni += truth || got;
      }
    EXPECT_GE(inter / uni, 0.9) << "card " << card << ", shadow " << shadow;
  }
  fs::remove_all(dir);
}

// A row of white downy plumes on a grey card (the blue-jay sheet's top row),
// each on a small grey base, the bases on one dark thread, the plumes touching
// and leaning apart by up to 10 degrees: one pale part whose distance-transform
// core falls into a piece per plume (docs/analysis.md, "Pale parts", "A row of
// white plumes"). Each plume is found as a feather of its own, read from its
// base (its shaft's ends near the drawn calamus and tip), and no feather spans
// two plumes. Before, the row was one region, reported as several feathers.
TEST(AnalysisPale, ARowOfWhitePlumesOnAThreadIsOneFeatherPerPlume) {
  const fs::path dir = pale_dir("white_row");
  // A plume standing on its calamus: a grey downy tuft (a disc kTuft across,
  // its centre kTuft above the calamus), and above it a white vane (an ellipse
  // from 0.12 to 1 of the length, `half` wide) with barbs slanting to the tip,
  // the rachis a paler line; leaning `lean_deg` to the right.
  struct Plume {
    glm::dvec2 calamus;
    double length = 300, half = 64, lean_deg = 0;
    glm::dvec2 axis() const {
      const double a = lean_deg * std::numbers::pi / 180;
      return {std::sin(a), -std::cos(a)};
    }
    glm::dvec2 tip() const { return calamus + length * axis(); }
    bool paint(double x, double y, glm::vec3& c) const {
      constexpr double kTuft = 30;
      const glm::dvec2 d = glm::dvec2(x, y) - calamus, up = axis(), across(-up.y, up.x);
      const double s = glm::dot(d, up), w = glm::dot(d, across);
      if (s >= 0 && s <= 0.2 * length && std::fabs(w) <= 1.5) return c = glm::vec3(0.80f), true;  // the quill
      const double mid = 0.56 * length, reach = 0.44 * length;
      if (in_ellipse(w, s - mid, half, reach)) {
        if (std::fabs(w) <= 1.2) return c = glm::vec3(0.98f), true;
        const double phase = (s - std::fabs(w) / std::tan(40.0 * std::numbers::pi / 180.0)) / 6.0;
        return c = glm::vec3(float(0.86 + 0.08 * std::cos(2 * std::numbers::pi * phase))), true;
      }
      if (glm::length(d - kTuft * up) <= kTuft) return c = glm::vec3(0.40f, 0.40f, 0.43f), true;
      return false;
    }
  };
  std::vector<Plume> row;
  const double xs[] = {170, 290, 410, 530}, leans[] = {-14, 0, 8, 14};
  for (int i = 0; i < 4; ++i) row.push_back({{xs[i], 560.0}, 300, 64, leans[i]});
  std::vector<Paint> paints;
  for (const Plume& p : row) paints.push_back([p](double x, double y, glm::vec3& c) { return p.paint(x, y, c); });
  paints.push_back([](double x, double y, glm::vec3& c) {  // the thread, 3 px, along the calami
    if (x < 130 || x > 570 || std::fabs(y - 562) > 1.5) return false;
    c = glm::vec3(0.25f);
    return true;
  });
  write_image(dir / "row.png", draw_card(740, 640, 0.62f, 0.04f, 0.015f, paints));
  const PhotoAnalysis A = analyze_photo(dir / "row.png", AnalyzeOptions{});
  EXPECT_EQ(A.layout.feathers.size(), row.size());
  EXPECT_TRUE(A.layout.skipped.empty());
  std::vector<int> found(row.size(), 0);
  for (const FeatherLayout& F : A.layout.feathers) {
    // The plume whose drawn calamus is nearest the traced one.
    const glm::dvec2 calamus = shaft_end(F, 0), tip = shaft_end(F, 1);
    std::size_t k = 0;
    for (std::size_t i = 1; i < row.size(); ++i)
      if (glm::length(row[i].calamus - calamus) < glm::length(row[k].calamus - calamus)) k = i;
    ++found[k];
    const Plume& p = row[k];
    SCOPED_TRACE("F" + std::to_string(F.id) + ", plume " + std::to_string(k + 1));
    // The calamus end is read within a corridor about the line from where the
    // piece's base band weighs to its tip (0.3-5.5 % of the length off; without
    // the corridor, on the thread at the foot of a cut, 18 %).
    EXPECT_LT(glm::length(calamus - p.calamus), 0.08 * p.length);
    EXPECT_LT(glm::length(tip - p.tip()), 0.05 * p.length);
  }
  for (std::size_t i = 0; i < row.size(); ++i) EXPECT_EQ(found[i], 1) << "plume " << i + 1;
  if (!HasFailure()) fs::remove_all(dir);
}
