#include "plumage/renderer/card_response.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/image.h"

namespace plumage {

namespace {

// Fitted by RenderMaterial.CardResponseFit (scripts/fit_card_response.sh): the
// closed vane rendered over cards 0.9, 0.5, 0.25 and 0.1 at each albedo, green
// channel, least squares in (1, 1/c, c).
constexpr CardResponse kHair{{{
    // clang-format off
    {0.00f, 0.0006f, 0.0242f, 0.0001f},
    {0.02f, 0.0291f, 0.0279f, 0.0024f},
    {0.05f, 0.0525f, 0.0306f, 0.0055f},
    {0.10f, 0.0893f, 0.0343f, 0.0074f},
    {0.15f, 0.1222f, 0.0377f, 0.0111f},
    {0.20f, 0.1564f, 0.0408f, 0.0131f},
    {0.30f, 0.2170f, 0.0468f, 0.0233f},
    {0.40f, 0.2805f, 0.0531f, 0.0329f},
    {0.50f, 0.3464f, 0.0591f, 0.0398f},
    {0.70f, 0.4700f, 0.0730f, 0.0721f},
    {0.90f, 0.6033f, 0.0893f, 0.1136f},
    {1.00f, 0.6825f, 0.0997f, 0.1426f},
    // clang-format on
}}};

constexpr CardResponse kSubstructure{{{
    // clang-format off
    {0.00f, 0.0013f, 0.0372f, 0.0003f},
    {0.02f, 0.0255f, 0.0409f, 0.0026f},
    {0.05f, 0.0488f, 0.0435f, 0.0043f},
    {0.10f, 0.0846f, 0.0472f, 0.0071f},
    {0.15f, 0.1185f, 0.0509f, 0.0098f},
    {0.20f, 0.1541f, 0.0542f, 0.0127f},
    {0.30f, 0.2190f, 0.0608f, 0.0218f},
    {0.40f, 0.2896f, 0.0673f, 0.0280f},
    {0.50f, 0.3588f, 0.0738f, 0.0381f},
    {0.70f, 0.5056f, 0.0870f, 0.0536f},
    {0.90f, 0.6464f, 0.1016f, 0.0837f},
    {1.00f, 0.7221f, 0.1095f, 0.1056f},
    // clang-format on
}}};

}  // namespace

const CardResponse& card_response(ShadingMode mode) { return mode == ShadingMode::Hair ? kHair : kSubstructure; }

CardCorrection::CardCorrection(const CardResponse& r, const glm::vec3& card) {
  glm::vec3 c;
  for (int i = 0; i < 3; ++i) c[i] = std::max(std::isfinite(card[i]) ? card[i] : 1.0f, 1e-3f);
  const float lc = std::max(luminance(c), 1e-3f);
  for (int i = 0; i < CardResponse::kNodes; ++i) {
    albedo_[i] = r.nodes[i].albedo;
    seen_[i] = r.seen(i, lc);
  }
}

glm::vec3 CardCorrection::operator()(const glm::vec3& seen) const {
  // Inverted on the luminance and applied to every channel as one factor: per
  // channel, a dark texel whose blue lies under what black fibres show but whose
  // red does not would turn a brown vane yellow.
  glm::vec3 s;
  for (int i = 0; i < 3; ++i) s[i] = std::isfinite(seen[i]) ? std::max(seen[i], 0.0f) : 0.0f;
  const float ls = luminance(s);
  if (!(ls > 0)) return glm::vec3(0.0f);
  // The albedo at which seen / card equals the texel's, linear between the nodes.
  float a = 1.0f;
  if (!(ls > seen_[0])) {
    a = 0.0f;
  } else {
    for (int i = 1; i < CardResponse::kNodes; ++i)
      if (ls <= seen_[i]) {
        const float lo = seen_[i - 1], hi = seen_[i];
        const float t = hi > lo ? (ls - lo) / (hi - lo) : 1.0f;
        a = albedo_[i - 1] + t * (albedo_[i] - albedo_[i - 1]);
        break;
      }
  }
  return glm::clamp(s * (a / ls), glm::vec3(0.0f), glm::vec3(1.0f));
}

glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r) {
  return CardCorrection(r, card)(seen);
}

}  // namespace plumage
