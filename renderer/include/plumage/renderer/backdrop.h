#pragma once
// The backdrop card under the feather: the white paper or black card the photo
// was taken on, a two-sided lambertian quad just below the feather (Scene builds
// it; docs/rendering.md).
#include <glm/glm.hpp>

namespace plumage {

// Where the card lies. Feather: under the feather's lowest point (a thick rachis
// holds the vane above it). Vane: under the lowest barb, as a photographed
// feather's vane lies on its card; a rachis thicker than the vane may reach
// through it (only the card's top side is seen from above). Either way the gap is
// four radii of the largest curve that sets it (barbs for Vane), at least a
// thousandth of the feather's larger side: farther than any curve's near-origin
// culling distance, and the same gap in units of the ribbon width for every vane,
// as in the closed-vane probe that card_response is fitted to.
enum class BackdropPlacement { Feather, Vane };

struct BackdropSpec {
  bool enabled = false;
  glm::vec3 albedo{0.8f};   // white paper ~0.8, black card ~0.03
  float extent = 3.0f;       // card side = extent x the feather's larger side
  BackdropPlacement placement = BackdropPlacement::Feather;
};

}  // namespace plumage
