#include "plumage/renderer/substructure.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/number_text.h"

namespace plumage {
namespace {

// Rodrigues' rotation of v about the unit axis k by angle a (right-handed).
glm::vec3 rotate(const glm::vec3& v, const glm::vec3& k, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0f - c));
}

}  // namespace

const char* to_string(Structure s) {
  switch (s) {
    case Structure::Ramus: return "ramus";
    case Structure::Distal: return "distal barbule";
    case Structure::Proximal: return "proximal barbule";
    case Structure::Empty: break;
  }
  return "empty";
}

BarbSubstructure::BarbSubstructure(const SubstructureParams& p, VaneSide side, std::string_view what)
    : p_(p), side_(side) {
  const std::string where = std::string(what) + " (" + to_string(side) + " vane): ";
  auto fail = [&](const std::string& msg) { throw Error(where + msg); };
  if (side == VaneSide::None) fail("a barb must belong to the left or right vane to tell distal from proximal");
  if (const auto bad = substructure_problem(p)) fail(bad->setting + ": " + bad->problem);
  // In range, but substructure shading also needs a ribbon with a ramus in it.
  if (!(p.ribbon_width > 0))
    fail("ribbon_width: value " + num(p.ribbon_width) +
         "; substructure shading needs the barb ribbon's width (mm) in the curve file's substructure record");
  if (!(p.ramus_radius > 0)) fail("ramus_radius: value " + num(p.ramus_radius) + "; substructure shading needs a ramus");
  distal_sign_ = side == VaneSide::Right ? 1.0f : -1.0f;
  half_width_ = 0.5f * p.ribbon_width;
  sin_theta_ = std::sin(p.elevation_deg * kDegToRad);
  cos_theta_ = std::cos(p.elevation_deg * kDegToRad);
  cot_theta_ = cos_theta_ / sin_theta_;
  sin_phi_ = std::sin(p.azimuth_deg * kDegToRad);
  cos_phi_ = std::cos(p.azimuth_deg * kDegToRad);
}

// Algorithm 1 (G_b) with the construction of DESIGN §5.
StructureHit BarbSubstructure::classify(double s, double w, double length) const {
  StructureHit hit;
  const double aw = std::fabs(w);
  if (!(aw <= half_width_)) return hit;
  const double r_r = p_.ramus_radius, r_b = p_.barbule_radius;
  if (aw <= r_r) {
    hit.structure = Structure::Ramus;
    hit.h = float(w / r_r);
    return hit;
  }
  if (p_.barbules_per_side == 0 || r_b <= 0 || !(length > 0) || !std::isfinite(s)) return hit;
  const bool distal = w * distal_sign_ > 0;
  const double d = aw - r_r;  // lateral distance from the ramus edge
  const double period = length / p_.barbules_per_side;
  // Barbule k leaves the ramus edge at s_k = (k + 1/2) L/N; at lateral distance d its
  // centreline has moved d cot(theta_b) toward the barb's tip (distal) or root (proximal).
  const double shift = distal ? d * cot_theta_ : -d * cot_theta_;
  const double x = (s - shift) / period - 0.5;
  const double ds = (x - std::nearbyint(x)) * period;  // along the barb, from the nearest centreline
  // Across the barbule, signed along its in-vane bitangent n x t_b.
  const double across = (w > 0 ? -1.0 : 1.0) * ds * sin_theta_;
  if (std::fabs(across) > r_b) return hit;
  hit.structure = distal ? Structure::Distal : Structure::Proximal;
  hit.h = float(std::clamp(across / r_b, -1.0, 1.0));
  const double f = p_.hooked_fraction;
  if (distal && f > 0) {
    const double along = d / (half_width_ - r_r);  // fraction of the barbule's length
    hit.hook = float(std::clamp((along - (1.0 - f)) / f, 0.0, 1.0));
  }
  return hit;
}

// Algorithm 2. t_b points from the barbule's base at the ramus to its tip.
Frame BarbSubstructure::frame(const Frame& barb, const StructureHit& hit, double w) const {
  if (hit.structure != Structure::Distal && hit.structure != Structure::Proximal) return barb;
  const bool distal = hit.structure == Structure::Distal;
  const float sigma = w >= 0 ? 1.0f : -1.0f;  // the ribbon side the barbule is on
  // t rotated about n by theta_b toward the barbule's side (proximal barbules point
  // back toward the barb's root: pi - theta_b) ...
  const float along = float(distal ? cos_theta_ : -cos_theta_);
  const float across = sigma * float(sin_theta_);
  // ... then about b by phi_b, lifting a distal barbule's tip dorsally (+n).
  const glm::vec3 tb = along * float(cos_phi_) * barb.t + across * barb.b + along * float(sin_phi_) * barb.n;
  Frame f;
  f.t = glm::normalize(tb);
  f.b = glm::normalize(glm::cross(barb.n, f.t));
  f.n = glm::cross(f.t, f.b);
  if (distal && hit.hook > 0) {
    // Pennulum hook: the tip keeps turning about n, by up to pi/2 at the barbule's end.
    const float a = sigma * hit.hook * std::numbers::pi_v<float> / 2;
    f.t = rotate(f.t, barb.n, a);
    f.b = rotate(f.b, barb.n, a);
    f.n = rotate(f.n, barb.n, a);
  }
  return f;
}

double BarbSubstructure::covered_fraction(double length) const {
  const double ramus = std::min(1.0, double(p_.ramus_radius) / half_width_);
  if (p_.barbules_per_side == 0 || p_.barbule_radius <= 0 || !(length > 0)) return ramus;
  const double barbule = std::min(1.0, 2.0 * p_.barbule_radius * p_.barbules_per_side / (length * sin_theta_));
  return ramus + (1.0 - ramus) * barbule;
}

FibreFrame structure_fibre_frame(const Frame& structure, float h, const glm::vec3& wo) {
  const Frame f = fibre_frame(structure.t, wo);
  return {f, std::clamp(h * glm::dot(structure.b, f.b), -1.0f, 1.0f)};
}

}  // namespace plumage
