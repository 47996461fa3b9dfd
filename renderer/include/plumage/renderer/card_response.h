#pragma once
// How a closed vane over a card looks, as a function of the albedo handed to the
// layer mapping (photo_albedo_to_fibre) and of the card's albedo. A photo's albedo
// texture on a light background is the vane's colour divided by the paper's, so
// the render must make the vane look that many times its own card; but part of
// what a vane sends back never reaches the card (the R lobe off the fibres'
// surfaces, sky light scattered through them) and does not scale with it. On white
// paper that part is small beside the vane; on a mid-grey card it lightens a dark
// feather by half its albedo or more (docs/hair-bcsdf.md, "A photo's albedo over a
// card"). Measured by rendering, per shading mode:
//
//   seen / card = (reflect + scatter A) / c + leak + through A
//
// with A the mapping's input albedo and c the card's (tests/render_material_test.cpp,
// RenderMaterial.CardResponseModelsAClosedVane holds the model to renders).
#include <glm/glm.hpp>

#include "plumage/renderer/shading_mode.h"

namespace plumage {

struct CardResponse {
  float reflect = 0;  // sent back without reaching the card, black fibres
  float scatter = 0;  // ... growing with A
  float leak = 0;     // the card seen past black fibres (their edges)
  float through = 1;  // the card seen through the vane, per unit of A
};

// The response of a closed vane (ribbons overlapping 1.3 times the barb gap,
// barbules closing them; the photo feathers' vanes, docs/analysis.md) with the
// default hair parameters under a uniform sky; Explicit and Farfield take
// Substructure's (their barbules lie in the vane as its do).
CardResponse card_response(ShadingMode mode);

// The mapping's input albedo that makes such a vane over a card of albedo `card`
// look `seen` times the card: on the luminances, A = (seen - reflect/c - leak) /
// (scatter/c + through), at least 0 (a seen below what black fibres show gives
// black), and `seen` scaled by A / its luminance so that the hue stays; clamped to
// [0, 1]. `card` is clamped to at least 1e-3; non-finite channels count as 0.
glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r);

}  // namespace plumage
