// FeatherLayout -> FeatherParams -> Feather: the generated feather has the
// analysed length, shaft direction, widths, barb angles and barb count, unsure
// values are replaced with a warning, and bad layouts are refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <tuple>
#include <unistd.h>

#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "plumage/common/bspline.h"
#include "plumage/common/error.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/layout_to_params.h"

using namespace plumage;

namespace {

constexpr double kLength = 120.0, kWidthLeft = 22.0, kWidthRight = 30.0;
constexpr double kAngleLeft = 40.0, kAngleRight = 55.0, kSpacing = 0.8;

double true_width(double t, double w) { return t < 0.15 ? 0.0 : w * std::pow(std::sin(kPi * (t - 0.15) / 0.85), 0.5); }

// A layout as analysis would report it for a feather with a known shaft (an arc
// turning by `bend_deg`, chord on +Y; or, straight, swinging `wiggle_mm` either way
// of the chord: x = wiggle sin(2 pi y / L)) and known vane profiles.
FeatherLayout known_layout(double bend_deg = 0.0, double wiggle_mm = 0.0) {
  FeatherLayout f;
  f.id = 3;
  const int n = 12;
  std::vector<glm::dvec2> pts;
  const double turn = bend_deg * kPi / 180.0;
  for (int i = 0; i < n; ++i) {
    const double s = double(i - 1) / double(n - 3);  // phantom ends: eval(0), eval(1) at the ends
    // A circular arc whose tangent turns anticlockwise by `turn`, chord on +Y.
    const double a = turn * (s - 0.5);
    pts.push_back(turn == 0.0 ? glm::dvec2(wiggle_mm * std::sin(2 * kPi * s), kLength * s)
                              : glm::dvec2((std::cos(a) - std::cos(0.5 * turn)) * kLength / turn,
                                           (std::sin(a) + std::sin(0.5 * turn)) * kLength / turn));
  }
  f.shaft_mm = BSpline2(pts);
  f.length_mm = arc_length(BSpline3([&] {
    std::vector<glm::dvec3> v;
    for (auto& p : pts) v.push_back(glm::dvec3(p, 0));
    return v;
  }()));
  f.shaft_width_mm = 1.6;
  // Photographed at 0.1 mm/px: barbs 0.8 mm apart are 8 px, resolved.
  f.feather_from_image = glm::dmat3x2(glm::dvec2(0.1, 0), glm::dvec2(0, -0.1), glm::dvec2(0));
  f.image_from_feather = glm::dmat3x2(glm::dvec2(10, 0), glm::dvec2(0, -10), glm::dvec2(0));
  for (int i = 0; i < 24; ++i) f.stations_t.push_back((i + 0.5) / 24.0);
  for (auto [v, w, a] : {std::tuple{&f.left, kWidthLeft, kAngleLeft}, std::tuple{&f.right, kWidthRight, kAngleRight}}) {
    for (double t : f.stations_t) {
      v->width_mm.push_back(true_width(t, w));
      v->width_confidence.push_back(1.0);
      v->barb_angle_deg.push_back(a);
      v->barb_angle_confidence.push_back(0.9);
      v->barb_spacing_mm.push_back(kSpacing);
      v->barb_spacing_confidence.push_back(0.8);
    }
  }
  return f;
}

BSpline3 spline(const Curve& c) {
  std::vector<glm::dvec3> v;
  for (const auto& p : c.points) v.push_back(glm::dvec3(p.p));
  return BSpline3(v);
}

bool has_warning(const std::vector<std::string>& w, const std::string& text) {
  return std::any_of(w.begin(), w.end(), [&](const std::string& s) { return s.find(text) != std::string::npos; });
}

}  // namespace

