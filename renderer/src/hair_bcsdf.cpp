// The hair BCSDF of Chiang et al. 2016 (Marschner et al. 2003 lobes, d'Eon et al.
// 2011 longitudinal term), written from the papers. Scalar terms: hair_terms.h.
#include "plumage/renderer/hair_bcsdf.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>
#include <sstream>
#include <string>

#include "fast_atan2.h"
#include "hair_terms.h"
#include "medulla_terms.h"
#include "plumage/common/error.h"
#include "plumage/common/finite.h"

namespace plumage {

namespace {


constexpr int kChiangLobes = 4;      // R, TT, TRT and the residual p >= 3 (then the medulla's)
constexpr double kBetaMin = 1e-3;    // below this the lobes are narrower than float directions resolve
constexpr double kMaxAlphaDeg = 45;  // 4 alpha (TRT) stays within a half turn
constexpr float kMinAlbedo = 1e-4f;  // ln(0) would make sigma_a infinite

[[noreturn]] void fail(std::string_view what, std::string_view name, double value,
                       std::string_view fix) {
  std::ostringstream msg;
  msg << what << ": " << name << " = " << value << " " << fix;
  throw Error(msg.str());
}


double clamp_beta(double beta) { return std::clamp(beta, kBetaMin, 1.0); }

double mean(const glm::dvec3& c) { return (c.x + c.y + c.z) / 3.0; }

// Longitude of a direction in the fibre frame, as (sin, cos) with cos >= 0.
struct Longitude {
  double sin, cos;
};
Longitude longitude(const glm::vec3& w) {
  const double s = std::clamp(static_cast<double>(w.x), -1.0, 1.0);
  return {s, std::sqrt(std::max(0.0, 1.0 - s * s))};
}

// Azimuth in the normal plane, phi = atan2(y, z) (0 for directions along the tangent).
double azimuth(const glm::vec3& w) { return std::atan2(double(w.y), double(w.z)); }

}  // namespace

void validate(const HairParams& p, std::string_view what) {
  const auto roughness = [&](const char* name, float beta) {
    if (!(beta > 0.0f && beta <= 1.0f))
      fail(what, name, beta, "is outside (0, 1]; use a roughness between 0.001 and 1");
  };
  roughness("beta_m", p.beta_m);
  roughness("beta_n", p.beta_n);
  if (!(std::abs(p.alpha_deg) <= kMaxAlphaDeg))
    fail(what, "alpha_deg", p.alpha_deg, "is outside [-45, 45]; cuticle tilts are a few degrees (2 is typical)");
  if (!(p.eta >= 1.0f && std::isfinite(p.eta)))
    fail(what, "eta", p.eta, "is not a finite index of refraction >= 1; keratin is 1.55");
  for (int c = 0; c < 3; ++c)
    if (!(p.sigma_a[c] >= 0.0f && std::isfinite(p.sigma_a[c])))
      fail(what, "sigma_a[" + std::to_string(c) + "]", p.sigma_a[c],
           "is not a finite absorption >= 0; use 0 for white, a few units for dark fibres");
  if (!(p.medulla_ratio >= 0.0f && p.medulla_ratio < 1.0f))
    fail(what, "medulla_ratio", p.medulla_ratio,
         "is outside [0, 1); the medulla's radius is a fraction of the fibre's (0 for none, about 0.7 in white barbs)");
  for (int c = 0; c < 3; ++c) {
    if (!(p.medulla_sigma_s[c] >= 0.0f && std::isfinite(p.medulla_sigma_s[c])))
      fail(what, "medulla_sigma_s[" + std::to_string(c) + "]", p.medulla_sigma_s[c],
           "is not a finite scattering coefficient >= 0; use 0 for a clear core, tens for a white one");
    if (!(p.medulla_sigma_a[c] >= 0.0f && std::isfinite(p.medulla_sigma_a[c])))
      fail(what, "medulla_sigma_a[" + std::to_string(c) + "]", p.medulla_sigma_a[c],
           "is not a finite absorption >= 0; use 0 for a core that only scatters");
  }
}

// Chiang et al. 2016 §4.1: linear combination of the eumelanin and pheomelanin
// absorption spectra of d'Eon et al. 2011 (per unit radius).
glm::vec3 sigma_a_from_melanin(float eumelanin, float pheomelanin) {
  const auto check = [](const char* name, float c) {
    if (!(c >= 0.0f && std::isfinite(c)))
      fail("melanin", name, c, "is not a finite concentration >= 0; about 8 gives black hair");
  };
  check("eumelanin", eumelanin);
  check("pheomelanin", pheomelanin);
  const glm::vec3 sigma_eumelanin(0.419f, 0.697f, 1.37f);
  const glm::vec3 sigma_pheomelanin(0.187f, 0.4f, 1.05f);
  return eumelanin * sigma_eumelanin + pheomelanin * sigma_pheomelanin;
}

// Chiang et al. 2016 eq. 9: sigma_a = (ln A / (5.969 - 0.215 bn + 2.532 bn^2 -
// 10.73 bn^3 + 5.574 bn^4 + 0.245 bn^5))^2; the denominator is >= 3.375 on (0,1].
glm::vec3 sigma_a_from_albedo(const glm::vec3& albedo, float beta_n) {
  if (!all_finite(albedo)) fail("albedo", "colour", albedo.x + albedo.y + albedo.z, "is not finite");
  if (!std::isfinite(beta_n)) fail("albedo", "beta_n", beta_n, "is not finite");
  const double b = clamp_beta(beta_n);
  const double denom =
      5.969 - 0.215 * b + 2.532 * b * b - 10.73 * std::pow(b, 3) + 5.574 * std::pow(b, 4) +
      0.245 * std::pow(b, 5);
  glm::vec3 sigma;
  for (int c = 0; c < 3; ++c) {
    const double a = std::clamp(albedo[c], kMinAlbedo, 1.0f);
    const double t = std::log(a) / denom;
    sigma[c] = static_cast<float>(t * t);
  }
  return sigma;
}

float mean_normal_chord(float eta) {
  if (!(eta >= 1.0f) || !std::isfinite(eta)) fail("albedo", "eta", eta, "is not a finite index of refraction >= 1");
  const double s = 1.0 / double(eta);
  return float(double(eta) * (s * std::sqrt(1.0 - s * s) + std::asin(s)));
}

glm::vec3 sigma_a_from_layer_albedo(const glm::vec3& albedo, float eta) {
  if (!all_finite(albedo)) fail("albedo", "colour", albedo.x + albedo.y + albedo.z, "is not finite");
  const double path = 2.0 * double(mean_normal_chord(eta));  // down to the card and back up
  glm::vec3 sigma;
  for (int c = 0; c < 3; ++c) sigma[c] = float(-std::log(double(std::clamp(albedo[c], kMinAlbedo, 1.0f))) / path);
  return sigma;
}

HairBCSDF::HairBCSDF(const HairParams& params, float h) : p_(params) {
  validate(params);
  if (!std::isfinite(h)) fail("hair BCSDF", "h", h, "is not finite; the renderer computed a bad fibre offset");
  h_ = std::clamp(h, -1.0f, 1.0f);
  p_.beta_m = static_cast<float>(clamp_beta(params.beta_m));
  p_.beta_n = static_cast<float>(clamp_beta(params.beta_n));

  // The lobe terms depend on beta_m, beta_n and alpha only, which rarely change
  // between the shading points of one thread: keep the last set computed.
  struct LobeTerms {
    float beta_m = -1, beta_n = -1, alpha_deg = 0;
    double v[4], log_norm[4], mp_exp[4], s, np_norm, np_lo, np_mass, sin_shift[3], cos_shift[3];
  };
  thread_local LobeTerms last;
  if (last.beta_m != p_.beta_m || last.beta_n != p_.beta_n || last.alpha_deg != p_.alpha_deg) {
    LobeTerms t;
    t.beta_m = p_.beta_m;
    t.beta_n = p_.beta_n;
    t.alpha_deg = p_.alpha_deg;
    // Chiang et al. 2016 §4.2: the TT lobe is half as wide as R, TRT and the residual twice.
    const double v = hair::variance_from_beta_m(p_.beta_m);
    t.v[0] = v;
    t.v[1] = 0.25 * v;
    t.v[2] = 4.0 * v;
    t.v[3] = 4.0 * v;
    for (int p = 0; p < 3; ++p) t.log_norm[p] = hair::longitudinal_mp_log_norm(t.v[p]);
    t.log_norm[3] = t.log_norm[2];
    for (int p = 0; p < 4; ++p) t.mp_exp[p] = std::exp(-2.0 / t.v[p]);  // sampling's e^{-2/v}
    t.s = hair::logistic_scale_from_beta_n(p_.beta_n);
    t.np_norm = hair::trimmed_logistic_norm(t.s);
    t.np_lo = hair::trimmed_logistic_cdf_lo(t.s);  // sampling's F(-pi) and mass on [-pi, pi]
    t.np_mass = std::tanh(kPi / (2.0 * t.s));
    // Marschner et al. 2003 Table 1 shifts, in the 2^k alpha form: R by 2 alpha toward
    // the root, TT by alpha and TRT by 4 alpha toward the tip. The shift is applied to
    // theta_o: the lobe is centred on theta_i = -(theta_o + shift). Double-angle formulas
    // give 2 alpha and 4 alpha from one sin/cos.
    const double alpha = double(p_.alpha_deg) * kPi / 180.0;
    const double s1 = std::sin(alpha), c1 = std::cos(alpha);
    const double s2 = 2.0 * s1 * c1, c2 = c1 * c1 - s1 * s1;
    const double s4 = 2.0 * s2 * c2, c4 = c2 * c2 - s2 * s2;
    t.sin_shift[0] = s2;
    t.cos_shift[0] = c2;
    t.sin_shift[1] = -s1;
    t.cos_shift[1] = c1;
    t.sin_shift[2] = -s4;
    t.cos_shift[2] = c4;
    last = t;
  }
  std::copy(last.v, last.v + 4, v_);
  std::copy(last.log_norm, last.log_norm + 4, mp_log_norm_);
  std::copy(last.mp_exp, last.mp_exp + 4, mp_exp_);
  s_ = last.s;
  np_norm_ = last.np_norm;
  np_lo_ = last.np_lo;
  np_mass_ = last.np_mass;
  std::copy(last.sin_shift, last.sin_shift + 3, sin_shift_);
  std::copy(last.cos_shift, last.cos_shift + 3, cos_shift_);
  gamma_o_ = std::asin(double(h_));
  cos_gamma_o_ = std::sqrt(std::max(0.0, 1.0 - double(h_) * h_));
  if (has_medulla(p_)) exit_ = medulla::exit_shape(p_.eta, p_.medulla_ratio);
}

HairBCSDF::HairBCSDF(const HairParams& params, float h, const glm::vec3& wo) : HairBCSDF(params, h) {
  if (!all_finite(wo)) return;
  const Longitude o = longitude(wo);
  bound_at_ = attenuation(o.sin, o.cos);
  bound_wo_ = wo;
  bound_ = true;
}

HairBCSDF::Attenuation HairBCSDF::attenuation_for(const glm::vec3& wo, double sin_o, double cos_o) const {
  if (bound_ && wo == bound_wo_) return bound_at_;
  return attenuation(sin_o, cos_o);
}

// Chiang et al. 2016 eqs. 3-6 (after Marschner et al. 2003 §4.2): A_0 = F,
// A_p = (1-F)^2 F^{p-1} T^p, residual A_3 = A_2 F T / (1 - F T); F is the Fresnel
// reflectance at cos(theta_o) cos(gamma_o), T the absorption along one internal
// chord, of length 2 cos(gamma_t) / cos(theta_t) radii.
HairBCSDF::Attenuation HairBCSDF::attenuation(double sin_o, double cos_o) const {
  Attenuation at;
  const double eta = p_.eta;
  // Bravais' effective index eta' = sqrt(eta^2 - sin^2 theta_o) / cos theta_o, written so
  // that theta_o = +-pi/2 and eta = 1 do not divide by zero.
  const double root = std::sqrt(std::max(0.0, eta * eta - sin_o * sin_o));
  const double sin_gamma_t = root > 0.0 ? std::clamp(double(h_) * cos_o / root, -1.0, 1.0) : 0.0;
  at.gamma_t = std::asin(sin_gamma_t);
  const double cos_gamma_t = std::sqrt(std::max(0.0, 1.0 - sin_gamma_t * sin_gamma_t));
  const double sin_t = sin_o / eta;
  const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t * sin_t));
  const double F = hair::fresnel_dielectric(cos_o * cos_gamma_o_, eta);
  if (exit_) {
    medulla_attenuation(at, F, sin_gamma_t, cos_gamma_t, cos_t);
  } else {
    const double chord = 2.0 * cos_gamma_t / std::max(cos_t, 1e-12);
    const glm::dvec3 T(std::exp(-double(p_.sigma_a.x) * chord), std::exp(-double(p_.sigma_a.y) * chord),
                       std::exp(-double(p_.sigma_a.z) * chord));
    at.A[0] = glm::dvec3(F);
    at.A[1] = (1.0 - F) * (1.0 - F) * T;
    at.A[2] = at.A[1] * F * T;
    for (int c = 0; c < 3; ++c) {
      const double loss = 1.0 - F * T[c];
      at.A[3][c] = loss > 0.0 ? at.A[2][c] * F * T[c] / loss : 0.0;
    }
    at.A[4] = glm::dvec3(0.0);
  }
  double total = 0.0;
  for (int p = 0; p < kLobes; ++p) total += mean(at.A[p]);
  for (int p = 0; p < kLobes; ++p) at.weight[p] = total > 0.0 ? mean(at.A[p]) / total : 0.0;
  return at;
}

