#pragma once
// How a closed vane over a card looks, as a function of the albedo handed to the
// layer mapping (photo_albedo_to_fibre) and of the card's albedo. A photo's albedo
// texture on a light background is the vane's colour divided by the paper's, so
// the render must make the vane look that many times its own card; but part of
// what a vane sends back never reaches the card (the R lobe off the fibres'
// surfaces, light scattered by them) and does not scale with it, and part goes
// back and forth between vane and card. On white paper the first part is small
// beside the vane; on a mid-grey card it lightens a dark feather by half its albedo
// or more (docs/hair-bcsdf.md, "A photo's albedo over a card"). Measured by
// rendering, per shading mode and at each of a table of input albedos A:
//
//   seen / card = through(A) + reflect(A) / c + bounce(A) c
//
// with c the card's albedo (tests/render_material_test.cpp fits the table,
// RenderMaterial.CardResponseFit, and RenderMaterial.CardResponseModelsAClosedVane
// holds it to renders); between the table's albedos the three terms are linear in A.
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

#include "plumage/renderer/shading_mode.h"

namespace plumage {

// The medulla radius (in fibre radii) of the fibres the photo inversion makes pale:
// the rami of white and structurally coloured barbs are mostly spongy medulla
// inside a thin cortex (Prum et al. 1998; Shawkey & Hill 2006).
inline constexpr float kPhotoMedullaRatio = 0.7f;

struct CardResponseNode {
  float albedo;   // the mapping's input albedo A
  float through;  // the card seen through and past the vane
  float reflect;  // sent back without reaching the card
  float bounce;   // light between card and vane, once more per card albedo
};

// One row of the table: the vane's fibres with a medulla of ratio kPhotoMedullaRatio
// scattering medulla_sigma_s per radius (row 0: none, the clear fibre).
struct CardResponseRow {
  float medulla_sigma_s;
  std::array<CardResponseNode, 12> nodes;  // albedo ascending, 0 to 1
};

struct CardResponse {
  static constexpr int kNodes = 12;
  static constexpr int kRows = 7;
  std::array<CardResponseRow, kRows> rows;  // medulla_sigma_s ascending, 0 first

  // seen / card at row j, node i over a card of albedo c.
  float seen(int j, int i, float c) const {
    const CardResponseNode& n = rows[j].nodes[i];
    return n.through + n.reflect / c + n.bounce * c;
  }
};

// The response of a closed vane (ribbons overlapping 1.3 times the barb gap,
// barbules closing them; the photo feathers' vanes, docs/analysis.md) with the
// default hair parameters, lying on its card (BackdropPlacement::Vane) under the
// 25-LED dome, all LEDs on (photo-to-feather's light); Explicit and Farfield take
// Substructure's (their barbules lie in the vane as its do).
const CardResponse& card_response(ShadingMode mode);

// What a texel of a photo becomes: the albedo handed to the layer mapping and the
// medulla's scattering (0: a clear fibre).
struct FibreColour {
  glm::vec3 albedo{0.0f};
  float medulla_sigma_s = 0.0f;
  bool clamped = false;  // the texel lies outside what the table's fibres can show over this card
};

// The fibre that makes such a vane over a card of albedo `card` look `seen` times
// the card (docs/hair-bcsdf.md, "Colours inverted through the renderer"):
// * while no channel is more than 10 % brighter than white clear fibres show (row 0's A = 1), a
//   clear fibre: on the luminances, the A at which row 0's seen / card, linear
//   between its nodes, equals seen (0 below what black fibres show), and `seen`
//   scaled by A / its luminance so that the hue stays; clamped to [0, 1];
// * paler texels get a medulla, each channel on the table over its own card channel:
//   its scattering is the largest that any channel's white fibres need to show it
//   (linear in sigma_s between the first row that reaches it and the row before),
//   then each channel's A is inverted on its table blended at that scattering.
//   Channels beyond the table's reach are clamped (and the texel counted).
// `card` is clamped to at least 1e-3; non-finite channels count as 0 (seen) or 1
// (card). Built once per card, applied per texel.
class CardCorrection {
 public:
  CardCorrection(const CardResponse& r, const glm::vec3& card);
  FibreColour operator()(const glm::vec3& seen) const;

 private:
  std::array<float, CardResponse::kNodes> albedo_;
  using Table = std::array<std::array<float, CardResponse::kNodes>, CardResponse::kRows>;
  Table seen_;                    // over the card's luminance (clear fibres)
  std::array<Table, 3> seen_rgb_;  // over each channel of the card (fibres with a medulla)
  std::array<float, CardResponse::kRows> sigma_s_;
};

// CardCorrection(r, card)(seen).albedo, for one texel.
glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r);

}  // namespace plumage
