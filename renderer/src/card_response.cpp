#include "plumage/renderer/card_response.h"

#include <algorithm>
#include <cmath>

namespace plumage {

CardResponse card_response(ShadingMode mode) {
  // Fitted to renders of the closed vane of RenderMaterial.CardResponseModelsAClosedVane
  // (cards 0.1 and 0.8, A = 0.02, 0.15, 0.4, 0.9, green channel, 64 spp, 32 x 32;
  // docs/hair-bcsdf.md). Substructure's flat in-vane barbules reflect more sky.
  if (mode == ShadingMode::Hair) return {0.024f, 0.060f, 0.020f, 0.80f};
  return {0.040f, 0.060f, 0.018f, 0.84f};
}

glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r) {
  glm::vec3 a;
  for (int i = 0; i < 3; ++i) {
    const float c = std::max(std::isfinite(card[i]) ? card[i] : 1.0f, 1e-3f);
    const float s = std::isfinite(seen[i]) ? seen[i] : 0.0f;
    const float v = (s - r.reflect / c - r.leak) / (r.scatter / c + r.through);
    a[i] = std::clamp(v, 0.0f, 1.0f);
  }
  return a;
}

}  // namespace plumage
