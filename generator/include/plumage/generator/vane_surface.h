#pragma once
// The vane as a Catmull-Clark subdivision surface (DESIGN §3): a regular grid of
// control points, `columns` along the shaft by `rows` from the shaft out to the
// vane edge, evaluated on its limit surface with OpenSubdiv's Bfr. Boundary edges
// and corners are sharp (Sdc VTX_BOUNDARY_EDGE_AND_CORNER), so the limit surface
// reaches the cage's border: the edge along the shaft and the outer edge are the
// uniform cubic B-splines of the border rows, ending at the corner points.
//
// The domain is (u, v) in [0,1]^2: u along the shaft (0 = vane base, 1 = tip),
// v across the vane (0 = shaft, 1 = edge). Normals are oriented by `dorsal_sign`
// so that they point to the dorsal side whichever way the grid runs.
#include <memory>
#include <vector>

#include <glm/glm.hpp>

namespace plumage {

class VaneSurface {
 public:
  struct Sample {
    glm::dvec3 p;       // limit position
    glm::dvec3 du, dv;  // partial derivatives with respect to the domain (u, v)
    glm::dvec3 n;       // unit limit normal, dorsal
  };

  // cage[i * rows + j] is the control point of column i (along the shaft) and row j
  // (0 at the shaft). dorsal_sign = +1 when du x dv points dorsally, else -1.
  // Throws plumage::Error if the grid is smaller than 2 x 2 or OpenSubdiv rejects it.
  VaneSurface(int columns, int rows, std::vector<glm::dvec3> cage, double dorsal_sign);
  ~VaneSurface();
  VaneSurface(VaneSurface&&) noexcept;
  VaneSurface& operator=(VaneSurface&&) noexcept;

  // (u, v) are clamped to [0,1].
  Sample eval(double u, double v) const;

  int columns() const { return columns_; }
  int rows() const { return rows_; }
  const std::vector<glm::dvec3>& cage() const { return cage_; }

 private:
  struct Impl;
  int columns_, rows_;
  std::vector<glm::dvec3> cage_;
  double dorsal_sign_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plumage