// The double cylinder (docs/hair-bcsdf.md, "The medulla"; after Yan et al. 2015):
// each internal chord at closest approach |sin gamma_t| to the axis crosses the
// core over 2 l = 2 sqrt(k^2 - sin^2 gamma_t) of it and the cortex over the rest,
// so the unscattered lobes keep T = T_cortex T_core per chord. What the core
// stops, summed over the internal reflections, is
//   (1 - F) sqrt(T_cortex) (1 - T_core) / (1 - F T),
// of which escape_albedo(sigma_s / sigma_t) leaves the core and
// exp(-sigma_a (1 - k)) crosses the cortex on the way out: A_4, the medulla lobe.
// Without absorption the five A_p sum to 1.
void HairBCSDF::medulla_attenuation(Attenuation& at, double F, double sin_gamma_t, double cos_gamma_t,
                                    double cos_t) const {
  const double k = p_.medulla_ratio;
  const double l = medulla::half_chord(sin_gamma_t, k);
  const double inv_cos_t = 1.0 / std::max(cos_t, 1e-12);
  const double cortex_half = std::max(0.0, cos_gamma_t - l) * inv_cos_t;  // one of the chord's two cortex pieces
  const double core = 2.0 * l * inv_cos_t;
  at.A[0] = glm::dvec3(F);
  for (int c = 0; c < 3; ++c) {
    const double sigma_a = p_.sigma_a[c];
    const double sigma_t = double(p_.medulla_sigma_s[c]) + double(p_.medulla_sigma_a[c]);
    const double tc_half = std::exp(-sigma_a * cortex_half);
    const double tm = std::exp(-sigma_t * core);
    const double T = tc_half * tc_half * tm;
    at.A[1][c] = (1.0 - F) * (1.0 - F) * T;
    at.A[2][c] = at.A[1][c] * F * T;
    const double loss = 1.0 - F * T;
    at.A[3][c] = loss > 0.0 ? at.A[2][c] * F * T / loss : 0.0;
    const double caught = loss > 0.0 ? (1.0 - F) * tc_half * (1.0 - tm) / loss : 0.0;
    const double alpha = sigma_t > 0.0 ? double(p_.medulla_sigma_s[c]) / sigma_t : 0.0;
    at.A[4][c] = caught * medulla::escape_albedo(alpha) * std::exp(-sigma_a * (1.0 - k));
  }
}

