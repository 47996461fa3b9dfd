#pragma once
// Orthonormal frames. Barb frames follow DESIGN §3: tangent t along the curve,
// normal n (the vane-surface normal, dorsal), bitangent b = n x t.
#include <glm/glm.hpp>

namespace plumage {

struct Frame {
  glm::vec3 t{1, 0, 0};  // tangent
  glm::vec3 b{0, 1, 0};  // bitangent = n x t
  glm::vec3 n{0, 0, 1};  // normal

  glm::vec3 to_local(const glm::vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  glm::vec3 to_world(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// An orthonormal basis around a unit vector `n` (becomes the frame's n), with no
// branch on a near-axis direction and no NaN for any unit input (Duff et al.,
// "Building an Orthonormal Basis, Revisited", JCGT 2017).
Frame frame_from_normal(const glm::vec3& n);

// The frame with tangent exactly `tangent` (normalised) and normal as close to
// `normal_hint` as orthogonality allows (Gram-Schmidt). When the hint is
// (nearly) parallel to the tangent or zero, falls back to frame_from_normal's
// choice so the result is always orthonormal and right-handed (b = n x t).
Frame frame_from_tangent_normal(const glm::vec3& tangent, const glm::vec3& normal_hint);

// Robust normalisation: returns `fallback` for zero, denormal, or non-finite input.
glm::vec3 safe_normalize(const glm::vec3& v, const glm::vec3& fallback = {0, 0, 1});

}  // namespace plumage