TEST(LayoutToParams, ParamsFollowTheMeasurements) {
  const LayoutParams lp = layout_to_params(known_layout(), "known.json");
  const FeatherParams& p = lp.params;
  // The repairs: this vane widens from nothing with an infinite slope at its
  // base, faster than barbs at 40 degrees can follow, so the angles are raised
  // there, and their fall to the measured angle above is spread along the shaft
  // (layout_to_params.cpp, make_buildable).
  for (const auto& w : lp.warnings)
    EXPECT_TRUE(w.find("raised where the vane widens") != std::string::npos ||
                w.find("so fast that barbs would fan apart") != std::string::npos)
        << w;
  // Nowhere does the angle fall faster than kMaxFan allows (barb_bend_deg is 0 here).
  for (const VaneParams* v : {&p.left, &p.right}) {
    const double widest = v->width.max_value();
    for (double x = 0.0; x + 0.01 <= 1.0; x += 0.01) {
      const double cot0 = 1.0 / std::tan(v->angle_deg(x) * kPi / 180.0);
      const double cot1 = 1.0 / std::tan(v->angle_deg(x + 0.01) * kPi / 180.0);
      EXPECT_LE(cot1 - cot0, kMaxFan * 0.01 * p.vane_length() / widest + 1e-6) << "x=" << x;
    }
  }
  EXPECT_NEAR(p.shaft.length, kLength, 1e-6);
  // The vane starts between the last bare station (t < 0.15) and the first with width.
  EXPECT_NEAR(p.shaft.calamus_length / kLength, 0.15, 0.05);
  EXPECT_NEAR(p.shaft.bend_deg, 0.0, 1e-6);
  const double barbs = p.vane_length() / kSpacing;
  EXPECT_NEAR(p.barb_count(VaneSide::Left), barbs, 1.0);
  EXPECT_NEAR(p.barb_count(VaneSide::Right), barbs, 1.0);
  for (double t : {0.3, 0.5, 0.7, 0.9}) {
    const double x = (t * kLength - p.shaft.calamus_length) / p.vane_length();
    EXPECT_NEAR(p.left.width(x), true_width(t, kWidthLeft), 0.03 * kWidthLeft) << "t=" << t;
    EXPECT_NEAR(p.right.width(x), true_width(t, kWidthRight), 0.03 * kWidthRight) << "t=" << t;
    if (t < 0.5) {  // raised where the vane still widens fast, never lowered
      EXPECT_GE(p.left.angle_deg(x), kAngleLeft - 1e-6) << "t=" << t;
      EXPECT_LE(p.left.angle_deg(x), kAngleLeft + (t < 0.35 ? 20.0 : 10.0)) << "t=" << t;
      EXPECT_GE(p.right.angle_deg(x), kAngleRight - 1e-6) << "t=" << t;
      EXPECT_LE(p.right.angle_deg(x), kAngleRight + (t < 0.35 ? 20.0 : 10.0)) << "t=" << t;
      continue;
    }
    EXPECT_NEAR(p.left.angle_deg(x), kAngleLeft, 1e-6) << "t=" << t;
    EXPECT_NEAR(p.right.angle_deg(x), kAngleRight, 1e-6) << "t=" << t;
  }
}

