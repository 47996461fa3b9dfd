#pragma once
// The local frame the hair BCSDF works in (hair_bcsdf.h): x along the fibre
// tangent, z toward the viewer (wo projected into the fibre's normal plane),
// y = z x x, and h in [-1,1] the hit's offset across the fibre along +y in units
// of the radius (h = sin gamma_o, Marschner et al. 2003 §4).
#include <glm/glm.hpp>

#include "plumage/common/frame.h"

namespace plumage {

struct FibreFrame {
  Frame frame;  // t = fibre x, b = y, n = z
  float h = 0;
};

// The frame for a fibre with tangent `tangent` seen along `wo` (pointing away from the fibre).
Frame fibre_frame(const glm::vec3& tangent, const glm::vec3& wo);

// Flat (ray-facing) ribbon: h comes from the hit's v across the ribbon. Embree 3.13
// gives v in [-1, 1] running along -y, so h = -v (a v in [0, 1] would need 2v - 1).
FibreFrame flat_fibre_frame(const glm::vec3& tangent, const glm::vec3& wo, float v);

// Round curve: Embree reports v = 0, so h is the hit point's offset from the
// centreline projected on y, divided by the radius (clamped to [-1,1]).
FibreFrame round_fibre_frame(const glm::vec3& tangent, const glm::vec3& wo, const glm::vec3& centre,
                             float radius, const glm::vec3& p);

}  // namespace plumage
