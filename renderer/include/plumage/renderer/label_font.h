#pragma once
// A tiny built-in 5x7 bitmap font for labelling panels of rendered images
// (`plumage compare`): upper-case letters (lower case is drawn as upper case),
// digits and a little punctuation; anything else is drawn as a box.
#include <string_view>

#include <glm/glm.hpp>

#include "plumage/common/image.h"

namespace plumage {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// Width and height in pixels of `text` drawn at `scale` (pixels per font pixel).
int text_width(std::string_view text, int scale);
inline int text_height(int scale) { return kGlyphHeight * scale; }

// Draws `text` with its top-left corner at (x, y); pixels outside the image are
// skipped, so a label may be clipped but never writes out of bounds.
void draw_text(Image& img, int x, int y, std::string_view text, const glm::vec3& colour, int scale = 2);

// A filled rectangle, clipped to the image (a label's background).
void fill_rect(Image& img, int x, int y, int w, int h, const glm::vec3& colour);

}  // namespace plumage
