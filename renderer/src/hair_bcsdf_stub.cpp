// TEMPORARY stand-in for the hair BCSDF (the bcsdf branch writes the real one,
// renderer/src/hair_bcsdf.cpp; delete this file when it lands on main). It keeps
// the hair_bcsdf.h API and its energy bookkeeping but scatters isotropically:
// f = A / pi^2, so the integral of f cos(theta_i) over the sphere (theta_i the
// longitudinal angle, cos = sqrt(1 - wi.x^2), the real BCSDF's convention) is the
// albedo A the absorption stands for. Enough to link and test the integrator.
#include <cmath>
#include <numbers>

#include "plumage/renderer/hair_bcsdf.h"

namespace plumage {
namespace {
constexpr float kPi = std::numbers::pi_v<float>;

// Chiang et al. 2016 eq. 9 denominator: sigma_a = (ln A / d(beta_n))^2.
float albedo_denominator(float beta_n) {
  const float b = beta_n;
  return 5.969f - 0.215f * b + 2.532f * b * b - 10.73f * b * b * b + 5.574f * b * b * b * b +
         0.245f * b * b * b * b * b;
}
}  // namespace

glm::vec3 sigma_a_from_melanin(float eumelanin, float pheomelanin) {
  // Chiang et al. 2016 §4.2: absorption per unit concentration of each pigment.
  const glm::vec3 eu{0.419f, 0.697f, 1.37f}, pheo{0.187f, 0.4f, 1.05f};
  return eumelanin * eu + pheomelanin * pheo;
}

glm::vec3 sigma_a_from_albedo(const glm::vec3& albedo, float beta_n) {
  glm::vec3 s;
  for (int i = 0; i < 3; ++i) {
    const float a = std::fmin(std::fmax(albedo[i], 1e-4f), 1.0f);
    const float x = std::log(a) / albedo_denominator(beta_n);
    s[i] = x * x;
  }
  return s;
}

HairBCSDF::HairBCSDF(const HairParams& params, float h) : p_(params), h_(h) {
  // Invert eq. 9 so the stand-in reflects the albedo the absorption was made from.
  for (int i = 0; i < 3; ++i)
    v_[i] = std::exp(-std::sqrt(std::fmax(p_.sigma_a[i], 0.0f)) * albedo_denominator(p_.beta_n));
  v_[3] = 0;
  for (int i = 0; i < 3; ++i) sin2k_alpha_[i] = cos2k_alpha_[i] = 0;
  s_ = 0;
  gamma_o_ = std::asin(std::fmin(std::fmax(h, -1.0f), 1.0f));
}

glm::vec3 HairBCSDF::f(const glm::vec3&, const glm::vec3&) const {
  return glm::vec3(v_[0], v_[1], v_[2]) / (kPi * kPi);
}

float HairBCSDF::pdf(const glm::vec3&, const glm::vec3&) const { return 1.0f / (4 * kPi); }

std::optional<BCSDFSample> HairBCSDF::sample(const glm::vec3& wo, const glm::vec2& u0,
                                             const glm::vec2& u1) const {
  // Uniform over the sphere.
  (void)u1;
  const float z = 1 - 2 * u0.x, r = std::sqrt(std::fmax(0.0f, 1 - z * z)), phi = 2 * kPi * u0.y;
  const glm::vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
  const float pdf_wi = pdf(wo, wi);
  if (!(pdf_wi > 0)) return std::nullopt;
  return BCSDFSample{wi, f(wo, wi), pdf_wi};
}

}  // namespace plumage
