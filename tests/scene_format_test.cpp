// The .fscene reader and writer (common/scene_format.h): placements compose their
// operations in the order written, the writer round-trips, similarity_of tells
// similarities from deforming maps over random extremes, and every rule the reader
// enforces fails at its FILE:LINE:COL.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "plumage/common/error.h"
#include "plumage/common/scene_format.h"

using namespace plumage;

namespace {

const char* const kScene =
    "fscene 1\n"
    "units mm\n"
    "feather dove preset rock-dove-wing seed 3   # a comment\n"
    "feather mine fcurves \"feathers/my \\\"best\\\".fcurves\"\n"
    "feather sheet layout \"../sheet/layout.json\" feather 12 seed 5\n"
    "camera position 0 0 400 look_at 0 0 0 fov 35\n"
    "lights 2-25\n"
    "place dove\n"
    "place dove rotate 0 0 90 translate 1 2 3\n"
    "place mine scale 2 mirror x\n"
    "end\n";

glm::vec3 apply(const glm::mat4& m, const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1)); }

// The message of the Error parsing `text` throws ("" when it parses).
std::string error_of(const std::string& text) {
  try {
    parse_fscene(text, "s.fscene");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SceneFormat, ReadsFeathersPlacementsCameraAndLights) {
  const FeatherScene s = parse_fscene(kScene, "s.fscene");
  ASSERT_EQ(s.feathers.size(), 3u);
  EXPECT_EQ(s.feathers[0].name, "dove");
  EXPECT_EQ(s.feathers[0].source, SceneFeatherSource::Preset);
  EXPECT_EQ(s.feathers[0].preset, "rock-dove-wing");
  EXPECT_EQ(s.feathers[0].seed, 3u);
  EXPECT_EQ(s.feathers[1].path, "feathers/my \"best\".fcurves");
  EXPECT_EQ(s.feathers[2].source, SceneFeatherSource::Layout);
  EXPECT_EQ(s.feathers[2].path, "../sheet/layout.json");
  EXPECT_EQ(s.feathers[2].layout_feather, 12u);
  EXPECT_EQ(s.feathers[2].seed, 5u);
  ASSERT_EQ(s.placements.size(), 3u);
  EXPECT_EQ(s.placements[2].feather, 1u);
  EXPECT_EQ(s.placements[1].line, 9);
  // rotate first, then translate: (1,0,0) -> (0,1,0) -> (1,3,3).
  const glm::vec3 q = apply(s.placements[1].to_world, {1, 0, 0});
  EXPECT_NEAR(q.x, 1, 1e-5);
  EXPECT_NEAR(q.y, 3, 1e-5);
  EXPECT_NEAR(q.z, 3, 1e-5);
  const auto sim = similarity_of(s.placements[2].to_world);
  ASSERT_TRUE(sim);
  EXPECT_TRUE(sim->mirrored);
  EXPECT_FLOAT_EQ(sim->scale, 2.0f);
  EXPECT_FLOAT_EQ(apply(s.placements[2].to_world, {1, 1, 1}).x, -2.0f);
  ASSERT_TRUE(s.camera.position && s.camera.look_at && s.camera.fov_deg);
  EXPECT_FALSE(s.camera.up);
  EXPECT_FLOAT_EQ(*s.camera.fov_deg, 35.0f);
  EXPECT_EQ(s.lights.value_or(""), "2-25");
}

TEST(SceneFormat, WriterRoundTripsToTheSameBytes) {
  const FeatherScene s = parse_fscene(kScene, "s.fscene");
  const std::string once = format_fscene(s);
  const FeatherScene back = parse_fscene(once, "once.fscene");
  EXPECT_EQ(format_fscene(back), once);
  ASSERT_EQ(back.placements.size(), s.placements.size());
  for (std::size_t i = 0; i < s.placements.size(); ++i)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_EQ(back.placements[i].to_world[c][r], s.placements[i].to_world[c][r]);
}

TEST(SceneFormat, EveryRuleFailsAtItsPlace) {
  const std::string head = "fscene 1\nfeather a preset rock-dove-wing seed 1\n";
  const std::pair<std::string, std::string> cases[] = {
      {"", "s.fscene:1:1: missing header"},
      {"fscene 2\nend\n", "s.fscene:1:8: format version 2 is newer"},
      {head + "place a\n", "missing 'end'"},
      {head + "end\n", "places no feather"},
      {head + "place b\nend\n", "s.fscene:3:7: place: no feather named 'b'"},
      {head + "feather a preset x seed 1\nplace a\nend\n", "s.fscene:3:9: feather 'a' defined twice (first on line 2)"},
      {head + "feather b$ preset x seed 1\nend\n", "s.fscene:3:9"},
      {head + "feather b blender \"x\"\nend\n", "s.fscene:3:11: feather: unknown source 'blender'"},
      {head + "feather b fcurves \"\"\nend\n", "the file name is empty"},
      {head + "feather b layout \"l.json\" feather 1\nend\n", "s.fscene:3:"},
      {head + "feather b layout \"l.json\" id 1 seed 2\nend\n", "s.fscene:3:27: feather layout: expected 'feather ID'"},
      {head + "feather b layout \"l.json\" feather -1 seed 2\nend\n", "s.fscene:3:35"},
      {head + "feather b layout \"l.json\" feather 4294967296 seed 2\nend\n", "larger than any layout holds"},
      {head + "feather b layout \"l.json\" feather 2 sed 2\nend\n", "s.fscene:3:37: feather layout: expected 'seed N'"},
      {head + "feather b layout \"\" feather 2 seed 2\nend\n", "feather layout: the file name is empty"},
      {head + "place a scale 0\nend\n", "s.fscene:3:15: place scale: must be above 0"},
      {head + "place a scale nan\nend\n", "must be finite"},
      {head + "place a mirror w\nend\n", "s.fscene:3:16: place mirror: expected x, y or z"},
      {head + "place a rotate 1 2\nend\n", "place rotate"},
      {head + "place a spin 3\nend\n", "s.fscene:3:9: place: unknown operation 'spin'"},
      {head + "place a matrix 1 0 0 0 0 1 0.5 0 0 0 1 0\nend\n", "s.fscene:3:9: place matrix: its 3x3 part must be a rotation"},
      {head + "place a matrix 1 0 0 0 0 1 0 0 0 0 1\nend\n", "expected 12 numbers"},
      {head + "place a scale 1e30 scale 1e30\nend\n", "overflows a float"},
      {head + "place a\ncamera fov 200\nend\n", "s.fscene:4:12: camera fov: must lie in (0, 180)"},
      {head + "place a\ncamera zoom 2\nend\n", "s.fscene:4:8: camera: unknown key 'zoom'"},
      {head + "place a\ncamera up 0 0 0\nend\n", "camera up: must not be zero"},
      {head + "place a\nlights all\nlights none\nend\n", "s.fscene:5:1: second 'lights' record (first on line 4)"},
      {head + "place a\nunits cm\nend\n", "s.fscene:4:7: units: Plumage works in millimetres"},
      {head + "place a\nend\nplace a\n", "s.fscene:5:1: text after 'end'"},
      {head + "place a\nwing 3\nend\n", "s.fscene:4:1: unknown record 'wing'"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string got = error_of(text);
    EXPECT_NE(got.find(expected), std::string::npos) << "text:\n" << text << "\nerror: " << got;
  }
}

TEST(SceneFormat, SimilarityOfTellsSimilaritiesFromDeformingMapsOverExtremes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1), lg(-3, 3);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
    const float angle = 3.14159265f * u(rng), scale = std::pow(10.0f, lg(rng));
    glm::mat4 m = glm::rotate(glm::mat4(1.0f), angle, axis);
    m = glm::scale(glm::mat4(1.0f), glm::vec3(scale)) * m;
    if (i % 3 == 0) m = glm::scale(glm::mat4(1.0f), glm::vec3(1, -1, 1)) * m;
    m[3] = glm::vec4(1e3f * u(rng), 1e3f * u(rng), 1e3f * u(rng), 1);
    const auto s = similarity_of(m);
    ASSERT_TRUE(s) << "scale " << scale;
    EXPECT_NEAR(s->scale, scale, 1e-4f * scale);
    EXPECT_EQ(s->mirrored, i % 3 == 0);
    EXPECT_NEAR(std::fabs(glm::determinant(s->rotation)), 1.0f, 1e-4f);
    ++accepted;
    // Any visible shear or unequal scale is refused.
    glm::mat4 d = m;
    d[i % 3][(i + 1) % 3] += 0.01f * scale * (u(rng) < 0 ? -1.0f : 1.0f);
    if (!similarity_of(d)) ++refused;
  }
  EXPECT_EQ(accepted, 20000);
  EXPECT_EQ(refused, 20000);
  EXPECT_FALSE(similarity_of(glm::mat4(0.0f)));
  glm::mat4 inf(1.0f);
  inf[3][0] = INFINITY;
  EXPECT_FALSE(similarity_of(inf));
  glm::mat4 projective(1.0f);
  projective[0][3] = 0.5f;
  EXPECT_FALSE(similarity_of(projective));
}
