#pragma once
// Axis-aligned boxes: one type for every box in Plumage, in double (curve
// geometry, tight_bounds) and in float (the renderer's scene, camera framing and
// culling). A default box is empty (lo = +inf, hi = -inf), so extending it by a
// first point gives that point.
#include <limits>

#include <glm/glm.hpp>

namespace plumage {

template <class T>
struct BasicBounds3 {
  using Vec = glm::vec<3, T>;
  Vec lo{std::numeric_limits<T>::infinity()};
  Vec hi{-std::numeric_limits<T>::infinity()};

  void extend(const Vec& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const BasicBounds3& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  Vec centre() const { return T(0.5) * (lo + hi); }
  Vec size() const { return hi - lo; }
  // Corner c of 8: bit 0 picks hi.x over lo.x, bit 1 hi.y, bit 2 hi.z.
  Vec corner(int c) const { return {c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z}; }
};

using Bounds3 = BasicBounds3<double>;
using Bounds3f = BasicBounds3<float>;

}  // namespace plumage
