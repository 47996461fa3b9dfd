#pragma once
// How closely a render reproduces a photo of a feather on a light card, in linear
// RGB: the mean colour inside the feather (the photo's own mask: pixels that
// differ from the card) and the card's level outside it, for the photo and for a
// render framed like it (photo-to-feather's comparison). Used by the fidelity
// test and, on comparison.png files, to measure before/after (docs/perf/render.md).
#include <algorithm>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/image.h"

namespace plumage::test {

struct PanelColours {
  glm::vec3 feather{0}, card{0};  // mean linear RGB inside / outside the mask
};

struct Fidelity {
  PanelColours photo, render;
  int feather_pixels = 0, card_pixels = 0;
};

using plumage::luminance;
// rg chromaticity r / (r+g+b), g / (r+g+b).
inline glm::vec2 chromaticity(const glm::vec3& c) {
  const float s = std::max(c.x + c.y + c.z, 1e-6f);
  return {c.x / s, c.y / s};
}

// The feather mask of a photo on a light card: the card's colour is the median of
// the border pixels; a pixel is feather when it is 10 % darker than the card in
// luminance or its chroma (max - min channel, relative to the card's level) exceeds 0.08.
inline std::vector<char> light_card_mask(const Image& photo, glm::vec3* card_out = nullptr) {
  std::vector<float> border[3];
  for (int x = 0; x < photo.width; ++x)
    for (int y : {0, photo.height - 1})
      for (int c = 0; c < 3; ++c) border[c].push_back(photo.at(x, y)[c]);
  glm::vec3 card;
  for (int c = 0; c < 3; ++c) {
    auto mid = border[c].begin() + std::ptrdiff_t(border[c].size() / 2);
    std::nth_element(border[c].begin(), mid, border[c].end());
    card[c] = *mid;
  }
  if (card_out) *card_out = card;
  const float level = std::max(luminance(card), 1e-3f);
  std::vector<char> mask(std::size_t(photo.width) * photo.height, 0);
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      const glm::vec3 p(photo.at(x, y)[0], photo.at(x, y)[1], photo.at(x, y)[2]);
      const float chroma = (std::max({p.x, p.y, p.z}) - std::min({p.x, p.y, p.z})) / level;
      mask[std::size_t(y) * photo.width + x] = luminance(p) < 0.9f * level || chroma > 0.08f;
    }
  return mask;
}

// Means of `img` inside and outside `mask` (img the same size as the mask's photo).
// The mask is eroded by `margin` pixels either way so edges (and a render's small
// misregistration) count for neither.
inline PanelColours masked_means(const Image& img, const std::vector<char>& mask, int width, int height,
                                 int margin, int* n_in = nullptr, int* n_out = nullptr) {
  glm::dvec3 in(0), out(0);
  int ni = 0, no = 0;
  for (int y = margin; y < height - margin; ++y)
    for (int x = margin; x < width - margin; ++x) {
      const char m = mask[std::size_t(y) * width + x];
      bool uniform = true;
      for (int dy = -margin; dy <= margin && uniform; ++dy)
        for (int dx = -margin; dx <= margin && uniform; ++dx)
          uniform = mask[std::size_t(y + dy) * width + (x + dx)] == m;
      if (!uniform) continue;
      const glm::dvec3 p(img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2]);
      if (m) {
        in += p;
        ++ni;
      } else {
        out += p;
        ++no;
      }
    }
  if (n_in) *n_in = ni;
  if (n_out) *n_out = no;
  return {glm::vec3(in / double(std::max(ni, 1))), glm::vec3(out / double(std::max(no, 1)))};
}

// Photo and render of the same size (linear RGB).
inline Fidelity measure_fidelity(const Image& photo, const Image& render, int margin = 3) {
  const std::vector<char> mask = light_card_mask(photo);
  Fidelity f;
  f.photo = masked_means(photo, mask, photo.width, photo.height, margin, &f.feather_pixels, &f.card_pixels);
  f.render = masked_means(render, mask, photo.width, photo.height, margin);
  return f;
}

// The panels of a side_by_side image (renderer/panel_layout.h) without their
// label strip: columns and rows whose pixels are not all the layout's dark
// background, split at the background gaps between panels.
inline std::vector<Image> split_panels(const Image& sheet) {
  const auto dark = [&](int x, int y) { return luminance({sheet.at(x, y)[0], sheet.at(x, y)[1], sheet.at(x, y)[2]}) < 0.03f; };
  // The label strip is the top rows up to the first row that is mostly not dark.
  int top = 0;
  for (; top < sheet.height; ++top) {
    int light = 0;
    for (int x = 0; x < sheet.width; ++x) light += !dark(x, top);
    if (light > sheet.width / 2) break;
  }
  std::vector<Image> panels;
  const int y_probe = std::min(sheet.height - 1, top + (sheet.height - top) / 2);
  for (int x = 0; x < sheet.width;) {
    if (dark(x, y_probe)) {
      ++x;
      continue;
    }
    int x1 = x;
    while (x1 < sheet.width && !(dark(x1, y_probe) && dark(x1, top) && dark(x1, sheet.height - 1))) ++x1;
    Image p(x1 - x, sheet.height - top, 3);
    for (int y = top; y < sheet.height; ++y)
      for (int i = x; i < x1; ++i) p.set_rgb(i - x, y - top, sheet.rgb(i, y));
    panels.push_back(std::move(p));
    x = x1;
  }
  return panels;
}

}  // namespace plumage::test
