#pragma once
// A render's colour brought to the photo's by rendering (docs/analysis.md, "Colour
// calibrated by rendering"). The card-response table (card_response.h) inverts a
// photo's texels for a generic closed vane under the dome; the feather actually
// rendered, in its own pose, shading mode, light and card, differs from that vane
// (how open its ribbons are, how much of its R lobe the camera sees, its shaft), so
// its mean colour misses the photo's by ΔE00 1–4. Calibration renders cheap probes
// of that very scene, measures their mean linear RGB inside the photo's feather
// mask, and finds per channel the gain on the photo texture's mean, applied as a
// shift of every texel (ViewSpec::photo_gain, FibreMaterial::set_card), at which
// the render's mean equals the photo's: a secant search, since the response is
// close to affine in the gain (a floor of light that never reaches the card plus a
// slope).
#include <functional>
#include <vector>

#include <glm/glm.hpp>

namespace plumage {

struct CalibrationSettings {
  int probes = 3;               // probe renders per shading mode (0: no calibration)
  int spp_divisor = 32;         // a probe takes the final render's spp / this (at least 1)
  double tolerance_de = 0.5;    // stop once a probe's mean colour is this close (ΔE00)
  float min_gain = 0.125f, max_gain = 8.0f;  // the gain's range per channel
};

struct CalibrationProbe {
  glm::vec3 gain{1.0f};
  glm::vec3 render_mean{0.0f};  // linear RGB inside the photo's feather mask
  double de2000 = 0;            // between render_mean and the photo's mean
};

struct ColourCalibration {
  glm::vec3 gain{1.0f};                 // what the final render takes
  std::vector<CalibrationProbe> probes;  // in the order rendered; probes[0] at gain 1
};

// The next gain to try from the probes so far (at least one), per channel: the
// first step scales by photo / render; later steps follow the secant through the
// last two probes where its slope is 0.2-2 times the ratio step's (render / gain),
// else scale again. Where the render's luminance barely followed the last step
// toward the photo (its secant 0-0.1 times the ratio step's: the render
// saturates), every channel goes back to its gain before that step. Each step is at most a factor 4, and the gain stays in
// [min_gain, max_gain]. A channel the render does not reach (render mean <= 0, or
// not finite: calibrate_colour takes it as 0) keeps its gain.
glm::vec3 next_gain(const std::vector<CalibrationProbe>& probes, const glm::vec3& photo_mean,
                    const CalibrationSettings& settings = {});

// Probes `render_mean(gain)` (a render of the scene with ViewSpec::photo_gain =
// gain, measured inside the photo's mask) from gain 1 up to settings.probes times,
// stopping early within tolerance_de; the result's gain is the first probe's within
// tolerance, else next_gain after the last probe where that probe is the closest
// yet, else the closest probe's. With probes = 0, gain 1 and no probes.
ColourCalibration calibrate_colour(const std::function<glm::vec3(const glm::vec3& gain)>& render_mean,
                                   const glm::vec3& photo_mean, const CalibrationSettings& settings = {});

}  // namespace plumage
