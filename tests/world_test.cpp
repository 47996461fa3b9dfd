// A world of placed feathers (renderer/world.h) against renders of single
// feathers: one placement at the identity is its Scene; a rigid placement seen by
// a camera moved alike, a scaled placement and a scaled feather, a mirrored
// placement and the mirrored image agree; a world's card matches a Scene's; and
// transforms that would deform the fibres are refused.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/world.h"
#include "render_test_feather.h"

using namespace plumage;
using test::mean_channel;

namespace {

// The test feather with its right vane only: mirroring it in x is another feather.
Feather one_vane_feather() {
  Feather f = test::make_test_feather(30.0f, 0.6f, 0.05f);
  std::erase_if(f.curves, [](const Curve& c) { return c.side == VaneSide::Left; });
  return f;
}

LightSet lights_for(const Bounds3f& b) {
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(0.6f)));
  lights.add(SphereLight{b.centre() + glm::vec3(40, 20, 120), 6.0f, glm::vec3(300.0f)});
  return lights;
}

Image render_with(const PathIntegrator& integrator, const Camera& camera, int spp = 8) {
  RenderSettings rs;
  rs.spp = spp;
  rs.seed = 7;
  rs.progress = false;
  rs.allocation = SampleAllocation::Uniform;
  return render(camera, integrator, rs).developed(0);
}

double rms_difference(const Image& a, const Image& b, bool flip_b = false) {
  double s = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = a.at(x, y)[c] - b.at(flip_b ? b.width - 1 - x : x, y)[c];
        s += d * d;
      }
  return std::sqrt(s / (3.0 * a.width * a.height));
}

// Mean of 4x4 blocks: sampling noise averaged down, the picture kept.
Image blocks(const Image& im) {
  Image out(im.width / 4, im.height / 4, 3);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      glm::vec3 s(0);
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const float* p = im.at(4 * x + i, 4 * y + j);
          s += glm::vec3(p[0], p[1], p[2]);
        }
      float* o = out.at(x, y);
      o[0] = s.x / 16, o[1] = s.y / 16, o[2] = s.z / 16;
    }
  return out;
}

// Dark brown fibres: the vane stands out against the bright environment.
HairParams dark_fibres() {
  HairParams hp;
  hp.sigma_a = {1.2f, 1.8f, 2.6f};
  return hp;
}

CameraSpec top_view(const glm::vec3& centre, float height) {
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = centre + glm::vec3(0, 0, 100);
  cs.look_at = centre;
  cs.ortho_height = height;
  return cs;
}

}  // namespace

TEST(World, OnePlacementAtTheIdentityRendersAsItsScene) {
  const Feather f = one_vane_feather();
  const Scene scene(f, SceneOptions{});
  const FibreMaterial material(dark_fibres());
  const World world({{&scene, &material}}, {{0, glm::mat4(1.0f)}}, BackdropSpec{});
  EXPECT_EQ(world.placement_count(), 1u);
  const LightSet lights = lights_for(scene.feather_bounds());
  const Camera camera(CameraSpec{}, 48, 64, scene.feather_bounds());
  const Image alone = render_with(PathIntegrator(scene, lights, material, IntegratorSettings{}), camera);
  const Image placed = render_with(PathIntegrator(world, lights, IntegratorSettings{}), camera);
  // The same rays reach the same Scene; only the secondary rays' skip margin
  // differs by a few float ulps, which changes no path here.
  EXPECT_LT(rms_difference(alone, placed), 1e-4 * mean_channel(alone, 1) + 1e-6);
  EXPECT_GT(mean_channel(alone, 1), 0.05);
}

