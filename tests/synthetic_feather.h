#pragma once
// A feather drawn from its definition, with known shaft, outline, barb angle
// and barb spacing: the ground truth for photo-analysis tests and benchmarks.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <optional>
#include <random>
#include <vector>

#include "plumage/common/constants.h"
#include "plumage/common/image.h"

namespace plumage::synthetic {


// A feather drawn from its definition: shaft from `calamus` along `dir` for
// `length` px; vanes from 20% of the length to the tip with half-widths
// w_side * sin(pi u)^0.6; straight barbs leaving the shaft at `theta_deg`
// toward the tip, one every `spacing` px along the shaft.
struct SyntheticFeather {
  int width = 900, height = 700;
  glm::dvec2 calamus{250, 640};
  double dir_deg = -62;  // image angle of calamus->tip (y down, so negative is up)
  double length = 560, shaft_width = 5;
  double w_left = 60, w_right = 95;
  double theta_deg = 38, spacing = 9;
  double barb_contrast = 0.28;  // barbs: brightness 1 - c .. 1 (times the vane colour)
  bool dark_background = false;
  double noise = 0.02;
  unsigned seed = 1;
  // Flight feathers on a scanned sheet: a pale fringe this wide along the outer
  // edge of the wider vane, and the feather's cast shadow (darker than the card)
  // this wide beyond that edge. 0: neither.
  double fringe = 0, shadow = 0;
  // How far the rachis colour is from the vane's (1: the default dark rachis,
  // smaller: a faint one).
  float rachis_contrast = 1;
  // The bare quill below the vane in its own colour (sRGB; a white calamus below a
  // dark rachis); unset: the rachis's.
  std::optional<glm::vec3> calamus_colour;
  // A downy base: over this fraction of the vane from its base, on side
  // `downy_side` (-1 left, +1 right, 0 both), the barbs are soft and faint
  // (downy_contrast times barb_contrast). 0: none.
  double downy_to = 0;
  int downy_side = 0;
  double downy_contrast = 0.15;
  // A rachis hidden from this fraction of the length on (the barbs drawn across
  // it, as the blue jay's bars hide its rachis); 1: seen to the tip.
  double rachis_seen_to = 1;
  // A line as dark as the rachis through the vane from fraction decoy_from to
  // decoy_to of the length: it leaves where the rachis runs and comes back,
  // decoy_bulge px to the side at its middle (negative: left), as the colour
  // boundary between a brown and a blue vane or a bar's edge does; drawn only
  // where it is at least decoy_gap px from the rachis. 0: none.
  double decoy_from = 0, decoy_to = 0, decoy_bulge = 0, decoy_gap = 0;
  // A plume: over this share of each barb period the card shows between the
  // barbs (0: a closed vane), each barb curling plume_curl px to either side
  // (a wave of about a third of the vane's width along it).
  double plume_open = 0, plume_curl = 4;

  glm::dvec2 dir() const { return {std::cos(dir_deg * kPi / 180), std::sin(dir_deg * kPi / 180)}; }
  glm::dvec2 right() const { return {-dir().y, dir().x}; }  // feather +X, tip up
  glm::dvec2 tip() const { return calamus + dir() * length; }
  // How far along the shaft from the calamus an image point lies.
  double along(double x, double y) const { return glm::dot(glm::dvec2(x, y) - calamus, dir()); }
  double vane_start() const { return 0.2 * length; }
  double half_width(double y, int side) const {
    if (y < vane_start() || y > length) return 0.0;
    const double u = (y - vane_start()) / (length - vane_start());
    return (side < 0 ? w_left : w_right) * std::pow(std::sin(kPi * u), 0.6);
  }
  int wide_side() const { return w_right >= w_left ? 1 : -1; }
  // 0 outside, 1 vane, 2 shaft, 3 fringe, 4 cast shadow (outside the feather),
  // 5 the decoy line, 6 the card between a plume's barbs (inside its outline);
  // and the barb brightness factor.
  int classify(glm::dvec2 p, double& shade) const {
    const glm::dvec2 d = p - calamus;
    const double y = glm::dot(d, dir()), x = glm::dot(d, right());
    shade = 1.0;
    if (y >= 0 && y <= rachis_seen_to * length && std::fabs(x) <= 0.5 * shaft_width * (1.0 - 0.5 * y / length))
      return 2;
    if (y < 0 || y > length) return 0;
    const int side = x < 0 ? -1 : 1;
    const double hw = half_width(y, side);
    if (std::fabs(x) > hw) return side == wide_side() && hw > 0 && std::fabs(x) <= hw + shadow ? 4 : 0;
    if (side == wide_side() && std::fabs(x) > hw - fringe) return 3;
    if (decoy_bulge != 0 && y > decoy_from * length && y < decoy_to * length) {
      const double u = (y - decoy_from * length) / ((decoy_to - decoy_from) * length);
      const double off = decoy_bulge * std::sin(kPi * u);
      if (std::fabs(off) >= decoy_gap && std::fabs(x - off) <= 0.5 * shaft_width) return 5;
    }
    double phase = (y - std::fabs(x) / std::tan(theta_deg * kPi / 180)) / spacing;
    if (plume_open > 0) {
      // Loose barbs: lines (1 - plume_open) of a period wide that wave along
      // themselves; the card between them (class 6, drawn as the card).
      phase += plume_curl / spacing * std::sin(2 * kPi * std::fabs(x) / std::max(0.3 * hw, 1.0));
      const double f = phase - std::floor(phase);
      if (std::min(f, 1.0 - f) > 0.5 * (1.0 - plume_open)) return 6;
      return 1;
    }
    const bool downy = (downy_side == 0 || downy_side == side) &&
                       y < vane_start() + downy_to * (length - vane_start());
    const double c = downy ? downy_contrast * barb_contrast : barb_contrast;
    shade = 1.0 - c + c * std::cos(2 * kPi * phase);
    return 1;
  }
  bool inside(glm::dvec2 p) const {
    double s;
    const int c = classify(p, s);
    return c != 0 && c != 4;
  }

