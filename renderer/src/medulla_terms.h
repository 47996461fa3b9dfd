#pragma once
// The scalar terms of the fibre's scattering medulla (docs/hair-bcsdf.md, "The
// medulla"): a double cylinder after Yan et al. 2015 (a clear, absorbing cortex
// around a core of radius k that scatters), reduced to one extra lobe whose
// energy is what the core catches and whose shape follows from reciprocity.
// Header-only so the BCSDF inlines them and the tests check each on its own.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "hair_terms.h"
#include "plumage/common/constants.h"

namespace plumage::medulla {

// Half the chord that a refracted ray at normal-plane offset sin_gamma_t (its
// closest approach to the axis, in radii) cuts through a core of radius k; 0 when
// it misses the core.
inline double half_chord(double sin_gamma_t, double k) {
  const double d = k * k - sin_gamma_t * sin_gamma_t;
  return d > 0.0 ? std::sqrt(d) : 0.0;
}

// The fraction of the light that a multiply scattering, optically thick core of
// single-scattering albedo `alpha` sends back out rather than absorbs: the
// two-stream (Kubelka-Munk) albedo of a semi-infinite medium, (1 - r) / (1 + r)
// with r = sqrt(1 - alpha). 1 without absorption, 0 without scattering; a thin
// core lets more out than this, so the medulla lobe errs dark.
inline double escape_albedo(double alpha) {
  const double r = std::sqrt(std::max(0.0, 1.0 - std::clamp(alpha, 0.0, 1.0)));
  return (1.0 - r) / (1.0 + r);
}

// The azimuthal distribution of light leaving a diffusely scattering cylinder
// (a Lambertian cylinder lit by parallel light: the integral over its surface of
// cos(to the light) cos(to the viewer)), normalised over [-pi, pi]:
// N(phi) = ((pi - |phi|) cos phi + sin |phi|) / 8, phi = phi_i - phi_o. Largest
// back toward the light (phi = 0), 0 straight through (|phi| = pi).
inline double lambertian_azimuth(double phi) {
  const double a = std::min(std::abs(phi), kPi);
  return std::max(0.0, ((kPi - a) * std::cos(phi) + std::sin(a)) * 0.125);
}
// The same from the cosine and |sine| of phi (no angle needed).
inline double lambertian_azimuth(double cos_phi, double abs_sin_phi) {
  const double a = std::atan2(abs_sin_phi, cos_phi);
  return std::max(0.0, ((kPi - a) * cos_phi + abs_sin_phi) * 0.125);
}
// Samples phi from lambertian_azimuth with two uniform numbers: a surface point at
// azimuth psi with density cos(psi) (the lit half), and the direction leaving it at
// chi from its normal with density cos(chi): phi = psi + chi, wrapped.
inline double sample_lambertian_azimuth(double u1, double u2) {
  const double psi = std::asin(std::clamp(2.0 * u1 - 1.0, -1.0, 1.0));
  const double chi = std::asin(std::clamp(2.0 * u2 - 1.0, -1.0, 1.0));
  return hair::wrap_angle(psi + chi);
}

// The longitudinal shape of the light the core sends out, as a density over
// u = sin(theta_i) (like d'Eon's Mp, integral du = 1): by reciprocity (a thick
// core's emission toward a direction is its absorption from it, as in
// Kirchhoff's law) proportional to g(theta) cos(theta), g the fraction of the light
// arriving from theta that enters the fibre and reaches the core, averaged over
// the offset h: (1 - F(cos theta cos gamma)) wherever the refracted ray meets the
// core. Tabulated at kNodes longitudes uniform in theta, linear in u between them
// (dense near the poles, where cos theta bends), for one (eta, k).
class ExitShape {
 public:
  static constexpr int kNodes = 65;