TEST(World, RigidPlacementSeenByACameraMovedAlikeRendersTheSameImage) {
  const Feather f = one_vane_feather();
  const Scene scene(f, SceneOptions{});
  const FibreMaterial material(dark_fibres());
  glm::mat4 T = glm::translate(glm::mat4(1.0f), glm::vec3(5, -7, 3));
  T = glm::rotate(T, glm::radians(30.0f), glm::vec3(0, 0, 1));
  T = glm::rotate(T, glm::radians(10.0f), glm::vec3(1, 0, 0));
  const World world({{&scene, &material}}, {{0, T}}, BackdropSpec{});
  // Only an environment, the same in every direction, and a camera carried by T:
  // the moved scene is the same picture.
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  const Bounds3f& b = scene.feather_bounds();
  CameraSpec here = top_view(b.centre(), b.size().y * 1.1f);
  CameraSpec there = here;
  there.position = glm::vec3(T * glm::vec4(*here.position, 1));
  there.look_at = glm::vec3(T * glm::vec4(*here.look_at, 1));
  there.up = glm::vec3(T * glm::vec4(here.up, 0));
  const Image a = render_with(PathIntegrator(scene, lights, material, IntegratorSettings{}), Camera(here, 48, 96, b));
  const Image moved = render_with(PathIntegrator(world, lights, IntegratorSettings{}), Camera(there, 48, 96, world.bounds()));
  const double m = mean_channel(a, 1);
  EXPECT_NEAR(mean_channel(moved, 1), m, 0.01 * m);
  EXPECT_LT(rms_difference(blocks(a), blocks(moved)), 0.02 * m);
}

TEST(World, ScaledPlacementRendersAsTheFeatherBuiltAtThatScale) {
  const Feather f = one_vane_feather();
  Feather big = f;
  for (Curve& c : big.curves)
    for (ControlPoint& p : c.points) p.p *= 2.0f, p.radius *= 2.0f;
  const Scene scene(f, SceneOptions{}), big_scene(big, SceneOptions{});
  const FibreMaterial material(dark_fibres());
  const World world({{&scene, &material}}, {{0, glm::scale(glm::mat4(1.0f), glm::vec3(2.0f))}}, BackdropSpec{});
  const LightSet lights = lights_for(big_scene.feather_bounds());
  const CameraSpec cs = top_view(big_scene.feather_bounds().centre(), big_scene.feather_bounds().size().y * 1.1f);
  const Image a = render_with(PathIntegrator(big_scene, lights, material, IntegratorSettings{}), Camera(cs, 48, 96, big_scene.feather_bounds()));
  const Image b = render_with(PathIntegrator(world, lights, IntegratorSettings{}), Camera(cs, 48, 96, world.bounds()));
  const double m = mean_channel(a, 1);
  EXPECT_NEAR(mean_channel(b, 1), m, 0.01 * m);
  EXPECT_LT(rms_difference(blocks(a), blocks(b)), 0.02 * m);
}

TEST(World, MirroredPlacementRendersTheMirrorImage) {
  const Feather f = one_vane_feather();
  const Scene scene(f, SceneOptions{});
  const FibreMaterial material(dark_fibres());
  const World world({{&scene, &material}}, {{0, glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1))}}, BackdropSpec{});
  // Lights symmetric under x -> -x, a camera centred on x = 0 looking straight down.
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(0.5f)));
  lights.add(SphereLight{glm::vec3(0, 80, 60), 5.0f, glm::vec3(300.0f)});  // out of view
  const Bounds3f& b = scene.feather_bounds();
  const float half_width = std::max(std::fabs(b.lo.x), std::fabs(b.hi.x));
  CameraSpec cs = top_view({0, b.centre().y, 0}, b.size().y * 1.05f);
  const int h = 96, w = 4 * int(std::ceil(24.0f * 2 * half_width / (b.size().y * 1.05f)));
  const Image a = render_with(PathIntegrator(scene, lights, material, IntegratorSettings{}), Camera(cs, w, h, b), 16);
  const Image m = render_with(PathIntegrator(world, lights, IntegratorSettings{}), Camera(cs, w, h, world.bounds()), 16);
  // The flip of one is the other (up to sampling noise); unflipped they differ.
  Image flipped(a.width, a.height, a.channels);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < a.channels; ++c) flipped.at(x, y)[c] = a.at(a.width - 1 - x, y)[c];
  const double as_mirror = rms_difference(blocks(flipped), blocks(m));
  const double unflipped = rms_difference(blocks(a), blocks(m));
  EXPECT_LT(as_mirror, 0.25 * unflipped) << "mirror " << as_mirror << ", unflipped " << unflipped;
  EXPECT_NEAR(mean_channel(m, 1), mean_channel(a, 1), 0.01 * mean_channel(a, 1));
}

