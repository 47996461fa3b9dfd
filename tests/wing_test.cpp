// The wing generator (generator/wing.h): blending key feathers' parameters (ends
// exact, every blend a valid feather), a rock-dove wing of at least 40 feathers and
// 15 000 barbs with primaries lengthening toward the tip, folding that narrows the
// wing, the pair's mirrored placements sharing the feathers, and `plumage wing`.
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "plumage/common/error.h"
#include "plumage/common/scene_format.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/generator/wing.h"
#include "cli_run.h"

using namespace plumage;
namespace fs = std::filesystem;

TEST(Wing, BlendHitsBothEndsAndEveryBlendIsAValidFeather) {
  const FeatherParams a = load_preset("rock-dove-wing"), b = load_preset("osprey-wing-covert");
  const FeatherParams at0 = blend_params(a, b, 0), at1 = blend_params(a, b, 1);
  EXPECT_EQ(at0.shaft, a.shaft);
  EXPECT_EQ(at1.shaft, b.shaft);
  EXPECT_EQ(at0.left.barbs, a.left.barbs);
  EXPECT_EQ(at1.right.substructure, b.right.substructure);
  for (double x = 0; x <= 1.0; x += 0.05) {
    EXPECT_NEAR(at0.left.width(x), a.left.width(x), 1e-9);
    EXPECT_NEAR(at1.right.angle_deg(x), b.right.angle_deg(x), 1e-9);
  }
  for (int i = 0; i <= 20; ++i) {
    const double t = i / 20.0;
    const FeatherParams m = blend_params(a, b, t);
    EXPECT_NO_THROW(validate(m, "blend")) << t;
    EXPECT_GE(m.shaft.length, std::min(a.shaft.length, b.shaft.length));
    EXPECT_LE(m.shaft.length, std::max(a.shaft.length, b.shaft.length));
    // At its knots a blended width lies between the two keys' (between knots the
    // monotone cubic through them may stray by a fraction of a percent).
    for (const glm::dvec2& k : m.right.width.knots()) {
      EXPECT_LE(k.y, std::max(a.right.width(k.x), b.right.width(k.x)) + 1e-9) << t << " " << k.x;
      EXPECT_GE(k.y, std::min(a.right.width(k.x), b.right.width(k.x)) - 1e-9) << t << " " << k.x;
    }
  }
}

TEST(Wing, RockDoveWingHasItsRowsAndBarbs) {
  const Wing w = build_wing(WingOptions{});
  int primaries = 0, secondaries = 0, coverts = 0;
  std::size_t barbs = 0;
  double last_primary = 0;
  for (std::size_t i = 0; i < w.feathers.size(); ++i) {
    const WingFeather& f = w.feathers[i];
    switch (f.row) {
      case WingRow::Primary:
        ++primaries;
        EXPECT_GT(f.params.shaft.length, last_primary) << f.name;  // longer toward the tip
        last_primary = f.params.shaft.length;
        break;
      case WingRow::Secondary: ++secondaries; break;
      default: ++coverts;
    }
    barbs += build_feather(f.params, i, "test").count(CurveKind::Barb);
    ASSERT_TRUE(similarity_of(f.to_world)) << f.name;
  }
  EXPECT_EQ(primaries, 10);
  EXPECT_EQ(secondaries, 11);
  EXPECT_EQ(coverts, 32);
  EXPECT_GE(w.feathers.size(), 40u);
  EXPECT_GE(barbs, 15000u);
  WingOptions ostrich;
  ostrich.preset = "ostrich";
  EXPECT_THROW(build_wing(ostrich), Error);
  WingOptions bad;
  bad.fold = 1.5;
  EXPECT_THROW(build_wing(bad), Error);
}

