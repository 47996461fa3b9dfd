#pragma once
// A ray and what it may ignore. Secondary rays leave a curve from behind their
// true origin (see Scene::spawn), so a ray carries the primitive it left and how
// far along the ray that primitive must be skipped.
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace plumage {

inline constexpr std::uint32_t kNoId = 0xffffffffu;

struct Ray {
  glm::vec3 o{0}, d{0, 0, 1};
  float tnear = 0;
  float tfar = std::numeric_limits<float>::infinity();
  // Hits on this (geometry, feather curve) with t < skip_until are rejected.
  std::uint32_t skip_geom = kNoId;
  std::uint32_t skip_curve = kNoId;
  float skip_until = 0;
  // A world of many feathers (world.h): the placement the skip applies in
  // (kWorldCard: the world's card); kNoId for a ray of one feather's Scene.
  std::uint32_t skip_placement = kNoId;
};

inline constexpr std::uint32_t kWorldCard = kNoId - 1;

// How far a ray from p along unit direction d travels before it is outside the
// infinite tube of radius R around the line through c along `axis` (any length):
// the larger root s of |q + s e|^2 = R^2, with q and e the parts of p - c and d
// normal to the axis. Infinity for a ray inside the tube and along its axis; 0 for
// a ray that never enters it (or is already leaving it from outside).
inline float tube_exit_distance(const glm::vec3& p, const glm::vec3& d, const glm::vec3& c, const glm::vec3& axis,
                                float R) {
  const float len2 = glm::dot(axis, axis);
  const glm::vec3 t = len2 > 0 ? axis / std::sqrt(len2) : glm::vec3(0);
  const glm::vec3 q = (p - c) - glm::dot(p - c, t) * t;
  const glm::vec3 e = d - glm::dot(d, t) * t;
  const float a = glm::dot(e, e), b = glm::dot(q, e), k = glm::dot(q, q) - R * R;
  if (!(a > 0)) return k <= 0 ? std::numeric_limits<float>::infinity() : 0.0f;
  const float disc = b * b - a * k;
  if (!(disc >= 0)) return 0.0f;
  return std::fmax(0.0f, (-b + std::sqrt(disc)) / a);
}

}  // namespace plumage
