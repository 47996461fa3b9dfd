#include "plumage/renderer/sphere_light.h"

#include <cmath>

#include "plumage/common/constants.h"
#include "plumage/common/frame.h"

namespace plumage {
namespace {

// 1 - cos(theta_max) of the cone, without the cancellation of 1 - sqrt(1 - s2) for tiny lights.
float one_minus_cos_max(float sin2_max) { return sin2_max / (1.0f + std::sqrt(std::fmax(0.0f, 1.0f - sin2_max))); }
}  // namespace

glm::vec3 SphereLight::radiance_for_intensity(const glm::vec3& intensity, float radius) {
  return intensity / (kPiF * radius * radius);
}

std::optional<SphereSample> sample_sphere_light(const SphereLight& l, const glm::vec3& p, const glm::vec2& u) {
  const glm::vec3 to_c = l.centre - p;
  const float d2 = glm::dot(to_c, to_c);
  const float r2 = l.radius * l.radius;
  if (!(d2 > r2)) return std::nullopt;
  const float d = std::sqrt(d2);
  const float sin2_max = r2 / d2;
  const float omc = one_minus_cos_max(sin2_max);
  // Uniform in solid angle over the cone: cos theta uniform on [cos theta_max, 1].
  const float one_minus_cos = u.x * omc;
  const float cos_t = 1.0f - one_minus_cos;
  const float sin_t = std::sqrt(std::fmax(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
  const float phi = 2.0f * kPiF * u.y;
  const Frame f = frame_from_normal(to_c / d);
  const glm::vec3 wi = glm::normalize(f.to_world({sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t}));
  // Near intersection along wi (the cone's rays all meet the sphere).
  const float b = glm::dot(to_c, wi);
  const float disc = std::fmax(0.0f, r2 - (d2 - b * b));
  const float dist = std::fmax(0.0f, b - std::sqrt(disc));
  return SphereSample{wi, dist, 1.0f / (2.0f * kPiF * omc)};
}

float sphere_light_pdf(const SphereLight& l, const glm::vec3& p) {
  const glm::vec3 to_c = l.centre - p;
  const float d2 = glm::dot(to_c, to_c);
  const float r2 = l.radius * l.radius;
  if (!(d2 > r2)) return 0.0f;
  return 1.0f / (2.0f * kPiF * one_minus_cos_max(r2 / d2));
}

glm::vec3 sphere_light_irradiance(const SphereLight& l, const glm::vec3& p, const glm::vec3& n) {
  const glm::vec3 to_c = l.centre - p;
  const float d2 = glm::dot(to_c, to_c);
  const float r2 = l.radius * l.radius;
  if (!(d2 > r2)) return glm::vec3(0);
  const float cos_t = glm::dot(to_c, n) / std::sqrt(d2);
  return cos_t > 0 ? l.radiance * (kPiF * r2 / d2 * cos_t) : glm::vec3(0);
}

}  // namespace plumage
