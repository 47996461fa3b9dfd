#pragma once
// The shaft (rachis and calamus) as a B-spline along a bent arc, with what the
// vanes need from it: position, tangent and the twisted lateral/dorsal frame at
// any arc length. Private to the generator.
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/bspline.h"
#include "plumage/generator/feather_params.h"

namespace plumage {

class Shaft {
 public:
  explicit Shaft(const ShaftParams& p);

  const BSpline3& curve() const { return table_.curve(); }
  double length() const { return table_.length(); }        // arc length of the B-spline
  double t_at(double s) const { return table_.t_at(s); }    // curve parameter at arc length s

  struct Frame {
    glm::dvec3 p, t;        // position, unit tangent
    glm::dvec3 lateral;     // unit, toward the right vane (+X when the shaft runs +Y)
    glm::dvec3 dorsal;      // unit, lateral x t (+Z for a flat feather)
  };
  // Frame at arc length s, rotated about the tangent by twist_rad.
  Frame frame(double s, double twist_rad = 0) const;

 private:
  ArcLengthTable table_;
};

}  // namespace plumage
