#pragma once
// Explicit mode (DESIGN §4): the reference the substructure technique is measured
// against. Every barb becomes real geometry: its ramus, a round curve of radius r_r
// along the barb's centreline, and per side N barbules, round curves of radius r_b.
// Barbule k of a side leaves the ramus edge (w = ±r_r) at arc length
// s_k = (k + 1/2) L/N in the direction t_b of Algorithm 2 (BarbSubstructure::frame:
// elevation theta_b in the vane, lifted by the azimuth phi_b; its line starts a
// little inside the ramus, out of sight), and ends where it is W/2 from the barb's
// centreline across the vane. A distal barbule's last
// `hooked_fraction` (of that lateral reach) turns further about the vane normal n by
// up to pi/2 (the pennulum hook). With phi_b = 0 and no hook the barbules' footprint
// on the vane is exactly the set G_b (Algorithm 1) calls non-empty.
//
// The curves are uniform cubic B-splines (control points x, y, z, radius), ready for
// Embree's RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE; this file knows nothing of Embree.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"
#include "plumage/renderer/substructure.h"

namespace plumage {

struct ExplicitFibre {
  Structure structure = Structure::Ramus;  // Ramus, Distal or Proximal
  std::uint32_t barb = 0;                  // the feather curve (Feather::curves) it belongs to
  std::uint32_t first_cp = 0;              // into ExplicitBarbs::control_points
  std::uint32_t num_cp = 0;                // >= 4
  std::size_t segments() const { return num_cp - 3; }
};

struct ExplicitBarbs {
  std::vector<glm::vec4> control_points;  // x, y, z (mm), radius (mm)
  std::vector<ExplicitFibre> fibres;

  std::size_t segments() const;
  // Bytes of the curve data handed to Embree (control points and one 32-bit index
  // per segment); Embree's BVH over the segments comes on top.
  std::size_t bytes() const;
};

// Points a distal barbule's hook is drawn through, after the straight part.
inline constexpr int kHookSegments = 4;

// Appends the ramus and barbules of feather curve `barb_index` (a barb of `vane`'s
// side) to `out`. Barbules of zero radius or zero length are left out; a barb of
// zero length gets its ramus only. Returns the barb's arc length (mm).
double add_explicit_barb(const Curve& barb, std::uint32_t barb_index, const BarbSubstructure& vane,
                         ExplicitBarbs& out);

// How many curves explicit mode makes for `feather` (rami plus barbules), without
// building them: sum over barbs of 1 + 2N (N of the barb's vane; 0 when r_b is 0).
std::size_t explicit_curve_count(const Feather& feather);

// Explicit mode's memory ceiling: its curves (about kExplicitBytesPerCurve each,
// control points, segment indices and Embree's BVH over them) must fit in 8 GiB.
inline constexpr std::size_t kExplicitBytesPerCurve = 512;
inline constexpr std::size_t kMaxExplicitBytes = std::size_t(8) << 30;

// Throws plumage::Error naming the barbule count and the limit when explicit
// mode's predicted memory (explicit_curve_count x kExplicitBytesPerCurve) is
// above kMaxExplicitBytes; call it before building the scene.
void check_explicit_fits(const Feather& feather);

}  // namespace plumage
