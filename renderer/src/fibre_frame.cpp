#include "plumage/renderer/fibre_frame.h"

#include <algorithm>
#include <cmath>

namespace plumage {
namespace {
// Embree 3.13 reports v in [-1, 1] across a flat ribbon (not [0, 1] as the
// documentation of other curve types suggests), increasing along -y of our frame;
// render_scene_test checks both facts against the hit's geometric offset.
constexpr float kEmbreeRibbonSign = -1.0f;
}  // namespace

Frame fibre_frame(const glm::vec3& tangent, const glm::vec3& wo) {
  const glm::vec3 x = safe_normalize(tangent, {1, 0, 0});
  const glm::vec3 z_raw = wo - glm::dot(wo, x) * x;
  // wo along the fibre leaves z free: any normal-plane direction will do.
  const float len = glm::length(z_raw);
  if (!(len > 1e-6f)) {
    Frame f = frame_from_normal(x);  // f.n = x; take its t, b as the normal plane
    return Frame{x, glm::cross(f.t, x), f.t};
  }
  const glm::vec3 z = z_raw / len;
  return Frame{x, glm::cross(z, x), z};
}

FibreFrame flat_fibre_frame(const glm::vec3& tangent, const glm::vec3& wo, float v) {
  const float h = std::clamp(kEmbreeRibbonSign * v, -1.0f, 1.0f);
  return {fibre_frame(tangent, wo), h};
}

FibreFrame round_fibre_frame(const glm::vec3& tangent, const glm::vec3& wo, const glm::vec3& centre,
                             float radius, const glm::vec3& p) {
  FibreFrame f{fibre_frame(tangent, wo), 0.0f};
  if (radius > 0) f.h = std::clamp(glm::dot(p - centre, f.frame.b) / radius, -1.0f, 1.0f);
  return f;
}

}  // namespace plumage