  glm::vec3 background() const { return dark_background ? glm::vec3(0.04f) : glm::vec3(0.96f); }
  // The colour at an image point (sRGB), and the class classify() gives it.
  glm::vec3 colour_at(glm::dvec2 p, int& cls) const {
    const glm::vec3 bg = background();
    const glm::vec3 vane =
        dark_background ? glm::vec3(0.85f, 0.72f, 0.66f) : glm::vec3(0.80f, 0.50f, 0.48f);
    const glm::vec3 rachis = glm::mix(vane, glm::vec3(0.55f, 0.18f, 0.10f), rachis_contrast);
    double shade;
    cls = classify(p, shade);
    const double a = along(p.x, p.y);
    return cls == 0 || cls == 6 ? bg
           : cls == 2 ? (calamus_colour && a < vane_start() ? *calamus_colour : rachis)
           : cls == 5 ? rachis
           : cls == 3 ? glm::mix(vane, glm::vec3(1.f), 0.6f)
           : cls == 4 ? bg * 0.8f
                      : vane * float(shade);
  }

  // sRGB-valued picture, 3x3 supersampled, blurred, with Gaussian noise.
  Image draw(int channels = 3) const {
    const Image img = supersampled([&](glm::dvec2 p) {
      int cls;
      return colour_at(p, cls);
    });
    return finish(img, channels, [&](glm::dvec2 p) { return inside(p); });
  }

  // This picture's size, each pixel the mean of `colour` (sRGB) at 3x3 points in it.
  template <class Colour>
  Image supersampled(Colour colour) const {
    Image img(width, height, 3);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        glm::vec3 acc(0.f);
        for (int sy = 0; sy < 3; ++sy)
          for (int sx = 0; sx < 3; ++sx) acc += colour(glm::dvec2(x + (sx + 0.5) / 3.0, y + (sy + 0.5) / 3.0));
        img.set_rgb(x, y, acc / 9.0f);
      }
    return img;
  }

  // The picture `img` (sRGB, 3 channels) blurred, with this feather's noise, as a
  // linear image of `channels` (4: alpha is `inside_at`).
  template <class Inside>
  Image finish(const Image& img, int channels, Inside inside_at) const {
    Image blurred = img;
    for (int y = 1; y + 1 < height; ++y)
      for (int x = 1; x + 1 < width; ++x) {
        glm::vec3 s(0.f);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            s += img.rgb(x + dx, y + dy) * float((2 - std::abs(dx)) * (2 - std::abs(dy)));
        blurred.set_rgb(x, y, s / 16.0f);
      }
    std::mt19937 rng(seed);
    std::normal_distribution<float> n(0.f, float(noise));
    Image out(width, height, channels);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const glm::vec3 c = blurred.rgb(x, y);
        float* p = out.at(x, y);
        if (channels == 1) {
          p[0] =
              srgb_to_linear(std::clamp(0.3f * c.x + 0.59f * c.y + 0.11f * c.z + n(rng), 0.f, 1.f));
          continue;
        }
        for (int k = 0; k < 3; ++k) p[k] = srgb_to_linear(std::clamp(c[k] + n(rng), 0.f, 1.f));
        if (channels == 4) p[3] = inside_at({x + 0.5, y + 0.5}) ? 1.f : 0.f;
      }
    return out;
  }
};

// Feathers lying over each other, later ones on top (a shingled row on a sheet):
// each point takes the colour of the topmost feather there (cast shadows are
// not drawn over other feathers). The picture's size, card, noise and seed are
// the first feather's.
inline Image draw_overlapping(const std::vector<SyntheticFeather>& layers) {
  const SyntheticFeather& base = layers.front();
  auto topmost = [&](glm::dvec2 p, glm::vec3& colour) {
    for (std::size_t k = layers.size(); k-- > 0;) {
      int cls;
      const glm::vec3 c = layers[k].colour_at(p, cls);
      if (cls != 0 && cls != 4) return colour = c, true;
    }
    return colour = base.background(), false;
  };
  const Image img = base.supersampled([&](glm::dvec2 p) {
    glm::vec3 c;
    topmost(p, c);
    return c;
  });
  return base.finish(img, 3, [&](glm::dvec2 p) { glm::vec3 c; return topmost(p, c); });
}

}  // namespace plumage::synthetic
