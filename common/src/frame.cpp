#include "plumage/common/frame.h"

#include <cmath>

namespace plumage {

glm::vec3 safe_normalize(const glm::vec3& v, const glm::vec3& fallback) {
  const double len2 = double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z;
  if (!(len2 > 1e-30) || !std::isfinite(len2)) return fallback;
  return glm::vec3(glm::dvec3(v) / std::sqrt(len2));
}

Frame frame_from_normal(const glm::vec3& n_in) {
  const glm::vec3 n = safe_normalize(n_in);
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  Frame f;
  f.n = n;
  f.t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  f.b = glm::cross(f.n, f.t);
  return f;
}

Frame frame_from_tangent_normal(const glm::vec3& tangent, const glm::vec3& normal_hint) {
  const glm::vec3 t = safe_normalize(tangent, glm::vec3(1, 0, 0));
  glm::vec3 n = normal_hint - glm::dot(normal_hint, t) * t;
  const float len = glm::length(n);
  const float hint_len = glm::length(normal_hint);
  if (!(len > 1e-4f * std::fmax(hint_len, 1e-20f)) || !std::isfinite(len)) {
    // Hint useless: any normal orthogonal to t.
    const Frame g = frame_from_normal(t);
    n = g.t;
  } else {
    n /= len;
  }
  Frame f;
  f.t = t;
  f.n = n;
  f.b = glm::cross(n, t);
  return f;
}

}  // namespace plumage
