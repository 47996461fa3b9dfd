#pragma once
// The hair BCSDF: Marschner et al. 2003 as made practical for path tracing by
// d'Eon et al. 2011 and Chiang et al. 2016 (R, TT, TRT lobes plus a residual
// lobe, importance sampled with its exact pdf). DESIGN §6.
//
// Local frame (the fibre frame): +x along the fibre tangent; y and z span the
// normal plane. h in [-1,1] is the offset of the hit across the fibre, measured
// along +y, in units of the fibre radius, for the outgoing direction wo:
// h = sin(gamma_o). Directions are unit vectors pointing away from the surface.
// RGB throughout (linear).
#include <optional>

#include <glm/glm.hpp>

namespace plumage {

struct HairParams {
  float beta_m = 0.3f;             // longitudinal roughness in (0,1]
  float beta_n = 0.3f;             // azimuthal roughness in (0,1]
  float alpha_deg = 2.0f;          // cuticle scale tilt (degrees)
  float eta = 1.55f;               // index of refraction of keratin
  glm::vec3 sigma_a{0.0f};         // absorption coefficient per unit radius (cross-section diameter 2)
};

// Absorption from melanin concentrations (Chiang et al. 2016, eumelanin and pheomelanin).
glm::vec3 sigma_a_from_melanin(float eumelanin, float pheomelanin);
// Absorption that gives a target multiple-scattering albedo colour (Chiang et al. 2016 eq. 9).
glm::vec3 sigma_a_from_albedo(const glm::vec3& albedo, float beta_n);

struct BCSDFSample {
  glm::vec3 wi;     // sampled incident direction (local frame)
  glm::vec3 f;      // BCSDF value f(wo, wi)
  float pdf;        // solid-angle pdf of wi
};

class HairBCSDF {
 public:
  HairBCSDF(const HairParams& params, float h);

  // f(wo, wi), without the |cos| factor.
  glm::vec3 f(const glm::vec3& wo, const glm::vec3& wi) const;
  // Samples wi given wo with 4 uniform numbers in [0,1); returns nullopt only when
  // no direction can be produced. f and pdf are exactly f(wo, wi) and pdf(wo, wi).
  std::optional<BCSDFSample> sample(const glm::vec3& wo, const glm::vec2& u0, const glm::vec2& u1) const;
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;

  const HairParams& params() const { return p_; }
  float h() const { return h_; }

 private:
  HairParams p_;
  float h_;
  // Precomputed per-instance terms (variances, shifts, ...) live here.
  float v_[4];
  float sin2k_alpha_[3], cos2k_alpha_[3];
  float s_;
  float gamma_o_;
};

}  // namespace plumage