TEST(LayoutToParams, FeatherMatchesBarbCountLengthWidthsAndAngles) {
  const FeatherLayout f = known_layout();
  const Feather feather = layout_to_feather(f, 7, ".", ".", "known.json");
  const double vane = f.length_mm * (1.0 - 0.15);
  EXPECT_NEAR(double(feather.count(VaneSide::Left)), vane / kSpacing, 0.05 * vane / kSpacing);
  EXPECT_NEAR(double(feather.count(VaneSide::Right)), vane / kSpacing, 0.05 * vane / kSpacing);
  ASSERT_NE(feather.shaft(), nullptr);
  const BSpline3 shaft = spline(*feather.shaft());
  EXPECT_NEAR(arc_length(shaft), kLength, 0.01 * kLength);
  EXPECT_NEAR(glm::length(glm::dvec2(shaft.eval(1.0)) - f.shaft_mm.eval(1.0)), 0.0, 0.01 * kLength);

  double reach_left = 0, reach_right = 0;
  std::vector<double> angle_left, angle_right;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    const BSpline3 b = spline(c);
    for (double u = 0; u <= 1.0; u += 0.05) {
      const double x = b.eval(u).x;
      (c.side == VaneSide::Left ? reach_left : reach_right) = std::max(
          c.side == VaneSide::Left ? reach_left : reach_right, c.side == VaneSide::Left ? -x : x);
    }
    if (c.root > 0.4 && c.root < 0.8) {
      // Angle at the root between the barb and the shaft's tip direction (+Y here).
      const glm::dvec3 d = glm::normalize(b.deriv(0.0));
      (c.side == VaneSide::Left ? angle_left : angle_right).push_back(std::acos(std::clamp(d.y, -1.0, 1.0)) * 180 / kPi);
    }
  }
  // The widest part of each vane reaches as far as the widest measured width.
  EXPECT_NEAR(reach_left, kWidthLeft, 0.1 * kWidthLeft);
  EXPECT_NEAR(reach_right, kWidthRight, 0.1 * kWidthRight);
  ASSERT_FALSE(angle_left.empty());
  ASSERT_FALSE(angle_right.empty());
  std::sort(angle_left.begin(), angle_left.end());
  std::sort(angle_right.begin(), angle_right.end());
  EXPECT_NEAR(angle_left[angle_left.size() / 2], kAngleLeft, 5.0);
  EXPECT_NEAR(angle_right[angle_right.size() / 2], kAngleRight, 5.0);
}

TEST(LayoutToParams, BentShaftEndsWhereTheAnalysedShaftEnds) {
  for (double bend : {-40.0, 25.0}) {
    const FeatherLayout f = known_layout(bend);
    const LayoutParams lp = layout_to_params(f, "bent.json");
    EXPECT_NEAR(lp.params.shaft.bend_deg, -bend, 2.0) << bend;  // + bends toward +X, i.e. clockwise
    const Feather feather = layout_to_feather(f, 1, ".", ".", "bent.json");
    const BSpline3 shaft = spline(*feather.shaft());
    for (double t : {0.0, 0.5, 1.0})
      EXPECT_NEAR(glm::length(glm::dvec2(shaft.eval(t)) - f.shaft_mm.eval(t)), 0.0, 0.02 * kLength)
          << "bend " << bend << " t " << t;
  }
}

TEST(LayoutToParams, ShaftBendingBothWaysIsFollowedAlongItsLength) {
  // A rachis swinging 2 mm either way of its chord: the builder's arc through both
  // ends misses it by up to 2 mm; the feather is laid along it (shaft_pose.h), so
  // each vane stands across the measured shaft as it was measured.
  const FeatherLayout f = known_layout(0.0, 2.0);
  const Feather feather = layout_to_feather(f, 1, ".", ".", "wiggle.json");
  const BSpline3 shaft = spline(*feather.shaft());
  double worst = 0;
  for (int i = 0; i <= 100; ++i) {
    const glm::dvec2 q(shaft.eval(i / 100.0));
    double best = 1e300;
    for (int j = 0; j <= 2000; ++j) best = std::min(best, glm::length(q - f.shaft_mm.eval(j / 2000.0)));
    worst = std::max(worst, best);
  }
  EXPECT_LT(worst, 0.01 * kLength / 12) << "built shaft up to " << worst << " mm off the analysed one";
  // The widest part of each vane still reaches the measured width from the shaft.
  double reach[2] = {0, 0};
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    const BSpline3 b = spline(c);
    const glm::dvec2 tip(b.eval(1.0));
    double best = 1e300;
    for (int j = 0; j <= 2000; ++j) best = std::min(best, glm::length(tip - f.shaft_mm.eval(j / 2000.0)));
    double& r = reach[c.side == VaneSide::Right];
    r = std::max(r, best);
  }
  EXPECT_NEAR(reach[0], kWidthLeft, 0.1 * kWidthLeft);
  EXPECT_NEAR(reach[1], kWidthRight, 0.1 * kWidthRight);
}