TEST(Wing, FoldingNarrowsTheWingAndThePairSharesItsFeathers) {
  // The span across x of the feathers' tips (the shaft's end, +Y in its frame).
  const auto span = [](const Wing& w) {
    float lo = 1e9f, hi = -1e9f;
    for (const WingFeather& f : w.feathers) {
      const glm::vec3 tip(f.to_world * glm::vec4(0, float(f.params.shaft.length), 0, 1));
      lo = std::min(lo, tip.x), hi = std::max(hi, tip.x);
    }
    return hi - lo;
  };
  WingOptions spread, folded;
  folded.fold = 1;
  const Wing s = build_wing(spread), f = build_wing(folded);
  EXPECT_LT(span(f), 0.5f * span(s));
  WingOptions pair;
  pair.pair = true;
  const FeatherScene scene = wing_scene(s, pair, "w");
  ASSERT_EQ(scene.placements.size(), 2 * s.feathers.size());
  EXPECT_EQ(scene.feathers.size(), s.feathers.size());
  for (std::size_t i = 0; i < s.feathers.size(); ++i) {
    const ScenePlacement& right = scene.placements[i];
    const ScenePlacement& left = scene.placements[i + s.feathers.size()];
    EXPECT_EQ(right.feather, left.feather);
    EXPECT_FALSE(similarity_of(right.to_world)->mirrored);
    EXPECT_TRUE(similarity_of(left.to_world)->mirrored);
    // The left wing is the right one reflected about the body's midline.
    const glm::vec3 r(right.to_world[3]), l(left.to_world[3]);
    EXPECT_NEAR(r.x + l.x, -30.0f, 1e-3f);
    EXPECT_FLOAT_EQ(r.y, l.y);
  }
  EXPECT_NO_THROW(parse_fscene(format_fscene(scene)));
}

TEST(Wing, AnalysedKeyFeathersSetTheRemigesAndTheWingsSize) {
  // Keys as photo analysis would give them: a few long feathers and short ones.
  std::vector<FeatherParams> keys;
  for (double length : {60.0, 240.0, 180.0, 30.0, 200.0, 150.0}) {
    FeatherParams k = load_preset("rock-dove-wing");
    k.shaft.length = length;
    k.shaft.calamus_length = 0.12 * length;
    k.albedo = glm::vec3(float(length) / 1000.0f);  // tells the keys apart
    keys.push_back(k);
  }
  WingOptions o;
  o.keys = keys;
  const Wing analysed = build_wing(o), preset = build_wing(WingOptions{});
  // P10 is the longest key, P1 the 0.25 rank of the remex keys (>= 40 % of the
  // longest: 240, 200, 180, 150; 60 and 30 are left to the coverts' colour).
  const auto find = [&](const Wing& w, const std::string& name) -> const WingFeather& {
    for (const WingFeather& f : w.feathers)
      if (f.name == name) return f;
    throw Error("no " + name);
  };
  EXPECT_NEAR(find(analysed, "P10").params.shaft.length, blend_params(keys[1], keys[4], 0.05).shaft.length, 1e-9);
  EXPECT_NEAR(find(analysed, "S11").params.shaft.length, blend_params(keys[2], keys[5], 10.5 / 11).shaft.length, 1e-9);
  EXPECT_FLOAT_EQ(find(analysed, "MC1").params.albedo.x, 0.03f);  // the shortest key's colour
  // The bones scale with the longest feather: 240 / 150 of the preset's.
  const glm::vec3 tip_a(find(analysed, "P10").to_world[3]), tip_p(find(preset, "P10").to_world[3]);
  EXPECT_NEAR(glm::length(glm::vec2(tip_a)), 1.6f * glm::length(glm::vec2(tip_p)), 1e-3f);
}

TEST(Wing, CliWritesASceneOfItsFeathers) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_wing_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto r = test::plumage_cli("-q wing -o " + (dir / "w.fscene").string() + " --pair");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "w_feathers" / "P10.fcurves"));
  const auto info = test::plumage_cli_streams("info " + (dir / "w.fscene").string() + " --json");
  ASSERT_EQ(info.rc, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j.at("placements").get<int>(), 106);
  EXPECT_EQ(j.at("distinct_feathers").get<int>(), 53);
  EXPECT_EQ(j.at("mirrored_placements").get<int>(), 53);
  EXPECT_GE(j.at("barbs").get<int>(), 30000);
  EXPECT_EQ(test::plumage_cli("-q wing -o " + (dir / "w.png").string()).rc, 2);
  EXPECT_EQ(test::plumage_cli("-q wing -o " + (dir / "x.fscene").string() + " --fold 2").rc, 2);
  EXPECT_EQ(test::plumage_cli("-q wing -o " + (dir / "x.fscene").string() + " --preset ostrich").rc, 1);
  EXPECT_FALSE(fs::exists(dir / "x.fscene"));
  EXPECT_FALSE(fs::exists(dir / "x_feathers"));  // the empty folder is taken back
  fs::remove_all(dir);
}