// Chiang et al. 2016 eq. 2: f = sum_p Mp Ap Np / cos(theta_i); the pdf of their §4.3
// sampling is sum_p w_p Mp Np (Mp Np is a density over solid angle).
HairBCSDF::Eval HairBCSDF::eval(const glm::vec3& wo, const glm::vec3& wi) const {
  if (!all_finite(wo) || !all_finite(wi)) return {glm::dvec3(0.0), 0.0};
  const Longitude o = longitude(wo);
  return eval(wo, wi, attenuation_for(wo, o.sin, o.cos));
}

HairBCSDF::Eval HairBCSDF::eval(const glm::vec3& wo, const glm::vec3& wi, const Attenuation& at) const {
  const Longitude o = longitude(wo), i = longitude(wi);
  // phi_i - phi_o from the normal-plane projections: one atan2 instead of two.
  const double phi = std::atan2(double(wi.y) * wo.z - double(wi.z) * wo.y,
                                double(wi.z) * wo.z + double(wi.y) * wo.y);

  glm::dvec3 f(0.0);
  double pdf = 0.0;
  for (int p = 0; p < 3; ++p) {
    const double sin_op = o.sin * cos_shift_[p] + o.cos * sin_shift_[p];
    const double cos_op = o.cos * cos_shift_[p] - o.sin * sin_shift_[p];
    const double mp = hair::longitudinal_mp(i.sin, i.cos, sin_op, cos_op, v_[p], mp_log_norm_[p]);
    const double np = hair::trimmed_logistic(
        hair::wrap_angle(phi - hair::azimuthal_shift(p, gamma_o_, at.gamma_t)), s_, np_norm_);
    f += at.A[p] * (mp * np);
    pdf += at.weight[p] * (mp * np);
  }
  // The residual lobe: unshifted, azimuthally uniform (Chiang et al. 2016 §4.1).
  const double mp3 = hair::longitudinal_mp(i.sin, i.cos, o.sin, o.cos, v_[3], mp_log_norm_[3]);
  f += at.A[3] * (mp3 / (2.0 * kPi));
  pdf += at.weight[3] * (mp3 / (2.0 * kPi));
  if (exit_) {
    // The medulla lobe: its exit shape over sin(theta_i) and the diffuse cylinder's azimuth.
    const double g = exit_->pdf(i.sin) * medulla::lambertian_azimuth(phi);
    f += at.A[4] * g;
    pdf += at.weight[4] * g;
  }

  f = i.cos > 0.0 ? f / i.cos : glm::dvec3(0.0);
  // pdf >= w_p Mp Np >= f cos / 3 per channel; flush what float would turn into f > 0, pdf = 0.
  if (!(float(pdf) > 0.0f) || !std::isfinite(float(pdf))) return {glm::dvec3(0.0), 0.0};
  return {f, pdf};
}

