#pragma once
// A small spherical area light of uniform radiance (one LED of the dome rig).
#include <cmath>
#include <optional>

#include <glm/glm.hpp>

namespace plumage {

struct SphereLight {
  glm::vec3 centre{0};
  float radius = 1;      // mm
  glm::vec3 radiance{1}; // W / (mm^2 sr), the same from every point and direction

  // Radiance that gives radiant intensity I (W/sr) toward any direction: I = L pi r^2.
  static glm::vec3 radiance_for_intensity(const glm::vec3& intensity, float radius);
};

struct SphereSample {
  glm::vec3 wi;  // unit direction from the shading point to the light
  float dist;    // distance to the light's surface along wi
  float pdf;     // solid-angle pdf
};

// Uniform sampling of the cone the sphere subtends from p (solid-angle sampling).
// nullopt when p is inside the sphere.
std::optional<SphereSample> sample_sphere_light(const SphereLight& l, const glm::vec3& p, const glm::vec2& u);
// The solid-angle pdf sample_sphere_light gives a direction that hits the sphere.
float sphere_light_pdf(const SphereLight& l, const glm::vec3& p);
// Irradiance at p on a surface of unit normal n: pi L sin^2(theta_max) cos(theta),
// exact for a sphere wholly above the surface's horizon (the usual case: a small
// LED far away); zero when the centre is below it or p is inside the sphere.
glm::vec3 sphere_light_irradiance(const SphereLight& l, const glm::vec3& p, const glm::vec3& n);
// Distance along a unit direction to the sphere's near side, or nullopt.
// Inline: every ray of a path tests every LED.
inline std::optional<float> intersect_sphere(const SphereLight& l, const glm::vec3& o, const glm::vec3& d) {
  const glm::vec3 oc = l.centre - o;
  const float b = glm::dot(oc, d);
  const float c = glm::dot(oc, oc) - l.radius * l.radius;
  if (c > 0 && b <= 0) return std::nullopt;  // outside, and the sphere is behind the ray
  // Distance from the centre to the line, computed stably (|oc - b d|^2).
  const glm::vec3 perp = oc - b * d;
  const float disc = l.radius * l.radius - glm::dot(perp, perp);
  if (disc < 0) return std::nullopt;
  const float s = std::sqrt(disc);
  if (c > 0) {
    const float t = b - s;
    if (t > 0) return t;
    return std::nullopt;
  }
  return b + s;  // inside: the far side
}

}  // namespace plumage
