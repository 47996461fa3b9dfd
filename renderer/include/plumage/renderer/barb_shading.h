#pragma once
// How a barb hit is shaded: one model per shading mode (shading_mode.h), each an
// implementation of BarbShading in its own file — hair_shading.cpp,
// substructure_shading.cpp, explicit_shading.cpp, farfield_shading.cpp. A model
// turns a barb hit into the Bsdf (bsdf.h) the path integrator shades with; the
// shaft and the card are shaded alike in every mode (PathIntegrator).
//
// Adding a model: its file, its ShadingMode, its line in make_barb_shading, and
// the geometry the scene builds for it (BarbGeometry, shading_mode.h).
#include <memory>

#include <glm/glm.hpp>

#include "plumage/renderer/bsdf.h"
#include "plumage/renderer/fibre_material.h"
#include "plumage/renderer/shading_mode.h"
#include "plumage/renderer/surface_hit.h"

namespace plumage {

class Scene;

class BarbShading {
 public:
  virtual ~BarbShading() = default;
  virtual ShadingMode mode() const = 0;
  // The Bsdf of the barb hit `hit` (hit.kind == HitKind::Barb) seen from wo,
  // built in `slot`; it lives until the slot is reused.
  virtual const Bsdf& at(const SurfaceHit& hit, const glm::vec3& wo, BsdfSlot& slot) const = 0;
};

// What every model reads: the scene (its geometry and structure queries), the
// fibres' material, and whether MIS weighs BCSDF-sampled rays
// (LightSet::hit_by_sampled_rays). All must outlive the model.
struct ShadingContext {
  const Scene& scene;
  const FibreMaterial& material;
  bool pdf_needed = true;
};

// The model of the scene's shading mode. In farfield mode it fits (or reads from
// the cache) each vane's table for the material at the feather's centre.
std::unique_ptr<const BarbShading> make_barb_shading(const ShadingContext& context);

}  // namespace plumage