TEST(LayoutToParams, UnsureValuesAreReplacedWithAWarning) {
  FeatherLayout f = known_layout();
  std::fill(f.right.barb_spacing_confidence.begin(), f.right.barb_spacing_confidence.end(), 0.1);
  std::fill(f.left.barb_angle_confidence.begin(), f.left.barb_angle_confidence.end(), 0.0);
  std::fill(f.left.barb_angle_deg.begin(), f.left.barb_angle_deg.end(), 170.0);  // nonsense, but unsure
  // A wild width at one unsure station must not show up in the profile.
  f.right.width_mm[12] = 500.0;
  f.right.width_confidence[12] = 0.0;
  const LayoutParams lp = layout_to_params(f, "unsure.json");
  EXPECT_TRUE(has_warning(lp.warnings, "right barb spacing")) << lp.warnings.size();
  EXPECT_TRUE(has_warning(lp.warnings, "left barb angle"));
  EXPECT_EQ(lp.params.barb_count(VaneSide::Right), lp.params.barb_count(VaneSide::Left));
  const FeatherParams d = default_feather_params();
  EXPECT_NEAR(lp.params.left.angle_deg(0.5), d.left.angle_deg(0.5), 1e-9);
  EXPECT_LT(lp.params.right.width.max_value(), 1.05 * kWidthRight);

  std::fill(f.left.barb_spacing_confidence.begin(), f.left.barb_spacing_confidence.end(), 0.0);
  const LayoutParams none = layout_to_params(f, "unsure.json");
  EXPECT_TRUE(has_warning(none.warnings, "either side"));
  EXPECT_TRUE(has_warning(none.warnings, "prior"));
  EXPECT_NEAR(none.params.vane_length() / none.params.barb_count(VaneSide::Left),
              barb_spacing_prior_mm(f.length_mm), 0.01);
}

// Barbs raised to stand steep where the vane widens fast at its base (blue-jay
// sheet feather 12: 81 degrees there, 28 degrees measured above) used to fall back
// to the measured angle within a few barbs, and the barbs between fanned apart,
// leaving wedges of open card. The fall is spread along the shaft: no two
// neighbouring barbs' tips are much further apart than the vane's typical pair.
TEST(LayoutToParams, AnglesRaisedAtAWideningBaseDoNotFanTheBarbsApart) {
  FeatherLayout f = known_layout();
  for (double& a : f.left.barb_angle_deg) a = 25.0;
  const Feather feather = layout_to_feather(f, 7, ".", ".", "fan.json");
  std::vector<glm::vec3> tips;
  for (const Curve& c : feather.curves)
    if (c.kind == CurveKind::Barb && c.side == VaneSide::Left && c.points.size() >= 2) tips.push_back(c.points.back().p);
  ASSERT_GT(tips.size(), 20u);
  std::vector<double> gaps;
  for (std::size_t i = 0; i + 1 < tips.size(); ++i) gaps.push_back(glm::length(tips[i + 1] - tips[i]));
  const double median = plumage::median(gaps);
  // Leave out the first tenth of the barbs: at the very base the vane is
  // narrower than a spacing and its stubs' tips are their roots.
  double worst = 0;
  for (std::size_t i = gaps.size() / 10; i < gaps.size(); ++i) worst = std::max(worst, gaps[i] / median);
  EXPECT_LT(worst, 3.0) << "median tip gap " << median << " mm";
}