  ExitShape() = default;
  ExitShape(double eta, double k) : eta_(eta), k_(k) {
    constexpr int kH = 64;  // midpoint rule over h in [0, 1] (g is even in h)
    for (int j = 0; j < kNodes; ++j) {
      const double theta = -0.5 * kPi + kPi * j / (kNodes - 1);
      const double s = std::sin(theta), c = std::max(0.0, std::cos(theta));
      u_[j] = j == 0 ? -1.0 : j == kNodes - 1 ? 1.0 : s;
      const double root = std::sqrt(std::max(0.0, eta * eta - s * s));
      double g = 0.0;
      for (int i = 0; i < kH; ++i) {
        const double h = (i + 0.5) / kH;
        const double sin_gamma_t = root > 0.0 ? h * c / root : 0.0;
        if (sin_gamma_t >= k) continue;
        g += 1.0 - hair::fresnel_dielectric(c * std::sqrt(1.0 - h * h), eta);
      }
      g_[j] = g / kH;
      p_[j] = g_[j] * c;
    }
    // Normalise the piecewise-linear density and build its cumulative mass.
    cdf_[0] = 0.0;
    for (int j = 1; j < kNodes; ++j) cdf_[j] = cdf_[j - 1] + 0.5 * (p_[j - 1] + p_[j]) * (u_[j] - u_[j - 1]);
    const double total = cdf_[kNodes - 1];
    norm_ = total;
    if (total > 0.0)
      for (int j = 0; j < kNodes; ++j) {
        p_[j] /= total;
        cdf_[j] /= total;
      }
  }

  double eta() const { return eta_; }
  double k() const { return k_; }
  // The integral of g(theta) cos^2(theta) d theta (the shape's normaliser).
  double norm() const { return norm_; }
  // g averaged over h at sin(theta) = u, linear between the nodes.
  double coupling(double u) const {
    const int j = segment(u);
    const double t = (u - u_[j]) / (u_[j + 1] - u_[j]);
    return g_[j] + t * (g_[j + 1] - g_[j]);
  }
  // The density over u = sin(theta_i).
  double pdf(double u) const {
    const int j = segment(u);
    const double t = (u - u_[j]) / (u_[j + 1] - u_[j]);
    return p_[j] + t * (p_[j + 1] - p_[j]);
  }
  // Inverts the cumulative mass: u in [0, 1) -> sin(theta_i) in [-1, 1].
  double sample(double xi) const {
    const double target = std::clamp(xi, 0.0, 1.0);
    int j = int(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin()) - 1;
    j = std::clamp(j, 0, kNodes - 2);
    const double w = u_[j + 1] - u_[j], a = p_[j], b = p_[j + 1];
    const double m = target - cdf_[j];  // mass to cover inside the segment
    // Within the segment the density is a + (b - a) t / w: solve a x + (b - a) x^2 / (2 w) = m.
    const double slope = (b - a) / w;
    double x;
    if (std::abs(slope) * w < 1e-9 * std::max(a, 1e-300)) {
      x = a > 0.0 ? m / a : 0.0;
    } else {
      const double disc = std::max(0.0, a * a + 2.0 * slope * m);
      x = 2.0 * m / (a + std::sqrt(disc));  // the root of the quadratic, without cancellation
    }
    return std::clamp(u_[j] + std::clamp(x, 0.0, w), -1.0, 1.0);
  }

 private:
  int segment(double u) const {
    const int j = int(std::upper_bound(u_.begin(), u_.end(), u) - u_.begin()) - 1;
    return std::clamp(j, 0, kNodes - 2);
  }
  double eta_ = 0.0, k_ = 0.0, norm_ = 0.0;
  std::array<double, kNodes> u_{}, g_{}, p_{}, cdf_{};
};

// The exit shape for (eta, k), built once per thread and kept while they stay
// (a fibre's parameters rarely change between the shading points of one thread).
inline std::shared_ptr<const ExitShape> exit_shape(double eta, double k) {
  thread_local std::shared_ptr<const ExitShape> last;
  if (!last || last->eta() != eta || last->k() != k) last = std::make_shared<const ExitShape>(eta, k);
  return last;
}

}  // namespace plumage::medulla