glm::vec3 HairBCSDF::f(const glm::vec3& wo, const glm::vec3& wi) const {
  return glm::vec3(eval(wo, wi).f);
}

float HairBCSDF::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
  return static_cast<float>(eval(wo, wi).pdf);
}

glm::vec3 HairBCSDF::f_pdf(const glm::vec3& wo, const glm::vec3& wi, float* pdf) const {
  const Eval e = eval(wo, wi);
  *pdf = static_cast<float>(e.pdf);
  return glm::vec3(e.f);
}

void HairBCSDF::f_cos(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<glm::vec3> out) const {
  if (!all_finite(wo)) {
    std::fill(out.begin(), out.end(), glm::vec3(0));
    return;
  }
  const Longitude o = longitude(wo);
  const Attenuation at = attenuation_for(wo, o.sin, o.cos);
  for (std::size_t k = 0; k < wi.size(); ++k)
    out[k] = all_finite(wi[k]) ? glm::vec3(eval(wo, wi[k], at).f) * bcsdf_cos(wi[k]) : glm::vec3(0);
}

namespace {

// The estimate's scalar pieces, written without branches (each side computed,
// then selected) and without libm calls, so that a loop over directions
// vectorises with the baseline instruction set.

// e^x within a few 1e-6 relative, for x in float's normal range (clamped there:
// e^-1000 comes out as about 1e-38, not 0). 2^t = 2^n 2^f, n the nearest integer,
// 2^f by its Taylor series in f ln 2 to degree 5 (|f| <= 1/2).
inline float exp_approx(float x) {
  const float t = std::min(std::max(x * 1.44269504f, -126.0f), 126.0f);
  const float n = (t + 0x1.8p23f) - 0x1.8p23f;  // round to nearest (|t| < 2^22)
  const float f = t - n;
  const float p =
      1.0f + f * (0.693147181f + f * (0.240226507f + f * (0.0555041087f + f * (0.00961812911f + f * 0.00133335581f))));
  return p * std::bit_cast<float>((std::int32_t(n) + 127) << 23);
}

// Mp of d'Eon et al. 2011 eq. 7 in float: I0 by its polynomial below 3.75 and
// above by the asymptotic series e^a / sqrt(2 pi a) (1 + 1/(8a) + 9/(128 a^2))
// (A&S 9.7.1; within 0.2 % from 3.75 on).
inline float mp_approx(float sin_i, float cos_i, float sin_o, float cos_o, float inv_v, float log_norm) {
  const float a = std::fabs(cos_i * cos_o) * inv_v, b = sin_i * sin_o * inv_v;
  const bool small = a < 3.75f;
  const float t = a * (1.0f / 3.75f), t2 = t * t;
  const float i0 = 1.0f + t2 * (3.5156229f + t2 * (3.0899424f + t2 * (1.2067492f + t2 * (0.2659732f +
                   t2 * (0.0360768f + t2 * 0.0045813f)))));
  const float al = std::max(a, 3.75f), r = 1.0f / al;
  const float series = (1.0f + r * (0.125f + 0.0703125f * r)) / std::sqrt(6.2831853f * al);
  return exp_approx(log_norm - b + (small ? 0.0f : a)) * (small ? i0 : series);
}

// x wrapped into [-pi, pi].
inline float wrap_approx(float x) {
  constexpr float k2Pi = 6.2831853f;
  const float n = (x * (1.0f / k2Pi) + 0x1.8p23f) - 0x1.8p23f;
  return x - k2Pi * n;
}

// The estimate's loop over directions, its per-wo terms as arguments (a free
// function of plain pointers: GCC vectorises it, not the same loop inside the member).
void estimate_kernel(std::size_t n, const float* x, const float* y, const float* z, float* __restrict out_r,
                     float* __restrict out_g, float* __restrict out_b, const float* sin_op, const float* cos_op,
                     const float* inv_v, const float* log_norm, const float* shift, const float (*A)[3], float inv_s,
                     float np_scale, float woy, float woz) {
  constexpr float kMax = std::numeric_limits<float>::max();
  for (std::size_t k = 0; k < n; ++k) {
    const float wx = x[k], wy = y[k], wz = z[k];
    const bool ok = (std::fabs(wx) <= kMax) & (std::fabs(wy) <= kMax) & (std::fabs(wz) <= kMax);  // & keeps it branch-free
    const float sin_i = std::min(std::max(wx, -1.0f), 1.0f), cos_i = std::sqrt((1.0f - sin_i) * (1.0f + sin_i));
    const float phi = atan2_approx(wy * woz - wz * woy, wz * woz + wy * woy);
    // Mp Np of lobe p (written out per lobe: the vectoriser wants no inner loop).
    const auto lobe = [&](int p) {
      const float mp = mp_approx(sin_i, cos_i, sin_op[p], cos_op[p], inv_v[p], log_norm[p]);
      const float e = exp_approx(-std::fabs(wrap_approx(phi - shift[p])) * inv_s);
      return mp * (e / ((1.0f + e) * (1.0f + e)) * np_scale);
    };
    const float g0 = lobe(0), g1 = lobe(1), g2 = lobe(2);
    const float g3 = mp_approx(sin_i, cos_i, sin_op[3], cos_op[3], inv_v[3], log_norm[3]) * 0.15915494f;
    // f cos(theta_i) = sum_p Mp Ap Np: the 1/cos(theta_i) of f cancels.
    const float fr = A[0][0] * g0 + A[1][0] * g1 + A[2][0] * g2 + A[3][0] * g3;
    const float fg = A[0][1] * g0 + A[1][1] * g1 + A[2][1] * g2 + A[3][1] * g3;
    const float fb = A[0][2] * g0 + A[1][2] * g1 + A[2][2] * g2 + A[3][2] * g3;
    out_r[k] = ok ? fr : 0.0f;
    out_g[k] = ok ? fg : 0.0f;
    out_b[k] = ok ? fb : 0.0f;
  }
}

}  // namespace

