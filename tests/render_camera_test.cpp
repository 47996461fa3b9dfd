// Cameras: auto-framing puts the whole feather in view with its margin, rays go
// where the projection says, and degenerate specs are refused.
#include <gtest/gtest.h>

#include "plumage/common/error.h"
#include "plumage/renderer/camera.h"

using namespace plumage;

namespace {
const Bounds3f kBox{{-10, 0, -1}, {10, 60, 1}};

// Where the ray through (x, y) meets the plane z = 0.
glm::vec3 on_plane(const Camera& c, float x, float y) {
  const Ray r = c.generate(x, y);
  return r.o + (-r.o.z / r.d.z) * r.d;
}
}  // namespace

TEST(RenderCamera, AutoFramedTopViewFitsTheFeatherWithMargin) {
  for (Projection p : {Projection::Perspective, Projection::Orthographic}) {
    CameraSpec spec;
    spec.projection = p;
    spec.margin = 0.1f;
    const Camera cam(spec, 200, 100, kBox);  // wide image: the 60 mm height limits
    EXPECT_NEAR(cam.forward().z, -1.0f, 1e-6f);
    const glm::vec3 centre = on_plane(cam, 100, 50);
    EXPECT_NEAR(centre.x, 0.0f, 1e-3f);
    EXPECT_NEAR(centre.y, 30.0f, 1e-3f);
    // Top edge of the image: +Y (the tip), at 30 + 0.5 * 60 * 1.2 for the feather's mid plane.
    const glm::vec3 top = on_plane(cam, 100, 0);
    EXPECT_GT(top.y, 60.0f);
    if (p == Projection::Orthographic) {
      EXPECT_NEAR(top.y, 30.0f + 36.0f, 1e-2f);
    }
    const glm::vec3 right = on_plane(cam, 200, 50);
    EXPECT_GT(right.x, 10.0f);  // +X to the right
  }
}

TEST(RenderCamera, OrthographicRaysAreParallelAndPerspectiveRaysShareAnOrigin) {
  CameraSpec spec;
  spec.position = glm::vec3(5, 5, 50);
  spec.look_at = glm::vec3(5, 5, 0);
  spec.projection = Projection::Orthographic;
  spec.ortho_height = 8;
  const Camera ortho(spec, 40, 40, kBox);
  const Ray a = ortho.generate(0, 0), b = ortho.generate(40, 40);
  EXPECT_EQ(a.d, b.d);
  EXPECT_NEAR(glm::length(a.o - b.o), 8.0f * std::sqrt(2.0f), 1e-4f);
  spec.projection = Projection::Perspective;
  spec.fov_deg = 90;
  const Camera persp(spec, 40, 40, kBox);
  const Ray c = persp.generate(0, 20), d = persp.generate(40, 20);
  EXPECT_EQ(c.o, d.o);
  // 90 degree fov: the image's left and right edges are 90 degrees apart.
  EXPECT_NEAR(glm::dot(c.d, d.d), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(c.d), 1.0f, 1e-6f);
}

TEST(RenderCamera, RefusesDegenerateSpecs) {
  CameraSpec same;
  same.position = glm::vec3(1, 2, 3);
  same.look_at = glm::vec3(1, 2, 3);
  EXPECT_THROW(Camera(same, 10, 10, kBox), Error);
  CameraSpec parallel_up;
  parallel_up.up = {0, 0, 1};  // the default top view looks along -Z
  EXPECT_THROW(Camera(parallel_up, 10, 10, kBox), Error);
  for (float fov : {0.0f, 180.0f, -5.0f, std::nanf("")}) {
    CameraSpec s;
    s.fov_deg = fov;
    EXPECT_THROW(Camera(s, 10, 10, kBox), Error) << fov;
  }
  EXPECT_THROW(Camera(CameraSpec{}, 0, 10, kBox), Error);
  EXPECT_THROW(Camera(CameraSpec{}, 10, -1, kBox), Error);
}
