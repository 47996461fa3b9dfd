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

#include <glm/glm.hpp>

#include "plumage/renderer/shading_mode.h"

namespace plumage {

struct CardResponseNode {
  float albedo;   // the mapping's input albedo A
  float through;  // the card seen through and past the vane
  float reflect;  // sent back without reaching the card
  float bounce;   // light between card and vane, once more per card albedo
};

struct CardResponse {
  static constexpr int kNodes = 12;
  std::array<CardResponseNode, kNodes> nodes;  // albedo ascending, 0 to 1

  // seen / card at node i over a card of albedo c.
  float seen(int i, float c) const { return nodes[i].through + nodes[i].reflect / c + nodes[i].bounce * c; }
};

// The response of a closed vane (ribbons overlapping 1.3 times the barb gap,
// barbules closing them; the photo feathers' vanes, docs/analysis.md) with the
// default hair parameters, lying on its card (BackdropPlacement::Vane) under the
// 25-LED dome, all LEDs on (photo-to-feather's light); Explicit and Farfield take
// Substructure's (their barbules lie in the vane as its do).
const CardResponse& card_response(ShadingMode mode);

// The mapping's input albedo that makes such a vane over a card of albedo `card`
// look `seen` times the card: on the luminances, the A at which the table's
// seen / card, linear between its nodes, equals seen (0 below what black fibres
// show, 1 above what white ones do), and `seen` scaled by A / its luminance so that
// the hue stays; clamped to [0, 1]. `card` is clamped to at least 1e-3; non-finite
// channels count as 0 (seen) or 1 (card). Built once per card (the table's seen /
// card over it), applied per texel.
class CardCorrection {
 public:
  CardCorrection(const CardResponse& r, const glm::vec3& card);
  glm::vec3 operator()(const glm::vec3& seen) const;

 private:
  std::array<float, CardResponse::kNodes> albedo_, seen_;
};

// CardCorrection(r, card)(seen), for one texel.
glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r);

}  // namespace plumage
