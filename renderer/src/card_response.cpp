#include "plumage/renderer/card_response.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/image.h"

namespace plumage {

namespace {

// Fitted by RenderMaterial.CardResponseFit (scripts/fit_card_response.sh): the
// closed vane rendered over cards 0.9, 0.5, 0.25 and 0.1 (and 0.02 for the rows with
// a medulla) at each albedo and medulla scattering, green channel, least squares in
// (1, 1/c, c).
constexpr CardResponse kHair{{{
    // clang-format off
    {0.00f, {{
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
    }}},
    {0.25f, {{
        {0.00f, 0.0193f, 0.0581f, 0.0029f},
        {0.02f, 0.1182f, 0.1288f, 0.0271f},
        {0.05f, 0.1537f, 0.1482f, 0.0405f},
        {0.10f, 0.1919f, 0.1673f, 0.0538f},
        {0.15f, 0.2187f, 0.1804f, 0.0656f},
        {0.20f, 0.2400f, 0.1916f, 0.0785f},
        {0.30f, 0.2787f, 0.2086f, 0.0934f},
        {0.40f, 0.3086f, 0.2231f, 0.1107f},
        {0.50f, 0.3354f, 0.2366f, 0.1280f},
        {0.70f, 0.3794f, 0.2588f, 0.1679f},
        {0.90f, 0.4177f, 0.2792f, 0.2051f},
        {1.00f, 0.4426f, 0.2894f, 0.2200f},
    }}},
    {0.50f, {{
        {0.00f, 0.0127f, 0.0814f, 0.0026f},
        {0.02f, 0.0750f, 0.1935f, 0.0271f},
        {0.05f, 0.0980f, 0.2242f, 0.0394f},
        {0.10f, 0.1233f, 0.2536f, 0.0547f},
        {0.15f, 0.1402f, 0.2735f, 0.0680f},
        {0.20f, 0.1552f, 0.2902f, 0.0797f},
        {0.30f, 0.1803f, 0.3153f, 0.0985f},
        {0.40f, 0.2009f, 0.3363f, 0.1195f},
        {0.50f, 0.2230f, 0.3551f, 0.1335f},
        {0.70f, 0.2549f, 0.3864f, 0.1730f},
        {0.90f, 0.2885f, 0.4138f, 0.2024f},
        {1.00f, 0.3029f, 0.4276f, 0.2220f},
    }}},
    {1.00f, {{
        {0.00f, 0.0065f, 0.1108f, 0.0017f},
        {0.02f, 0.0366f, 0.2765f, 0.0203f},
        {0.05f, 0.0493f, 0.3209f, 0.0307f},
        {0.10f, 0.0642f, 0.3632f, 0.0411f},
        {0.15f, 0.0721f, 0.3922f, 0.0533f},
        {0.20f, 0.0816f, 0.4157f, 0.0637f},
        {0.30f, 0.0967f, 0.4513f, 0.0804f},
        {0.40f, 0.1068f, 0.4817f, 0.1006f},
        {0.50f, 0.1189f, 0.5069f, 0.1153f},
        {0.70f, 0.1414f, 0.5494f, 0.1434f},
        {0.90f, 0.1591f, 0.5848f, 0.1757f},
        {1.00f, 0.1644f, 0.6028f, 0.1976f},
    }}},
    {2.00f, {{
        {0.00f, 0.0030f, 0.1344f, 0.0009f},
        {0.02f, 0.0168f, 0.3453f, 0.0119f},
        {0.05f, 0.0229f, 0.4012f, 0.0181f},
        {0.10f, 0.0297f, 0.4548f, 0.0279f},
        {0.15f, 0.0340f, 0.4912f, 0.0358f},
        {0.20f, 0.0385f, 0.5202f, 0.0440f},
        {0.30f, 0.0467f, 0.5636f, 0.0578f},
        {0.40f, 0.0536f, 0.6001f, 0.0708f},
        {0.50f, 0.0583f, 0.6300f, 0.0857f},
        {0.70f, 0.0709f, 0.6803f, 0.1080f},
        {0.90f, 0.0843f, 0.7219f, 0.1308f},
        {1.00f, 0.0898f, 0.7428f, 0.1418f},
    }}},
    {4.00f, {{
        {0.00f, 0.0018f, 0.1433f, 0.0004f},
        {0.02f, 0.0117f, 0.3707f, 0.0074f},
        {0.05f, 0.0173f, 0.4314f, 0.0113f},
        {0.10f, 0.0236f, 0.4889f, 0.0178f},
        {0.15f, 0.0257f, 0.5280f, 0.0260f},
        {0.20f, 0.0317f, 0.5587f, 0.0297f},
        {0.30f, 0.0383f, 0.6051f, 0.0401f},
        {0.40f, 0.0419f, 0.6439f, 0.0538f},
        {0.50f, 0.0460f, 0.6764f, 0.0651f},
        {0.70f, 0.0564f, 0.7295f, 0.0843f},
        {0.90f, 0.0641f, 0.7729f, 0.1082f},
        {1.00f, 0.0683f, 0.7941f, 0.1190f},
    }}},
    {8.00f, {{
        {0.00f, 0.0019f, 0.1443f, 0.0002f},
        {0.02f, 0.0116f, 0.3737f, 0.0066f},
        {0.05f, 0.0160f, 0.4351f, 0.0120f},
        {0.10f, 0.0216f, 0.4930f, 0.0187f},
        {0.15f, 0.0256f, 0.5317f, 0.0235f},
        {0.20f, 0.0291f, 0.5633f, 0.0311f},
        {0.30f, 0.0359f, 0.6103f, 0.0401f},
        {0.40f, 0.0417f, 0.6491f, 0.0519f},
        {0.50f, 0.0449f, 0.6813f, 0.0635f},
        {0.70f, 0.0522f, 0.7348f, 0.0861f},
        {0.90f, 0.0599f, 0.7790f, 0.1059f},
        {1.00f, 0.0664f, 0.8000f, 0.1163f},
    }}},
    // clang-format on
}}};

constexpr CardResponse kSubstructure{{{
    // clang-format off
    {0.00f, {{
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
    }}},
    {0.25f, {{
        {0.00f, 0.0254f, 0.0811f, 0.0039f},
        {0.02f, 0.1297f, 0.1716f, 0.0352f},
        {0.05f, 0.1632f, 0.1942f, 0.0521f},
        {0.10f, 0.2027f, 0.2148f, 0.0640f},
        {0.15f, 0.2264f, 0.2284f, 0.0776f},
        {0.20f, 0.2472f, 0.2399f, 0.0864f},
        {0.30f, 0.2807f, 0.2550f, 0.1002f},
        {0.40f, 0.3053f, 0.2676f, 0.1154f},
        {0.50f, 0.3284f, 0.2778f, 0.1233f},
        {0.70f, 0.3614f, 0.2935f, 0.1487f},
        {0.90f, 0.3902f, 0.3068f, 0.1689f},
        {1.00f, 0.4054f, 0.3131f, 0.1765f},
    }}},
    {0.50f, {{
        {0.00f, 0.0202f, 0.1099f, 0.0031f},
        {0.02f, 0.0891f, 0.2456f, 0.0352f},
        {0.05f, 0.1125f, 0.2778f, 0.0492f},
        {0.10f, 0.1334f, 0.3080f, 0.0655f},
        {0.15f, 0.1491f, 0.3270f, 0.0789f},
        {0.20f, 0.1632f, 0.3420f, 0.0858f},
        {0.30f, 0.1793f, 0.3643f, 0.1060f},
        {0.40f, 0.2007f, 0.3811f, 0.1137f},
        {0.50f, 0.2127f, 0.3952f, 0.1250f},
        {0.70f, 0.2293f, 0.4180f, 0.1544f},
        {0.90f, 0.2510f, 0.4346f, 0.1690f},
        {1.00f, 0.2577f, 0.4427f, 0.1795f},
    }}},
    {1.00f, {{
        {0.00f, 0.0162f, 0.1450f, 0.0025f},
        {0.02f, 0.0593f, 0.3314f, 0.0254f},
        {0.05f, 0.0726f, 0.3755f, 0.0347f},
        {0.10f, 0.0820f, 0.4160f, 0.0499f},
        {0.15f, 0.0940f, 0.4408f, 0.0552f},
        {0.20f, 0.0986f, 0.4611f, 0.0645f},
        {0.30f, 0.1071f, 0.4899f, 0.0783f},
        {0.40f, 0.1175f, 0.5121f, 0.0860f},
        {0.50f, 0.1235f, 0.5306f, 0.0970f},
        {0.70f, 0.1304f, 0.5593f, 0.1191f},
        {0.90f, 0.1424f, 0.5814f, 0.1306f},
        {1.00f, 0.1458f, 0.5933f, 0.1377f},
    }}},
    {2.00f, {{
        {0.00f, 0.0142f, 0.1719f, 0.0017f},
        {0.02f, 0.0463f, 0.3961f, 0.0148f},
        {0.05f, 0.0552f, 0.4492f, 0.0198f},
        {0.10f, 0.0620f, 0.4968f, 0.0273f},
        {0.15f, 0.0672f, 0.5272f, 0.0325f},
        {0.20f, 0.0715f, 0.5514f, 0.0370f},
        {0.30f, 0.0778f, 0.5852f, 0.0461f},
        {0.40f, 0.0801f, 0.6121f, 0.0555f},
        {0.50f, 0.0838f, 0.6335f, 0.0592f},
        {0.70f, 0.0922f, 0.6660f, 0.0684f},
        {0.90f, 0.0982f, 0.6934f, 0.0762f},
        {1.00f, 0.0992f, 0.7061f, 0.0822f},
    }}},
    {4.00f, {{
        {0.00f, 0.0139f, 0.1810f, 0.0013f},
        {0.02f, 0.0438f, 0.4183f, 0.0117f},
        {0.05f, 0.0521f, 0.4741f, 0.0144f},
        {0.10f, 0.0585f, 0.5243f, 0.0194f},
        {0.15f, 0.0630f, 0.5567f, 0.0223f},
        {0.20f, 0.0665f, 0.5813f, 0.0262f},
        {0.30f, 0.0732f, 0.6181f, 0.0305f},
        {0.40f, 0.0765f, 0.6456f, 0.0361f},
        {0.50f, 0.0800f, 0.6681f, 0.0420f},
        {0.70f, 0.0869f, 0.7035f, 0.0478f},
        {0.90f, 0.0923f, 0.7314f, 0.0523f},
        {1.00f, 0.0918f, 0.7435f, 0.0585f},
    }}},
    {8.00f, {{
        {0.00f, 0.0139f, 0.1818f, 0.0013f},
        {0.02f, 0.0445f, 0.4195f, 0.0093f},
        {0.05f, 0.0513f, 0.4762f, 0.0142f},
        {0.10f, 0.0592f, 0.5268f, 0.0183f},
        {0.15f, 0.0631f, 0.5591f, 0.0222f},
        {0.20f, 0.0665f, 0.5844f, 0.0260f},
        {0.30f, 0.0729f, 0.6203f, 0.0302f},
        {0.40f, 0.0772f, 0.6483f, 0.0332f},
        {0.50f, 0.0806f, 0.6711f, 0.0394f},
        {0.70f, 0.0854f, 0.7064f, 0.0457f},
        {0.90f, 0.0899f, 0.7352f, 0.0530f},
        {1.00f, 0.0927f, 0.7477f, 0.0551f},
    }}},
    // clang-format on
}}};

}  // namespace

const CardResponse& card_response(ShadingMode mode) { return mode == ShadingMode::Hair ? kHair : kSubstructure; }

CardCorrection::CardCorrection(const CardResponse& r, const glm::vec3& card) {
  glm::vec3 c;
  for (int i = 0; i < 3; ++i) c[i] = std::max(std::isfinite(card[i]) ? card[i] : 1.0f, 1e-3f);
  const float lc = std::max(luminance(c), 1e-3f);
  for (int i = 0; i < CardResponse::kNodes; ++i) albedo_[i] = r.rows[0].nodes[i].albedo;
  for (int j = 0; j < CardResponse::kRows; ++j) {
    sigma_s_[j] = r.rows[j].medulla_sigma_s;
    for (int i = 0; i < CardResponse::kNodes; ++i) {
      seen_[j][i] = r.seen(j, i, lc);
      for (int k = 0; k < 3; ++k) seen_rgb_[k][j][i] = r.seen(j, i, c[k]);
    }
  }
}

namespace {

// How much paler than white clear fibres a texel's brightest channel must be before it
// gets a medulla: a saturated pale colour (the pink feather's red, 4 % beyond them on
// white paper) keeps the clear fibre, whose albedo steers the other channels finely,
// where the medulla rows' steep first step (A = 0 to 0.02) would not.
constexpr float kMedullaMargin = 1.1f;

// The albedo at which a row's seen / card (linear between its nodes) equals s:
// 0 at or below the first node, 1 above the last.
template <class Seen>
float invert_row(const std::array<float, CardResponse::kNodes>& albedo, Seen&& seen, float s) {
  if (!(s > seen(0))) return 0.0f;
  for (int i = 1; i < CardResponse::kNodes; ++i)
    if (s <= seen(i)) {
      const float lo = seen(i - 1), hi = seen(i);
      const float t = hi > lo ? (s - lo) / (hi - lo) : 1.0f;
      return albedo[i - 1] + t * (albedo[i] - albedo[i - 1]);
    }
  return 1.0f;
}

}  // namespace

FibreColour CardCorrection::operator()(const glm::vec3& seen) const {
  glm::vec3 s;
  for (int i = 0; i < 3; ++i) s[i] = std::isfinite(seen[i]) ? std::max(seen[i], 0.0f) : 0.0f;
  const float top = std::max({s.x, s.y, s.z});
  constexpr int last = CardResponse::kNodes - 1;
  FibreColour out;
  if (top <= kMedullaMargin * seen_[0][last]) {
    // A clear fibre. Inverted on the luminance and applied to every channel as one
    // factor: per channel, a dark texel whose blue lies under what black fibres show
    // but whose red does not would turn a brown vane yellow.
    const float ls = luminance(s);
    if (!(ls > 0)) return out;
    const float a = invert_row(albedo_, [&](int i) { return seen_[0][i]; }, ls);
    out.albedo = glm::clamp(s * (a / ls), glm::vec3(0.0f), glm::vec3(1.0f));
    return out;
  }
  // Paler than white clear fibres: each channel on the table over its own card
  // channel (the medulla's light is mostly sent back without reaching the card, so
  // a pink card shows a white vane greener than a grey one). The scattering is the
  // largest that any channel's white fibres need to show it (linear in sigma_s
  // between the first row that reaches it and the row before), and each channel's
  // albedo is inverted on its table blended at that scattering.
  float sigma = 0.0f;
  for (int c = 0; c < 3; ++c) {
    const auto& rows = seen_rgb_[c];
    float need = sigma_s_[CardResponse::kRows - 1];
    bool reached = false;
    for (int j = 1; j < CardResponse::kRows && !reached; ++j)
      if (s[c] <= rows[j][last]) {
        const float below = rows[j - 1][last];
        const float t = s[c] > below && rows[j][last] > below ? (s[c] - below) / (rows[j][last] - below) : 0.0f;
        need = sigma_s_[j - 1] + t * (sigma_s_[j] - sigma_s_[j - 1]);
        reached = true;
      }
    if (!reached) out.clamped = true;
    sigma = std::max(sigma, need);
  }
  out.medulla_sigma_s = sigma;
  int hi = 1;
  while (hi < CardResponse::kRows - 1 && sigma_s_[hi] < sigma) ++hi;
  const int lo = hi - 1;
  const float t = std::clamp((sigma - sigma_s_[lo]) / (sigma_s_[hi] - sigma_s_[lo]), 0.0f, 1.0f);
  for (int c = 0; c < 3; ++c) {
    const auto& rows = seen_rgb_[c];
    const auto row = [&](int i) { return rows[lo][i] + t * (rows[hi][i] - rows[lo][i]); };
    if (s[c] < row(0) * 0.98f - 1e-3f || s[c] > row(last) * 1.02f + 1e-3f) out.clamped = true;
    out.albedo[c] = invert_row(albedo_, row, s[c]);
  }
  return out;
}

glm::vec3 albedo_over_card(const glm::vec3& seen, const glm::vec3& card, const CardResponse& r) {
  return CardCorrection(r, card)(seen).albedo;
}

}  // namespace plumage