// A side whose vane begins later than the other's (robin sheet feather 14: the inner
// vane starts 4 mm up the quill) is reported over the bare quill with its measured
// width, about the rachis' half-width, at width confidence 0: the side is absent
// there. Held at its first sure width, the vane ran down the quill.
TEST(LayoutToParams, ASideAbsentAtTheBaseBeginsWhereItIsSeen) {
  FeatherLayout f = known_layout();
  constexpr double kSeenFrom = 0.35;
  for (std::size_t i = 0; i < f.stations_t.size(); ++i)
    if (f.stations_t[i] < kSeenFrom) {
      f.right.width_mm[i] = 0.5 * f.shaft_width_mm;
      f.right.width_confidence[i] = 0.0;
    }
  const FeatherParams p = layout_to_params(f, "late-side.json").params;
  const auto x_at = [&](double t) { return (t * kLength - p.shaft.calamus_length) / p.vane_length(); };
  // The left side still sets where the vane begins.
  EXPECT_NEAR(p.shaft.calamus_length / kLength, 0.15, 0.05);
  const double first_seen = true_width(f.stations_t[8], kWidthRight);  // t = 0.354
  // Held at the first sure width, the vane would be first_seen wide all the way down.
  for (double t : {0.17, 0.22, 0.27, 0.30}) EXPECT_LT(p.right.width(x_at(t)), 0.2 * first_seen) << "t=" << t;
  for (double t : {0.5, 0.7, 0.9}) EXPECT_NEAR(p.right.width(x_at(t)), true_width(t, kWidthRight), 0.03 * kWidthRight);
  // An unsure station inside the vane is still bridged by its neighbours.
  f.right.width_mm[14] = 0.0;
  f.right.width_confidence[14] = 0.0;
  const FeatherParams q = layout_to_params(f, "late-side.json").params;
  const double t14 = f.stations_t[14];
  EXPECT_NEAR(q.right.width(x_at(t14)), true_width(t14, kWidthRight), 0.03 * kWidthRight);
}

// Where a photo cannot resolve barbs, a confident "spacing" is the period of
// texture or colour bars: a 250 mm flight feather at 0.86 mm/px read 13 barbs
// per side. Each of the three tests sends such a vane to the prior.
TEST(LayoutToParams, UnresolvedBarbSpacingFallsBackToThePrior) {
  const double prior = barb_spacing_prior_mm(kLength);
  EXPECT_GT(prior, 0.25);
  EXPECT_LT(prior, 0.75);
  auto count_with = [](FeatherLayout f, double mm, double mm_per_px, double jitter) {
    f.feather_from_image = glm::dmat3x2(glm::dvec2(mm_per_px, 0), glm::dvec2(0, -mm_per_px), glm::dvec2(0));
    for (auto* v : {&f.left, &f.right})
      for (std::size_t i = 0; i < v->barb_spacing_mm.size(); ++i)
        v->barb_spacing_mm[i] = mm * (1.0 + ((i % 2) ? jitter : -jitter));
    return layout_to_params(f, "spacing.json");
  };
  // Resolved: 0.8 mm at 0.1 mm/px (8 px), stations agree, near the prior.
  const LayoutParams ok = count_with(known_layout(), kSpacing, 0.1, 0.02);
  EXPECT_FALSE(has_warning(ok.warnings, "barb spacing"));
  EXPECT_NEAR(ok.params.vane_length() / ok.params.barb_count(VaneSide::Left), kSpacing, 0.02);
  // A period of 1 px, stations that disagree by +-50 %, a spacing 10x the prior.
  for (const auto& [mm, mm_per_px, jitter, reason] :
       {std::tuple{0.8, 0.8, 0.02, "px is under"}, std::tuple{0.8, 0.1, 0.5, "disagree"},
        std::tuple{10 * prior, 0.1, 0.02, "of the prior"}}) {
    const LayoutParams lp = count_with(known_layout(), mm, mm_per_px, jitter);
    EXPECT_TRUE(has_warning(lp.warnings, reason)) << reason;
    EXPECT_TRUE(has_warning(lp.warnings, "used the prior")) << reason;
    for (VaneSide side : {VaneSide::Left, VaneSide::Right})
      EXPECT_NEAR(lp.params.vane_length() / lp.params.barb_count(side), prior, 0.01) << reason;
  }
  // A 250 mm feather gets hundreds of barbs per side, never a skeleton.
  FeatherLayout big = known_layout();
  for (auto* v : {&big.left, &big.right})
    std::fill(v->barb_spacing_confidence.begin(), v->barb_spacing_confidence.end(), 0.0);
  big.length_mm = 250;
  const LayoutParams lp = layout_to_params(big, "big.json");
  EXPECT_GT(lp.params.barb_count(VaneSide::Left), 200);
}