void HairBCSDF::f_cos_estimate(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<glm::vec3> out) const {
  const std::size_t n = wi.size();
  std::vector<float> soa(6 * n);
  float* in = soa.data();
  for (std::size_t k = 0; k < n; ++k) {
    in[k] = wi[k].x;
    in[n + k] = wi[k].y;
    in[2 * n + k] = wi[k].z;
  }
  float* const channels[3] = {in + 3 * n, in + 4 * n, in + 5 * n};
  f_cos_estimate(wo, n, in, in + n, in + 2 * n, channels);
  for (std::size_t k = 0; k < n; ++k) out[k] = {channels[0][k], channels[1][k], channels[2][k]};
}

void HairBCSDF::f_cos_estimate(const glm::vec3& wo, std::size_t n, const float* x, const float* y, const float* z,
                               float* const out[3]) const {
  float* __restrict out_r = out[0];
  float* __restrict out_g = out[1];
  float* __restrict out_b = out[2];
  if (!all_finite(wo)) {
    std::fill(out_r, out_r + n, 0.0f);
    std::fill(out_g, out_g + n, 0.0f);
    std::fill(out_b, out_b + n, 0.0f);
    return;
  }
  const Longitude o = longitude(wo);
  const Attenuation at = attenuation_for(wo, o.sin, o.cos);
  float sin_op[4], cos_op[4], inv_v[4], log_norm[4], shift[3], A[4][3];
  for (int p = 0; p < kChiangLobes; ++p) {
    inv_v[p] = float(1.0 / v_[p]);
    log_norm[p] = float(mp_log_norm_[p]);
    for (int c = 0; c < 3; ++c) A[p][c] = float(at.A[p][c]);
  }
  for (int p = 0; p < 3; ++p) {
    sin_op[p] = float(o.sin * cos_shift_[p] + o.cos * sin_shift_[p]);
    cos_op[p] = float(o.cos * cos_shift_[p] - o.sin * sin_shift_[p]);
    shift[p] = float(hair::azimuthal_shift(p, gamma_o_, at.gamma_t));
  }
  sin_op[3] = float(o.sin);  // the residual lobe is not shifted
  cos_op[3] = float(o.cos);
  // The trimmed logistic e / (s (1 + e)^2) norm with e = exp(-|x| / s).
  const float inv_s = float(1.0 / s_), np_scale = float(np_norm_ / s_);
  estimate_kernel(n, x, y, z, out_r, out_g, out_b, sin_op, cos_op, inv_v, log_norm, shift, A, inv_s, np_scale, wo.y,
                  wo.z);
  if (!exit_) return;
  // The medulla lobe, with its azimuth's angle from atan2_approx (within 1e-5 rad):
  // like the four above, an estimate for the choice of light only.
  const glm::vec3 As(at.A[4]);
  const float woy = wo.y, woz = wo.z, wo_len = std::sqrt(woy * woy + woz * woz);
  for (std::size_t k = 0; k < n; ++k) {
    if (!(std::isfinite(x[k]) && std::isfinite(y[k]) && std::isfinite(z[k]))) continue;
    const double sin_i = std::clamp(double(x[k]), -1.0, 1.0);
    const float dot = z[k] * woz + y[k] * woy, cross = std::fabs(y[k] * woz - z[k] * woy);
    const float len = wo_len * std::sqrt(y[k] * y[k] + z[k] * z[k]);
    // N(phi) = ((pi - |phi|) cos phi + sin |phi|) / 8 (medulla_terms.h), phi from its cosine and sine.
    const float az = len > 0.0f ? std::max(0.0f, ((kPiF - atan2_approx(cross, dot)) * dot + cross) / len * 0.125f) : 0.0f;
    const float g = float(exit_->pdf(sin_i)) * az;
    out_r[k] += As.x * g;
    out_g[k] += As.y * g;
    out_b[k] += As.z * g;
  }
}