TEST(World, CardUnderOnePlacementMatchesTheScenesCard) {
  const Feather f = one_vane_feather();
  SceneOptions with_card;
  with_card.backdrop = {true, glm::vec3(0.5f)};
  const Scene carded(f, with_card), bare(f, SceneOptions{});
  const FibreMaterial material(dark_fibres());
  const World world({{&bare, &material}}, {{0, glm::mat4(1.0f)}}, with_card.backdrop);
  EXPECT_TRUE(world.backdrop().enabled);
  const LightSet lights = lights_for(bare.feather_bounds());
  const Camera camera(CameraSpec{}, 48, 64, bare.feather_bounds());
  const Image a = render_with(PathIntegrator(carded, lights, material, IntegratorSettings{}), camera, 16);
  const Image b = render_with(PathIntegrator(world, lights, IntegratorSettings{}), camera, 16);
  // Both cards lie four of the largest radius under the feather's lowest point.
  const double m = mean_channel(a, 1);
  EXPECT_NEAR(mean_channel(b, 1), m, 0.02 * m);
  EXPECT_LT(rms_difference(blocks(a), blocks(b)), 0.03 * m);
}

TEST(World, ManyPlacementsShareOneSceneAndAllShow) {
  const Feather f = one_vane_feather();
  const Scene scene(f, SceneOptions{});
  const FibreMaterial material(dark_fibres());
  std::vector<WorldPlacement> placements;
  for (int i = 0; i < 40; ++i)
    placements.push_back({0, glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(25.0f * float(i % 8), 40.0f * float(i / 8), 0)),
                                         glm::radians(9.0f * float(i)), glm::vec3(0, 0, 1))});
  const World world({{&scene, &material}}, placements, BackdropSpec{});
  EXPECT_EQ(world.placement_count(), 40u);
  EXPECT_EQ(world.feathers().size(), 1u);
  // Every placement is found by a ray straight down onto its own shaft's middle.
  int found = 0;
  const Curve& shaft = f.curves.front();
  const glm::vec3 mid = shaft.points[shaft.points.size() / 2].p;
  for (std::uint32_t i = 0; i < 40; ++i) {
    const glm::vec3 p = glm::vec3(placements[i].to_world * glm::vec4(mid, 1));
    Ray r;
    r.o = p + glm::vec3(0, 0, 50);
    r.d = {0, 0, -1};
    WorldHit hit;
    if (world.intersect(r, hit) && hit.placement == i && hit.local.kind == HitKind::Shaft &&
        std::fabs(hit.p.z - p.z) < 1.0f)
      ++found;
  }
  EXPECT_EQ(found, 40);
}

TEST(World, RefusesTransformsThatDeformTheFibres) {
  const Scene scene(one_vane_feather(), SceneOptions{});
  const FibreMaterial material(dark_fibres());
  glm::mat4 shear(1.0f);
  shear[1][0] = 0.3f;
  EXPECT_THROW(World({{&scene, &material}}, {{0, shear}}, BackdropSpec{}), Error);
  EXPECT_THROW(World({{&scene, &material}}, {{0, glm::scale(glm::mat4(1.0f), glm::vec3(1, 2, 1))}}, BackdropSpec{}), Error);
  EXPECT_THROW(World({{&scene, &material}}, {{0, glm::mat4(0.0f)}}, BackdropSpec{}), Error);
  EXPECT_THROW(World({{&scene, &material}}, {{1, glm::mat4(1.0f)}}, BackdropSpec{}), Error);
  EXPECT_THROW(World({{&scene, &material}}, {}, BackdropSpec{}), Error);
  SceneOptions carded;
  carded.backdrop.enabled = true;
  const Scene with_card(one_vane_feather(), carded);
  EXPECT_THROW(World({{&with_card, &material}}, {{0, glm::mat4(1.0f)}}, BackdropSpec{}), Error);
}
