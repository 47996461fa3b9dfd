#pragma once
// The scalar terms of the hair BCSDF, one function per term of the papers
// (Marschner et al. 2003; d'Eon et al. 2011; Chiang et al. 2016). Header-only so
// the BCSDF can inline them and the tests can check each against its definition.
// Double precision: Mp subtracts terms of size 1/v, which reaches 10^7 for the
// smoothest fibres we allow.
#include <algorithm>
#include <cmath>

#include "plumage/common/constants.h"

namespace plumage::hair {


// I0(x) for 0 <= x < 3.75 (Abramowitz & Stegun 9.8.1, |relative error| < 1.6e-7).
inline double bessel_i0_small(double x) {
  const double t = (x / 3.75) * (x / 3.75);
  return 1.0 + t * (3.5156229 + t * (3.0899424 + t * (1.2067492 +
         t * (0.2659732 + t * (0.0360768 + t * 0.0045813)))));
}

// sqrt(x) e^{-x} I0(x) for x >= 3.75 (Abramowitz & Stegun 9.8.2, |error| < 1.9e-7): the
// factor e^x is left to the caller, so I0 of huge arguments never overflows.
inline double bessel_i0_scaled_large(double x) {
  const double t = 3.75 / x;
  return 0.39894228 + t * (0.01328592 + t * (0.00225319 + t * (-0.00157565 +
         t * (0.00916281 + t * (-0.02057706 + t * (0.02635537 +
         t * (-0.01647633 + t * 0.00392377)))))));
}

inline double log_bessel_i0(double x) {
  if (x < 3.75) return std::log(bessel_i0_small(x));
  return x + std::log(bessel_i0_scaled_large(x) / std::sqrt(x));
}

// Longitudinal variance from beta_m (Chiang et al. 2016 eq. 7).
inline double variance_from_beta_m(double beta_m) {
  const double b2 = beta_m * beta_m, b4 = b2 * b2, b20 = b4 * b4 * b4 * b4 * b4;
  const double b = 0.726 * beta_m + 0.812 * b2 + 3.7 * b20;
  return b * b;
}

// Logistic scale from beta_n (Chiang et al. 2016 eq. 8).
inline double logistic_scale_from_beta_n(double beta_n) {
  const double b2 = beta_n * beta_n, b4 = b2 * b2, b22 = b4 * b4 * b4 * b4 * b4 * b2;
  return std::sqrt(kPi / 8.0) * (0.265 * beta_n + 1.194 * b2 + 5.372 * b22);
}

// d'Eon et al. 2011 eq. 7, Mp = csch(1/v)/(2v) exp(-sin_i sin_o / v) I0(cos_i cos_o / v),
// evaluated as exp of its log with csch(1/v)/(2v) = e^{-1/v} / (v (1 - e^{-2/v})),
// which is exact for every v and stable as v -> 0 (their eq. 8 is its limit).
// Normalised so that the integral of Mp(theta_i) cos(theta_i) d theta_i is 1.
inline double longitudinal_mp_log_norm(double v) {
  return -std::log(v) - 1.0 / v - std::log1p(-std::exp(-2.0 / v));
}
// log_norm = longitudinal_mp_log_norm(v), which a BCSDF precomputes per lobe.
inline double longitudinal_mp(double sin_i, double cos_i, double sin_o, double cos_o, double v,
                              double log_norm) {
  const double a = std::abs(cos_i * cos_o) / v;
  const double b = sin_i * sin_o / v;
  if (a < 3.75) return std::exp(log_norm - b) * bessel_i0_small(a);
  return std::exp(log_norm - b + a) * (bessel_i0_scaled_large(a) / std::sqrt(a));
}
inline double longitudinal_mp(double sin_i, double cos_i, double sin_o, double cos_o, double v) {
  return longitudinal_mp(sin_i, cos_i, sin_o, cos_o, v, longitudinal_mp_log_norm(v));
}

// Samples sin(theta_i) from Mp by sampling the von Mises-Fisher lobe that Mp is the
// longitudinal marginal of (d'Eon et al. 2011 §4; inversion of the vMF cosine after
// Jakob 2012): mean direction theta = -theta_o, concentration 1/v.
// `exp_neg_2_over_v` = e^{-2/v}, which a BCSDF precomputes per lobe.
inline double sample_mp_sin_theta(double sin_o, double cos_o, double v, double exp_neg_2_over_v, double u1,
                                  double u2) {
  // cos of the angle to the lobe axis: 1 + v log(u + (1-u) e^{-2/v}).
  const double x =
      std::clamp(1.0 + v * std::log(std::max(u1 + (1.0 - u1) * exp_neg_2_over_v, 1e-300)), -1.0, 1.0);
  const double sin_axis = std::sqrt(std::max(0.0, 1.0 - x * x));
  const double sin_i = -x * sin_o + sin_axis * std::cos(2.0 * kPi * u2) * std::abs(cos_o);
  return std::clamp(sin_i, -1.0, 1.0);
}

// The logistic distribution of scale s (Chiang et al. 2016 eq. 11), symmetric so |x|
// keeps e^{-|x|/s} from overflowing.
inline double logistic(double x, double s) {
  const double e = std::exp(-std::abs(x) / s);
  return e / (s * (1.0 + e) * (1.0 + e));
}

// The logistic restricted to [-pi, pi] and renormalised (Chiang et al. 2016 eq. 12);
// its integral over [-pi, pi] is F(pi) - F(-pi) = tanh(pi / (2 s)).
inline double trimmed_logistic_norm(double s) { return 1.0 / std::tanh(kPi / (2.0 * s)); }
inline double trimmed_logistic(double x, double s, double norm) { return logistic(x, s) * norm; }
inline double trimmed_logistic(double x, double s) {
  return trimmed_logistic(x, s, trimmed_logistic_norm(s));
}

// Inverts the trimmed logistic's CDF (Chiang et al. 2016 eq. 13): u in [0,1] -> [-pi, pi].
// `lo` = F(-pi) = 1 / (1 + e^{pi/s}) and `mass` = tanh(pi / (2 s)), which a BCSDF
// precomputes.
inline double trimmed_logistic_cdf_lo(double s) { return 1.0 / (1.0 + std::exp(kPi / s)); }
inline double sample_trimmed_logistic(double u, double s, double lo, double mass) {
  const double q = lo + u * mass;
  const double x = s * (std::log(q) - std::log1p(-q));
  return std::clamp(x, -kPi, kPi);
}

// Wraps an angle into [-pi, pi].
inline double wrap_angle(double x) {
  return x - 2.0 * kPi * std::round(x / (2.0 * kPi));
}

// Azimuthal deflection of lobe p (Marschner et al. 2003 eq. 3, Phi = 2p gamma_t -
// 2 gamma_o + p pi), with the sign of gamma flipped because Plumage measures h
// along +y: in this frame R leaves at phi_o + 2 gamma_o.
inline double azimuthal_shift(int p, double gamma_o, double gamma_t) {
  return 2.0 * gamma_o - 2.0 * p * gamma_t + p * kPi;
}

// Unpolarised Fresnel reflectance of a dielectric for the cosine of the incidence
// angle (Fresnel equations; Born & Wolf §1.5). Grazing incidence reflects fully.
inline double fresnel_dielectric(double cos_i, double eta) {
  if (cos_i <= 0.0) return 1.0;
  cos_i = std::min(cos_i, 1.0);
  const double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin_t2);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

}  // namespace plumage::hair
