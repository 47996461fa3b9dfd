#pragma once
// How a hit scatters light: the interface the path integrator shades through, in
// the manner of pbrt-v4's BxDFs (evaluate, sample, pdf). One object per hit, its
// outgoing direction wo fixed when it is made; every direction is a world-space
// unit vector pointing away from the hit.
//
// Implementations: DiffuseBsdf (the card, diffuse_bsdf.h), FibreBsdf (the hair
// BCSDF of one fibre, fibre_bsdf.h) and FarfieldBsdf (a vane's measured table,
// farfield_bsdf.h). Which one a barb hit gets is its shading model's choice
// (barb_shading.h).
#include <cstddef>
#include <new>
#include <optional>
#include <type_traits>
#include <utility>

#include <glm/glm.hpp>

#include "plumage/renderer/light_set.h"

namespace plumage {

// A direction sample(): wi, its throughput weight f cos / pdf and its pdf (0 when
// the implementation gives none: then no MIS weight is asked of it).
struct BsdfSample {
  glm::vec3 wi;
  glm::vec3 weight;
  float pdf;
};

class Bsdf {
 public:
  virtual ~Bsdf() = default;
  // f(wo, wi) times the projection cosine, and in *pdf the density sample() gives wi.
  virtual glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const = 0;
  // A direction for the four numbers u in [0,1); nothing when there is none.
  virtual std::optional<BsdfSample> sample(const glm::vec4& u) const = 0;
  // The density sample() gives wi.
  float pdf(const glm::vec3& wi) const {
    float p = 0;
    f_cos(wi, &p);
    return p;
  }
  // Weighs every light for the choice of light only: w[i] = lum(strength_i x
  // f cos(wi_i)) over the proxies, f cos exact or a cheaper approximation of it.
  // The environment's entry is the caller's (it has no single direction).
  virtual void estimate_weights(const LightProxies& lp, float* w) const;
  // Whether sample() follows f cos closely enough that a constant environment is
  // left to it alone (LightSet::sampled_count()).
  virtual bool samples_like_f_cos() const { return true; }
};

// Room on the stack for the one Bsdf a hit needs, so a path allocates nothing.
// emplace() destroys what the slot held and builds a T in its place.
class BsdfSlot {
 public:
  BsdfSlot() = default;
  BsdfSlot(const BsdfSlot&) = delete;
  BsdfSlot& operator=(const BsdfSlot&) = delete;
  ~BsdfSlot() { reset(); }

  template <class T, class... Args>
  T& emplace(Args&&... args) {
    static_assert(std::is_base_of_v<Bsdf, T>, "a BsdfSlot holds Bsdfs");
    static_assert(sizeof(T) <= kBytes && alignof(T) <= kAlign, "BsdfSlot: raise kBytes or kAlign for this Bsdf");
    reset();
    T* t = ::new (static_cast<void*>(bytes_)) T(std::forward<Args>(args)...);
    held_ = t;
    return *t;
  }
  void reset() {
    if (held_) held_->~Bsdf();
    held_ = nullptr;
  }

  static constexpr std::size_t kBytes = 640, kAlign = 16;

 private:
  alignas(kAlign) unsigned char bytes_[kBytes];
  Bsdf* held_ = nullptr;
};

}  // namespace plumage
