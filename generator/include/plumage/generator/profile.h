#pragma once
// A function of position along the vane (x in [0,1], 0 = end of the calamus,
// 1 = tip) given by knots and interpolated with a monotone cubic (Fritsch &
// Carlson 1980, "Monotone piecewise cubic interpolation", SIAM J. Numer. Anal.
// 17(2)): smooth, and it never overshoots the knots, so a width profile whose
// knots are all positive never goes negative between them.
#include <vector>

#include <glm/glm.hpp>

namespace plumage {

class Profile {
 public:
  Profile() = default;
  // knots: (x, y) with x strictly increasing, first x = 0, last x = 1
  // (validate_profile checks; the constructor assumes it).
  explicit Profile(std::vector<glm::dvec2> knots);

  double operator()(double x) const;   // x clamped to [0,1]
  double derivative(double x) const;   // dy/dx
  double max_value() const;
  double min_value() const;
  const std::vector<glm::dvec2>& knots() const { return knots_; }
  bool operator==(const Profile& o) const { return knots_ == o.knots_; }

 private:
  std::size_t segment(double x) const;
  std::vector<glm::dvec2> knots_;
  std::vector<double> slopes_;  // Fritsch-Carlson tangents at the knots
};

}  // namespace plumage
