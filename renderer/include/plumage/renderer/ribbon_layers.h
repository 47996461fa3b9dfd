#pragma once
// How many barb ribbons lie over a point of the feather's plane seen from above
// (its "layers"): neighbouring ribbons of width W overlap wherever the barbs are
// closer than W, so a vane is one ribbon deep in some places and two or three in
// others. A photo's albedo texture is the area mean of whatever the vane is deep
// there, so the albedo mapping divides it among the layers (FibreMaterial::at;
// docs/hair-bcsdf.md, "A photo's albedo over overlapping ribbons").
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"

namespace plumage {

class RibbonLayers {
 public:
  // No map: every point is one layer deep.
  RibbonLayers() = default;
  // Every barb of `feather` drawn top-down (XY) at its render radius
  // (render_radius: W/2 for a vane with a ribbon width) into a grid of cells a
  // quarter of the thinnest barb radius wide (coarser only where that would pass
  // kMaxCells), each cell counting the barbs whose band covers its centre.
  explicit RibbonLayers(const Feather& feather);

  // The count at (x, y) mm, at least 1 (a point no barb covers, e.g. off the map, is 1).
  int at(const glm::vec2& xy) const;
  float cell_mm() const { return cell_; }

  static constexpr std::size_t kMaxCells = std::size_t(1) << 23;

 private:
  glm::vec2 origin_{0};
  float cell_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> count_;
};

}  // namespace plumage
