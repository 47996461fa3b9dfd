#include "plumage/renderer/card_response.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/image.h"

namespace plumage {

CardResponse card_response(ShadingMode mode) {
  // Fitted to renders of the closed vane of RenderMaterial.CardResponseModelsAClosedVane
  // (cards 0.1 and 0.8, A = 0.02, 0.15, 0.4, 0.9, green channel, 64 spp, 32 x 32;
  // docs/hair-bcsdf.md). Substructure's flat in-vane barbules reflect more sky.
  if (mode == ShadingMode::Hair) return {0.024f, 0.060f, 0.020f, 0.80f};
  return {0.040f, 0.060f, 0.018f, 0.84f};
}

glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r) {
  // Inverted on the luminance and applied to every channel as one factor: per
  // channel, a dark texel whose blue lies under what black fibres show but whose
  // red does not would turn a brown vane yellow.
  glm::vec3 s, c;
  for (int i = 0; i < 3; ++i) {
    s[i] = std::isfinite(seen[i]) ? std::max(seen[i], 0.0f) : 0.0f;
    c[i] = std::max(std::isfinite(card[i]) ? card[i] : 1.0f, 1e-3f);
  }
  const float ls = luminance(s), lc = std::max(luminance(c), 1e-3f);
  if (!(ls > 0)) return glm::vec3(0.0f);
  const float a = std::max((ls - r.reflect / lc - r.leak) / (r.scatter / lc + r.through), 0.0f);
  return glm::clamp(s * (a / ls), glm::vec3(0.0f), glm::vec3(1.0f));
}

}  // namespace plumage
