#pragma once
// Laying rendered images out for people to compare (`plumage compare`): panels
// side by side at one height, each under a label strip, and contact sheets of
// many small labelled tiles under a title (the paper's Fig. 5 style).
#include <string>
#include <vector>

#include "plumage/common/image.h"

namespace plumage {

struct Panel {
  Image image;
  std::string label;
};

// Resampled (box filter over the source footprint) to `height`, aspect kept.
// Throws plumage::Error for an empty image or height < 1.
Image scale_to_height(const Image& img, int height);

// Panels left to right, each scaled to the tallest panel's height, each with its
// label in a strip above it; RGB on a dark background.
Image side_by_side(const std::vector<Panel>& panels, int label_scale = 2);

// Tiles in rows of `columns` (each scaled to the first tile's height), each with
// its label, under `title`.
Image contact_sheet(const std::vector<Panel>& tiles, int columns, const std::string& title, int label_scale = 2);

}  // namespace plumage