// Chiang et al. 2016 §4.3: pick a lobe by its weight, sample theta_i from its Mp and
// the azimuth from its trimmed logistic (uniform for the residual).
bool HairBCSDF::sample_direction(const glm::vec3& wo, const glm::vec2& u0, const glm::vec2& u1,
                                 LobeDirection& d) const {
  if (!all_finite(wo)) return false;
  const Longitude o = longitude(wo);
  d.at = attenuation_for(wo, o.sin, o.cos);
  const Attenuation& at = d.at;
  // The last lobe with weight catches u0.x beyond a cdf that rounding left below 1.
  int p = -1;
  double cdf = 0.0;
  for (int q = 0; q < kLobes; ++q) {
    if (at.weight[q] <= 0.0) continue;
    p = q;
    cdf += at.weight[q];
    if (double(u0.x) < cdf) break;
  }
  if (p < 0) return false;  // every lobe absorbed: no direction carries light

  if (p == 4) {
    // The medulla lobe: u0.x, rescaled within the lobe's share of [0, 1), and u0.y
    // give the diffuse cylinder's azimuth, u1.x the exit shape's longitude.
    const double lo = cdf - at.weight[4];
    const double u = std::clamp((double(u0.x) - lo) / at.weight[4], 0.0, 1.0);
    const double sin_i = exit_->sample(u1.x);
    const double cos_i = std::sqrt(std::max(0.0, 1.0 - sin_i * sin_i));
    const double phi_i = azimuth(wo) + medulla::sample_lambertian_azimuth(u0.y, u);
    const glm::vec3 wi = glm::normalize(glm::vec3(glm::dvec3(sin_i, cos_i * std::sin(phi_i), cos_i * std::cos(phi_i))));
    if (!all_finite(wi)) return false;
    d.wi = wi;
    d.lobe = p;
    return true;
  }
  double sin_op = o.sin, cos_op = o.cos;
  if (p < 3) {
    sin_op = o.sin * cos_shift_[p] + o.cos * sin_shift_[p];
    cos_op = o.cos * cos_shift_[p] - o.sin * sin_shift_[p];
  }
  const double sin_i = hair::sample_mp_sin_theta(sin_op, cos_op, v_[p], mp_exp_[p], u1.x, u1.y);
  const double cos_i = std::sqrt(std::max(0.0, 1.0 - sin_i * sin_i));
  const double dphi = p < 3 ? hair::azimuthal_shift(p, gamma_o_, at.gamma_t) +
                                  hair::sample_trimmed_logistic(u0.y, s_, np_lo_, np_mass_)
                            : 2.0 * kPi * u0.y;
  const double phi_i = azimuth(wo) + dphi;
  const glm::vec3 wi = glm::normalize(
      glm::vec3(glm::dvec3(sin_i, cos_i * std::sin(phi_i), cos_i * std::cos(phi_i))));
  if (!all_finite(wi)) return false;
  d.wi = wi;
  d.lobe = p;
  return true;
}

