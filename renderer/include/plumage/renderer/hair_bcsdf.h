#pragma once
// The hair BCSDF: Marschner et al. 2003 as made practical for path tracing by
// d'Eon et al. 2011 and Chiang et al. 2016 (R, TT, TRT lobes plus a residual
// lobe, importance sampled with its exact pdf). DESIGN §6.
//
// Local frame (the fibre frame): +x along the fibre tangent; y and z span the
// normal plane. h in [-1,1] is the offset of the hit across the fibre, measured
// along +y, in units of the fibre radius, for the outgoing direction wo:
// h = sin(gamma_o). Precisely: with azimuths phi = atan2(y, z), the fibre normal
// at the hit has azimuth phi_o + gamma_o; when the frame's z is wo projected into
// the normal plane (a ray-facing ribbon), h is simply the hit's y / radius.
// Directions are unit vectors pointing away from the surface. RGB throughout
// (linear). Positive alpha_deg shifts R toward -x (the root, when +x points to
// the tip) and TT/TRT toward +x. Model, clamps and references: docs/hair-bcsdf.md.
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include <glm/glm.hpp>

namespace plumage {

namespace medulla {
class ExitShape;
}

struct HairParams {
  float beta_m = 0.3f;             // longitudinal roughness in (0,1]
  float beta_n = 0.3f;             // azimuthal roughness in (0,1]
  float alpha_deg = 2.0f;          // cuticle scale tilt (degrees)
  float eta = 1.55f;               // index of refraction of keratin
  glm::vec3 sigma_a{0.0f};         // absorption coefficient per unit radius (cross-section diameter 2)
  // The medulla: a scattering core of radius medulla_ratio (in fibre radii, [0, 1))
  // inside the cortex, whose absorption is sigma_a (docs/hair-bcsdf.md, "The
  // medulla"). Off (the clear fibre of Chiang et al. 2016, to the last bit) while
  // medulla_ratio is 0 or the core neither scatters nor absorbs.
  float medulla_ratio = 0.0f;
  glm::vec3 medulla_sigma_s{0.0f};  // scattering coefficient of the core per unit radius
  glm::vec3 medulla_sigma_a{0.0f};  // absorption coefficient of the core per unit radius
};

// Whether params' medulla changes anything (see HairParams).
inline bool has_medulla(const HairParams& p) {
  const glm::vec3 t = p.medulla_sigma_s + p.medulla_sigma_a;
  return p.medulla_ratio > 0.0f && (t.x > 0.0f || t.y > 0.0f || t.z > 0.0f);
}

// Throws plumage::Error naming the parameter and its valid range when params are
// unusable (non-finite, beta outside (0,1], eta < 1, |alpha_deg| > 45, sigma_a < 0,
// medulla_ratio outside [0, 1), a medulla coefficient < 0).
// `what` prefixes the message (for example "feather.fcurves:12: barb material").
void validate(const HairParams& params, std::string_view what = "hair BCSDF");

// The cosine that f is "without": cos of the longitudinal angle of w, i.e. the
// cosine to the fibre's normal plane, sqrt(1 - w.x^2). Integrate f * bcsdf_cos(wi).
// (1-s)(1+s) rather than 1-s^2: exact rounding near the tangent, where f ~ 1/cos.
inline float bcsdf_cos(const glm::vec3& w) {
  const float s = glm::clamp(w.x, -1.0f, 1.0f);
  return std::sqrt((1.0f - s) * (1.0f + s));
}

// Absorption from melanin concentrations (Chiang et al. 2016, eumelanin and pheomelanin).
// Concentrations are >= 0 (about 8 is black hair); throws plumage::Error otherwise.
glm::vec3 sigma_a_from_melanin(float eumelanin, float pheomelanin);
// Absorption that gives a target multiple-scattering albedo colour (Chiang et al. 2016 eq. 9).
// Albedo channels are clamped to [1e-4, 1] (a texture may hold exact 0); beta_n to
// [0.001, 1]; non-finite input throws plumage::Error.
glm::vec3 sigma_a_from_albedo(const glm::vec3& albedo, float beta_n);
// Absorption that makes one layer of fibres over a white card look `albedo` times
// the card: light crossing a fibre on its way down to the card and again on its
// way up keeps exp(-2 sigma_a c) = albedo, c the mean chord (radii) of the
// refracted path across the fibre at normal incidence, averaged over the offset h:
// c = eta (s sqrt(1 - s^2) + asin s), s = 1/eta (1.85 for keratin). Same clamps as
// sigma_a_from_albedo; eta must be >= 1. docs/hair-bcsdf.md, "Albedo to absorption".
glm::vec3 sigma_a_from_layer_albedo(const glm::vec3& albedo, float eta);
// The mean chord c above, in fibre radii.
float mean_normal_chord(float eta);

struct BCSDFSample {
  glm::vec3 wi;     // sampled incident direction (local frame)
  glm::vec3 f;      // BCSDF value f(wo, wi)
  float pdf;        // solid-angle pdf of wi
};

// A sampled direction and its throughput weight alone (no pdf): HairBCSDF::sample_throughput.
struct BCSDFThroughput {
  glm::vec3 wi;      // sampled incident direction (local frame)
  glm::vec3 weight;  // the estimator's f cos / pdf for it
};

class HairBCSDF {
 public:
  // Validates params (see validate()) and throws plumage::Error for a non-finite h;
  // h is clamped to [-1,1] and the betas to [0.001, 1] (docs/hair-bcsdf.md).
  HairBCSDF(const HairParams& params, float h);
  // The same, with the terms that depend on wo alone (the lobes' attenuations A_p)
  // computed once for `wo`: a shading point evaluates many wi for one wo.
  HairBCSDF(const HairParams& params, float h, const glm::vec3& wo);

