#pragma once
// The substructure technique of Baron et al. 2021 (§5.3; DESIGN §5). A barb is a
// ribbon of width W lying in the vane. A point on it is given by s, the arc length
// along the barb from its root, and w, the offset across it along the barb's
// bitangent b = n x t. The geometric term G_b (Algorithm 1) says whether (s, w)
// lies on the ramus, a distal or a proximal barbule, or in empty space; Algorithm 2
// gives the barbule's own frame; Eq. 1 shades each structure as a fibre in that frame.
#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"
#include "plumage/common/frame.h"
#include "plumage/renderer/fibre_frame.h"

namespace plumage {

enum class Structure : std::uint8_t { Empty, Ramus, Distal, Proximal };
const char* to_string(Structure s);

// What G_b found at a point of the ribbon.
struct StructureHit {
  Structure structure = Structure::Empty;
  // Offset across the structure in units of its radius, in [-1, 1], measured along
  // the structure's in-vane bitangent (barb_substructure frame's b).
  float h = 0;
  // Distal barbules: position along the hooked tip (pennulum), 0 where the hook
  // starts (and before it) to 1 at the barbule's tip.
  float hook = 0;
};

// Substructure mode: where a barb hit lies on its ribbon and what is there.
struct StructureSample {
  double s = 0, w = 0;   // arc length along the barb from its root; offset along b (mm)
  Frame barb;            // the barb's frame (t, b = n x t, n the vane normal) at the hit
  StructureHit hit;      // G_b (Algorithm 1)
  Frame frame;           // the structure's shading frame (Algorithm 2)
};

// The substructure of the barbs of one vane: its parameters, validated, and the
// trigonometry they need, precomputed once.
class BarbSubstructure {
 public:
  // Throws plumage::Error naming `what` and the setting (its curve-format key)
  // for side None, any value substructure_problem() refuses, W <= 0 or r_r <= 0.
  BarbSubstructure(const SubstructureParams& params, VaneSide side, std::string_view what = "substructure");

  // Barbules closer to the barb than this are rejected: as theta_b -> 0 a barbule
  // becomes a line along the ramus and its period across the ribbon vanishes.
  static constexpr float kMinElevationDeg = kMinBarbuleElevationDeg;

  // G_b (Algorithm 1) at arc length s along a barb of length L and offset w.
  StructureHit classify(double s, double w, double length) const;

  // Algorithm 2: the frame a structure is shaded in, from the barb's frame
  // (t, b, n) at the point, for a hit at offset w (its sign gives the side).
  Frame frame(const Frame& barb, const StructureHit& hit, double w) const;

  // +1 when the distal side is +w (toward +b), -1 when it is -w. Distal barbules
  // point toward the feather's tip: +b on the right vane, -b on the left (DESIGN §3).
  float distal_sign() const { return distal_sign_; }
  float half_width() const { return half_width_; }
  const SubstructureParams& params() const { return p_; }
  VaneSide side() const { return side_; }

  // The fraction of the ribbon's area covered by ramus and barbules, analytically:
  // 2 r_r / W for the ramus, and across the rest a barbule of width 2 r_b / sin(theta_b)
  // (along the barb) every L / N.
  double covered_fraction(double length) const;

 private:
  SubstructureParams p_;
  VaneSide side_;
  float distal_sign_;
  float half_width_;
  double sin_theta_, cos_theta_, cot_theta_, sin_phi_, cos_phi_;
};

// The BCSDF frame of a structure seen along wo (Eq. 1): the structure's tangent,
// and h projected onto the fibre frame's y, so a structure seen edge-on gets the
// offset it actually shows the ray.
FibreFrame structure_fibre_frame(const Frame& structure, float h, const glm::vec3& wo);

}  // namespace plumage