std::optional<BCSDFSample> HairBCSDF::sample(const glm::vec3& wo, const glm::vec2& u0,
                                             const glm::vec2& u1) const {
  LobeDirection d;
  if (!sample_direction(wo, u0, u1, d)) return std::nullopt;
  // Re-evaluate at the float direction returned so f and pdf match f() and pdf() exactly.
  const Eval e = eval(wo, d.wi, d.at);
  if (!(e.pdf > 0.0)) return std::nullopt;
  return BCSDFSample{d.wi, glm::vec3(e.f), static_cast<float>(e.pdf)};
}

// The lobe-selection estimator: lobe p is chosen with probability w_p and its
// Mp Np (a density over solid angle) is sampled exactly, so
// E[A_p / w_p g(wi)] = sum_p int A_p Mp Np g dwi = int f cos g dwi.
std::optional<BCSDFThroughput> HairBCSDF::sample_throughput(const glm::vec3& wo, const glm::vec2& u0,
                                                            const glm::vec2& u1) const {
  LobeDirection d;
  if (!sample_direction(wo, u0, u1, d)) return std::nullopt;
  if (!(std::fabs(d.wi.x) < 1.0f)) return std::nullopt;  // f has no cos(theta_i) to stand on at the tangent
  return BCSDFThroughput{d.wi, glm::vec3(d.at.A[d.lobe] / d.at.weight[d.lobe])};
}

}  // namespace plumage