// The pink photo once gave the right vane two trusted spacing stations, 0.6 mm and
// a 2.18 mm harmonic; the median of the two took the harmonic and the vane got 54
// barbs against the left's 197. Too few trusted stations borrow the other side's.
// A side's downy base (docs/analysis.md, "Downy base") is built as the generator's
// afterfeather, over the mean of the two sides' share of the vane, and its
// readings are not the vane's: loose barbs at 85 degrees 3 mm apart neither pull
// the barb angles above them nor set the barb count.
TEST(LayoutToParams, ADownyBaseIsBuiltAsLooseBarbsAndItsReadingsAreNotTheVanes) {
  const FeatherParams plain = layout_to_params(known_layout(), "plain.json").params;
  EXPECT_FALSE(plain.afterfeather.enabled);
  FeatherLayout f = known_layout();
  f.left.afterfeather_to_t = 0.35;
  f.right.afterfeather_to_t = 0.25;
  for (VaneProfile* v : {&f.left, &f.right})
    for (std::size_t i = 0; i < f.stations_t.size(); ++i) {
      if (f.stations_t[i] < v->afterfeather_to_t) {
        v->barb_angle_deg[i] = 85.0;
        v->barb_spacing_mm[i] = 3.0;
        v->barb_spacing_confidence[i] = 0.9;
      } else if (i % 4) {  // a quarter of the vane's stations trusted: fewer than the down's
        v->barb_spacing_confidence[i] = 0.1;
      }
    }
  const LayoutParams lp = layout_to_params(f, "downy.json");
  const FeatherParams& p = lp.params;
  ASSERT_TRUE(p.afterfeather.enabled);
  const double cal = p.shaft.calamus_length / kLength;
  EXPECT_NEAR(p.afterfeather.fraction, 0.5 * ((0.35 - cal) + (0.25 - cal)) / (1 - cal), 1e-9);
  EXPECT_TRUE(has_warning(lp.warnings, "downy base")) << lp.warnings.size();
  EXPECT_NEAR(p.vane_length() / p.barb_count(VaneSide::Left), kSpacing, 0.02);
  EXPECT_NEAR(p.vane_length() / p.barb_count(VaneSide::Right), kSpacing, 0.02);
  // As without down: raised where the vane widens fast (at most 20 degrees), not pulled to 85.
  for (double t : {0.3, 0.4}) {
    const double x = (t * kLength - p.shaft.calamus_length) / p.vane_length();
    EXPECT_LE(p.left.angle_deg(x), plain.left.angle_deg(x) + 1e-6) << "t=" << t;
    EXPECT_LE(p.right.angle_deg(x), plain.right.angle_deg(x) + 1e-6) << "t=" << t;
  }
}

