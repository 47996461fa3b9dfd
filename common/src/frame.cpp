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
  Frame f;
  f.t = safe_normalize(tangent, glm::vec3(1, 0, 0));
  // Gram-Schmidt in double: a hint at a grazing angle to the tangent loses about
  // -log10(angle) digits to cancellation, which float cannot spare. The float
  // tangent is renormalised in double, since its own rounding (|t|^2 - 1 ~ 1e-7)
  // would otherwise leak into n at the same amplification.
  const glm::dvec3 t = glm::normalize(glm::dvec3(f.t));
  const glm::dvec3 h(safe_normalize(normal_hint, glm::vec3(0)));
  const glm::dvec3 n = h - glm::dot(h, t) * t;
  const double len = glm::length(n);
  // Below ~1e-4 rad the hint no longer says which way is up (and a zero, NaN or
  // infinite hint says nothing): any normal orthogonal to t will do.
  f.n = len > 1e-4 ? glm::vec3(n / len) : frame_from_normal(f.t).t;
  f.b = glm::cross(f.n, f.t);
  return f;
}

}  // namespace plumage
