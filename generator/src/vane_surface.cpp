#include "plumage/generator/vane_surface.h"

#include <algorithm>
#include <cmath>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "plumage/common/error.h"
#include "plumage/common/frame.h"

namespace plumage {
namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

// One Bfr surface per cage face with its patch points prepared once, so that an
// evaluation is only the patch basis applied to a handful of points.
struct VaneSurface::Impl {
  std::vector<osd::Bfr::Surface<double>> faces;
  std::vector<std::vector<double>> patch_points;
};

VaneSurface::VaneSurface(int columns, int rows, std::vector<glm::dvec3> cage, double dorsal_sign)
    : columns_(columns), rows_(rows), cage_(std::move(cage)), dorsal_sign_(dorsal_sign < 0 ? -1.0 : 1.0) {
  if (columns_ < 2 || rows_ < 2 || cage_.size() != std::size_t(columns_) * rows_)
    throw Error("vane control cage must be a grid of at least 2 x 2 points (got " + std::to_string(columns_) +
                " x " + std::to_string(rows_) + " with " + std::to_string(cage_.size()) + " points)");

  // Quads (i,j) (i+1,j) (i+1,j+1) (i,j+1): the face's own (s,t) runs along u then v.
  const int nfaces = (columns_ - 1) * (rows_ - 1);
  std::vector<int> verts_per_face(nfaces, 4), face_verts;
  face_verts.reserve(4 * nfaces);
  for (int i = 0; i + 1 < columns_; ++i)
    for (int j = 0; j + 1 < rows_; ++j)
      face_verts.insert(face_verts.end(), {i * rows_ + j, (i + 1) * rows_ + j, (i + 1) * rows_ + j + 1,
                                           i * rows_ + j + 1});

  osd::Far::TopologyDescriptor desc;
  desc.numVertices = int(cage_.size());
  desc.numFaces = nfaces;
  desc.numVertsPerFace = verts_per_face.data();
  desc.vertIndicesPerFace = face_verts.data();
  osd::Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
  std::unique_ptr<osd::Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(osd::Sdc::SCHEME_CATMARK, sdc)));
  if (!refiner) throw Error("OpenSubdiv rejected the vane control cage");

  osd::Bfr::RefinerSurfaceFactory<> factory(*refiner);
  impl_ = std::make_unique<Impl>();
  impl_->faces.resize(nfaces);
  impl_->patch_points.resize(nfaces);
  const double* mesh = &cage_[0].x;  // glm::dvec3 is three packed doubles
  for (int f = 0; f < nfaces; ++f) {
    auto& s = impl_->faces[f];
    if (!factory.InitVertexSurface(f, &s))
      throw Error("OpenSubdiv found no limit surface for vane cage face " + std::to_string(f));
    impl_->patch_points[f].resize(std::size_t(s.GetNumPatchPoints()) * 3);
    s.PreparePatchPoints(mesh, 3, impl_->patch_points[f].data(), 3);
  }
}

VaneSurface::~VaneSurface() = default;
VaneSurface::VaneSurface(VaneSurface&&) noexcept = default;
VaneSurface& VaneSurface::operator=(VaneSurface&&) noexcept = default;

VaneSurface::Sample VaneSurface::eval(double u, double v) const {
  const double x = std::clamp(u, 0.0, 1.0) * (columns_ - 1), y = std::clamp(v, 0.0, 1.0) * (rows_ - 1);
  const int i = std::min(int(x), columns_ - 2), j = std::min(int(y), rows_ - 2);
  const int f = i * (rows_ - 1) + j;
  const double st[2] = {x - i, y - j};
  double P[3], Du[3], Dv[3];
  impl_->faces[f].Evaluate(st, impl_->patch_points[f].data(), 3, P, Du, Dv);
  Sample s;
  s.p = {P[0], P[1], P[2]};
  // Chain rule: the face's (s,t) covers 1/(columns-1) by 1/(rows-1) of the domain.
  s.du = glm::dvec3(Du[0], Du[1], Du[2]) * double(columns_ - 1);
  s.dv = glm::dvec3(Dv[0], Dv[1], Dv[2]) * double(rows_ - 1);
  const glm::dvec3 c = glm::cross(s.du, s.dv) * dorsal_sign_;
  const double len = glm::length(c);
  s.n = len > 0 && std::isfinite(len) ? c / len : glm::dvec3(0, 0, 1);
  return s;
}

}  // namespace plumage