TEST(LayoutToParams, TwoTrustedSpacingStationsDoNotSetAVanesBarbCount) {
  FeatherLayout f = known_layout();
  std::fill(f.right.barb_spacing_confidence.begin(), f.right.barb_spacing_confidence.end(), 0.0);
  f.right.barb_spacing_confidence[10] = f.right.barb_spacing_confidence[20] = 0.7;
  f.right.barb_spacing_mm[20] = 3.6 * f.right.barb_spacing_mm[10];
  const LayoutParams lp = layout_to_params(f, "harmonic.json");
  EXPECT_TRUE(has_warning(lp.warnings, "right barb spacing")) << lp.warnings.size();
  EXPECT_EQ(lp.params.barb_count(VaneSide::Right), lp.params.barb_count(VaneSide::Left));
  // Three trusted stations are enough for the median to drop the outlier.
  f.right.barb_spacing_confidence[15] = 0.7;
  const LayoutParams three = layout_to_params(f, "harmonic.json");
  EXPECT_FALSE(has_warning(three.warnings, "right barb spacing"));
  EXPECT_NEAR(three.params.barb_count(VaneSide::Right), three.params.barb_count(VaneSide::Left),
              0.02 * three.params.barb_count(VaneSide::Left));
}

TEST(LayoutToParams, ExtremeMeasurementsStayInTheGeneratorsRange) {
  FeatherLayout f = known_layout();
  for (auto* v : {&f.left, &f.right}) {
    std::fill(v->barb_angle_deg.begin(), v->barb_angle_deg.end(), 179.0);
    std::fill(v->barb_spacing_mm.begin(), v->barb_spacing_mm.end(), 1e-6);  // would be millions of barbs
    std::fill(v->width_mm.begin(), v->width_mm.end(), 0.0);
  }
  const LayoutParams lp = layout_to_params(f, "extreme.json");  // validate() inside: would throw
  EXPECT_LE(lp.params.barb_count(VaneSide::Left), 5000);
  EXPECT_LE(lp.params.left.angle_deg.max_value(), 90.0);
  EXPECT_GT(lp.params.left.width.max_value(), 0.0);
  EXPECT_TRUE(has_warning(lp.warnings, "above 90 degrees ignored"));
  EXPECT_NEAR(lp.params.left.angle_deg(0.5), default_feather_params().left.angle_deg(0.5), 1e-9);
  EXPECT_TRUE(has_warning(lp.warnings, "widths are 0"));
}

TEST(LayoutToParams, WrappedAndStrayTipAnglesAreIgnoredAndTinyOnesRaised) {
  FeatherLayout f = known_layout();
  const std::size_t n = f.stations_t.size();
  f.left.barb_angle_deg[n - 1] = 176.0;  // orientation wrapped at the tip
  f.left.barb_angle_deg[n - 2] = 2.0;    // flat enough for the tip, but not what its neighbours read
  const LayoutParams lp = layout_to_params(f, "tip.json");
  EXPECT_TRUE(has_warning(lp.warnings, "1 station(s) above 90 degrees ignored"));
  EXPECT_TRUE(has_warning(lp.warnings, "1 station(s) off their neighbours along the shaft ignored"));
  EXPECT_FALSE(has_warning(lp.warnings, "raised to 5"));
  // A vane that reads 2 degrees everywhere: only its tip can be that flat, and
  // that is what the whole vane gets, raised to the generator's 5.
  std::fill(f.left.barb_angle_deg.begin(), f.left.barb_angle_deg.end(), 2.0);
  const LayoutParams flat = layout_to_params(f, "tip.json");
  EXPECT_TRUE(has_warning(flat.warnings, "raised to 5"));
  EXPECT_GE(flat.params.left.angle_deg.min_value(), 5.0);
  // Toward the tip nothing rises above the measured angle (the base, where the
  // vane widens fast, is raised: ParamsFollowTheMeasurements).
  for (double x = 0.5; x <= 1.0; x += 0.01) EXPECT_LE(lp.params.left.angle_deg(x), kAngleLeft + 1e-9) << x;
  EXPECT_GE(lp.params.left.angle_deg.min_value(), 5.0);
}