  // f(wo, wi), without the |cos| factor (see bcsdf_cos). Finite and >= 0 for any
  // input; 0 for non-finite directions.
  glm::vec3 f(const glm::vec3& wo, const glm::vec3& wi) const;
  // Samples wi given wo with 4 uniform numbers in [0,1); returns nullopt only when
  // no direction can be produced. f and pdf are exactly f(wo, wi) and pdf(wo, wi).
  std::optional<BCSDFSample> sample(const glm::vec3& wo, const glm::vec2& u0, const glm::vec2& u1) const;
  // The same directions as sample() for the same numbers, weighed by the lobe-selection
  // estimator instead: A_p / w_p for the lobe p that was sampled (w_p its selection
  // probability), no evaluation of f and no pdf. Unbiased like sample()'s f cos / pdf
  // and equal to it in the mean over RGB (both are sum_p mean(A_p) there); cheaper, and for
  // paths whose BCSDF-sampled rays need no MIS weight (docs/hair-bcsdf.md, "Sampling").
  std::optional<BCSDFThroughput> sample_throughput(const glm::vec3& wo, const glm::vec2& u0,
                                                   const glm::vec2& u1) const;
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  // f(wo, wi) and, in *pdf, pdf(wo, wi), from one evaluation.
  glm::vec3 f_pdf(const glm::vec3& wo, const glm::vec3& wi, float* pdf) const;
  // f(wo, wi[k]) * bcsdf_cos(wi[k]) for many wi and one wo, the wo-dependent terms
  // computed once (next-event estimation weighs every light with it).
  void f_cos(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<glm::vec3> out) const;
  // An approximation of f_cos in float arithmetic (Bessel I0 by its asymptotic series
  // above 3.75, the azimuth by a polynomial atan2), cheaper: for weighing
  // choices (next-event estimation's light pick), never for radiance. Within 1 %
  // of f_cos where f_cos is not negligible (tests/hair_bcsdf_test.cpp).
  void f_cos_estimate(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<glm::vec3> out) const;
  // The same for n directions given as structure of arrays (x[k], y[k], z[k]),
  // writing channel c of direction k to out[c][k]: branch-free, so the loop over
  // directions vectorises (exp and atan2 by polynomials, no libm call).
  void f_cos_estimate(const glm::vec3& wo, std::size_t n, const float* x, const float* y, const float* z,
                      float* const out[3]) const;

  const HairParams& params() const { return p_; }
  float h() const { return h_; }

 private:
  HairParams p_;
  float h_;
  struct Eval {
    glm::dvec3 f;
    double pdf;
  };
  // Chiang et al. 2016 eqs. 3-6: A_p per lobe, the lobe selection weights, gamma_t.
  // Lobe 4 is the medulla's scattered light (0 without a medulla).
  static constexpr int kLobes = 5;
  struct Attenuation {
    glm::dvec3 A[kLobes];
    double weight[kLobes];  // lobe selection probabilities, A_p (mean over RGB) normalised
    double gamma_t;
  };
  Attenuation attenuation(double sin_o, double cos_o) const;
  // attenuation()'s A_p with the medulla (lobe 4 its scattered light).
  void medulla_attenuation(Attenuation& at, double F, double sin_gamma_t, double cos_gamma_t, double cos_t) const;
  // attenuation() for wo: the one computed at construction when wo is that one.
  Attenuation attenuation_for(const glm::vec3& wo, double sin_o, double cos_o) const;
  Eval eval(const glm::vec3& wo, const glm::vec3& wi) const;
  struct LobeDirection {
    glm::vec3 wi;
    int lobe;
    Attenuation at;  // the attenuation for wo that chose the lobe
  };
  // Sampling's direction, the lobe it came from and the attenuation that weighed the
  // lobes, into d (sample() and sample_throughput() share it); false for a
  // non-finite wo and when no lobe carries light.
  bool sample_direction(const glm::vec3& wo, const glm::vec2& u0, const glm::vec2& u1, LobeDirection& d) const;
  Eval eval(const glm::vec3& wo, const glm::vec3& wi, const Attenuation& at) const;

  // Precomputed per-instance terms (double: Mp subtracts terms of size 1/v).
  double v_[4];                                 // longitudinal variances of R, TT, TRT, residual
  double mp_log_norm_[4];                       // log of Mp's normalisation per lobe
  double mp_exp_[4];                            // e^{-2/v} per lobe (Mp sampling)
  double np_norm_;                              // 1 / (mass of the logistic on [-pi, pi])
  double np_lo_, np_mass_;                      // its CDF at -pi and that mass (Np sampling)
  double sin_shift_[3], cos_shift_[3];          // cuticle shifts of theta_o for R, TT, TRT
  double s_;                                    // logistic scale
  double gamma_o_, cos_gamma_o_;
  // The medulla's exit shape for (eta, medulla_ratio); null without a medulla.
  std::shared_ptr<const medulla::ExitShape> exit_;
  bool bound_ = false;  // constructed for one wo: bound_at_ holds its attenuation
  glm::vec3 bound_wo_{0};
  Attenuation bound_at_{};
};

}  // namespace plumage
