#pragma once
// A ray and what it may ignore. Secondary rays leave a curve from behind their
// true origin (see Scene::spawn), so a ray carries the primitive it left and how
// far along the ray that primitive must be skipped.
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
};

}  // namespace plumage
