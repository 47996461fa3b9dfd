// Colour calibration by rendering (colour_calibration.h).
#include "plumage/pipeline/colour_calibration.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/pipeline/fidelity.h"

namespace plumage {

namespace {
constexpr float kMaxStep = 4.0f;  // per probe, a channel's gain moves by at most this factor
// A secant's slope against the ratio step's: an affine response whose floor (light
// that never reaches the card) is up to 80 % of the render gives 0.2; a response
// proportional to the gain gives 1.
constexpr float kMinSecant = 0.2f, kMaxSecant = 2.0f;
// Under this the luminance secant says the render saturates: blue-jay F26's
// substructure probes 0.08 of the ratio step's (a white plume whose render cannot
// reach the photo's white), the sheets' other calibrations that step at all 0.2
// and over or below 0 (noise).
constexpr float kSaturated = 0.1f;

// The probe whose render came closest to the photo (the first of equals).
const CalibrationProbe& closest(const std::vector<CalibrationProbe>& probes) {
  return *std::min_element(probes.begin(), probes.end(),
                           [](const CalibrationProbe& a, const CalibrationProbe& b) { return a.de2000 < b.de2000; });
}
}  // namespace

glm::vec3 next_gain(const std::vector<CalibrationProbe>& probes, const glm::vec3& photo_mean,
                    const CalibrationSettings& settings) {
  if (probes.empty()) throw Error("next_gain: no probe yet");
  const CalibrationProbe& last = probes.back();
  if (probes.size() >= 2) {
    // The last step went toward the photo and the render's luminance barely
    // followed (a secant under kSaturated of the ratio step's, not below 0: the
    // render saturates, its texels clamped at the inversion's brightest or
    // darkest fibre). More gain would only clamp more texels and tint the
    // mid-tones it still moves, most in the channel that saturates last (a white
    // plume's fluff turned pink), so every channel goes back to its gain before
    // that step.
    const CalibrationProbe& prev = probes[probes.size() - 2];
    const float dg = luminance(last.gain) - luminance(prev.gain), dr = luminance(last.render_mean) - luminance(prev.render_mean);
    const float p = luminance(photo_mean), r = luminance(last.render_mean), slope = dr / dg;
    if (std::abs(dg) > 1e-6f && std::isfinite(slope) && std::isfinite(p) && r > 0.0f && slope >= 0.0f &&
        slope < kSaturated * r / luminance(last.gain) && (dg > 0) == (p > r))
      return prev.gain;
  }
  glm::vec3 g = last.gain;
  for (int k = 0; k < 3; ++k) {
    const float p = photo_mean[k], r = last.render_mean[k], g1 = last.gain[k];
    if (!(r > 0.0f) || !std::isfinite(r) || !std::isfinite(p)) continue;
    float want = g1 * p / r;  // the render as a multiple of the gain
    if (probes.size() >= 2) {
      const CalibrationProbe& prev = probes[probes.size() - 2];
      const float dg = g1 - prev.gain[k], dr = r - prev.render_mean[k];
      // Through the last two probes: render = r + slope (gain - g1).
      // Taken only where its slope is within [kMinSecant, kMaxSecant] of the ratio
      // step's (r / g1): a channel moved by its neighbours' gains (the clear fibre's
      // albedo follows the texel's luminance) or across the inversion's clear ->
      // medulla step gives secants that would throw the gain far off.
      const float slope = dr / dg, ratio_slope = r / g1;
      if (std::abs(dg) > 1e-6f * g1 && std::isfinite(slope) && slope >= kMinSecant * ratio_slope &&
          slope <= kMaxSecant * ratio_slope)
        want = g1 + (p - r) / slope;
    }
    want = std::clamp(want, g1 / kMaxStep, g1 * kMaxStep);
    g[k] = std::clamp(want, settings.min_gain, settings.max_gain);
  }
  return g;
}

ColourCalibration calibrate_colour(const std::function<glm::vec3(const glm::vec3& gain)>& render_mean,
                                   const glm::vec3& photo_mean, const CalibrationSettings& settings) {
  ColourCalibration c;
  glm::vec3 gain(1.0f);
  for (int i = 0; i < settings.probes; ++i) {
    CalibrationProbe probe;
    probe.gain = gain;
    probe.render_mean = render_mean(gain);
    for (int k = 0; k < 3; ++k)  // a channel the render did not give counts as unreached
      if (!std::isfinite(probe.render_mean[k])) probe.render_mean[k] = 0.0f;
    probe.de2000 = ciede2000_linear_rgb(probe.render_mean, photo_mean);
    c.probes.push_back(probe);
    if (probe.de2000 <= settings.tolerance_de) {
      c.gain = gain;
      return c;
    }
    // A probe farther from the photo than an earlier one stepped across something
    // (the inversion's clear -> medulla threshold): halve the step back toward the
    // closest probe, as bisection would; else the next step of the search.
    const CalibrationProbe& best = closest(c.probes);
    gain = &best != &c.probes.back() ? 0.5f * (best.gain + probe.gain) : next_gain(c.probes, photo_mean, settings);
  }
  // Converging (every probe closer than the one before): one step beyond the last.
  // Else (a step across the inversion's clear -> medulla threshold threw a probe
  // off, and a step beyond the last could cross it again) the closest probe's gain.
  if (!c.probes.empty()) {
    bool converging = true;
    for (std::size_t i = 1; i < c.probes.size(); ++i) converging = converging && c.probes[i].de2000 < c.probes[i - 1].de2000;
    if (!converging) gain = closest(c.probes).gain;
  }
  c.gain = gain;
  return c;
}

}  // namespace plumage