TEST(LayoutToParams, BadLayoutsAreRefusedByName) {
  const auto expect_error = [](const FeatherLayout& f, const std::string& text) {
    try {
      layout_to_params(f, "bad.json");
      ADD_FAILURE() << "no error; expected one mentioning " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  FeatherLayout f = known_layout();
  f.length_mm = 0;
  expect_error(f, "length_mm");
  f = known_layout();
  f.length_mm = std::nan("");
  expect_error(f, "length_mm");
  f = known_layout();
  f.left.width_mm.pop_back();
  expect_error(f, "expected 24");
  f = known_layout();
  f.stations_t[3] = f.stations_t[2];
  expect_error(f, "stations_t[3]");
  f = known_layout();
  f.right.barb_angle_deg[5] = INFINITY;
  expect_error(f, "barb_angle_deg[5]");
  f = known_layout();
  f.shaft_mm = BSpline2({{0, 0}, {0, 1}});
  expect_error(f, "control_points_mm");

  Layout layout;
  layout.feathers = {known_layout()};
  EXPECT_EQ(pick_feather(layout, std::nullopt).id, 3);
  EXPECT_EQ(pick_feather(layout, 3).id, 3);
  try {
    pick_feather(layout, 4, "sheet.json");
    ADD_FAILURE() << "no error for a missing feather";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has 3"), std::string::npos) << e.what();
  }
  layout.feathers.clear();
  EXPECT_THROW(pick_feather(layout, std::nullopt), Error);
}

TEST(LayoutToParams, AlbedoTextureIsReferencedFromTheCurveFilesFolder) {
  const auto dir = std::filesystem::temp_directory_path() / ("plumage_l2p_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "analysis");
  std::filesystem::create_directories(dir / "curves");
  { std::ofstream(dir / "analysis" / "a.png") << "x"; }
  FeatherLayout f = known_layout();
  f.albedo = {"a.png", 40, 100, {-20.0, 130.0}, 0.5, 1.0, {}};
  const Feather feather = layout_to_feather(f, 1, dir / "analysis", dir / "curves", "l.json");
  EXPECT_EQ(feather.albedo.texture, "../analysis/a.png");
  EXPECT_NEAR(feather.albedo.rect_min.x, -20.0, 1e-5);
  EXPECT_NEAR(feather.albedo.rect_min.y, 80.0, 1e-5);
  EXPECT_NEAR(feather.albedo.rect_max.x, 0.0, 1e-5);
  EXPECT_NEAR(feather.albedo.rect_max.y, 130.0, 1e-5);
  f.albedo.file = "missing.png";
  EXPECT_THROW(layout_to_feather(f, 1, dir / "analysis", dir / "curves", "l.json"), Error);
  std::filesystem::remove_all(dir);
}

TEST(LayoutToParams, AlbedoOutsideTheMaskIsTheMeanUnderIt) {
  Image a(4, 2, 4);
  // Two opaque texels (red, blue), one half-covered green, the rest background black.
  a.set_rgb(0, 0, {1, 0, 0});
  a.at(0, 0)[3] = 1;
  a.set_rgb(1, 0, {0, 0, 1});
  a.at(1, 0)[3] = 1;
  a.set_rgb(2, 0, {0, 1, 0});
  a.at(2, 0)[3] = 0.5f;
  glm::vec3 mean;
  const Image out = albedo_for_render(a, &mean);
  const glm::vec3 expect = glm::vec3(1, 0.5f, 1) / 2.5f;
  EXPECT_NEAR(glm::length(mean - expect), 0.0f, 1e-5f);
  EXPECT_EQ(out.channels, 3);
  EXPECT_NEAR(glm::length(out.rgb(0, 0) - glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(out.rgb(3, 1) - expect), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(out.rgb(2, 0) - 0.5f * (expect + glm::vec3(0, 1, 0))), 0.0f, 1e-5f);
  Image clear(3, 3, 4);  // nothing under the mask: a neutral grey, not NaN
  const Image grey = albedo_for_render(clear, &mean);
  EXPECT_NEAR(grey.rgb(1, 1).x, 0.5f, 1e-6f);
  EXPECT_THROW(albedo_for_render(Image()), Error);
}
