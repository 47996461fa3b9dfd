#pragma once
// A one-feather layout.json as `plumage analyze` would write it for a drawn
// 800x800 photo at 0.1 mm per pixel: a 60 mm shaft along +Y, vanes 8 sin(pi t) mm
// wide, barbs every 0.4 mm at 50 - 20 t degrees (at station `odd_station`, when
// given, an implausible 120 degrees that layout -> params must repair).
#include <cmath>
#include <optional>

#include "plumage/common/bspline.h"
#include "plumage/layout/layout.h"

namespace plumage::test {

inline Layout drawn_layout(int id = 1, std::optional<int> odd_station = std::nullopt) {
  Layout layout;
  layout.source_image = "drawn.png";
  layout.image_width = 800, layout.image_height = 800, layout.background = "light";
  layout.scale.mm_per_px = 0.1;
  FeatherLayout f;
  f.id = id;
  f.bbox_px = {300, 100, 200, 600};
  f.outline_px = {{300, 100}, {500, 100}, {500, 700}, {300, 700}};
  f.albedo = {"layout.feather" + std::to_string(id) + ".albedo.png", 20, 60, {-10, 70}, 1.0, 1.0, {}};
  f.shaft_mm = BSpline2({{0, -20}, {0, 0}, {0, 20}, {0, 40}, {0, 60}, {0, 80}});
  f.length_mm = 60;
  f.shaft_width_mm = 0.6;
  f.feather_from_image = glm::dmat3x2(glm::dvec2(0.1, 0), glm::dvec2(0, -0.1), glm::dvec2(0));
  f.image_from_feather = glm::dmat3x2(glm::dvec2(10, 0), glm::dvec2(0, -10), glm::dvec2(0));
  for (int i = 0; i < 12; ++i) {
    const double t = (i + 0.5) / 12;
    f.stations_t.push_back(t);
    for (VaneProfile* v : {&f.left, &f.right}) {
      v->width_mm.push_back(8 * std::sin(3.14159 * t)), v->width_confidence.push_back(1);
      v->barb_angle_deg.push_back(odd_station && i == *odd_station ? 120 : 50 - 20 * t);
      v->barb_angle_confidence.push_back(0.9);
      v->barb_spacing_mm.push_back(0.4), v->barb_spacing_confidence.push_back(0.8);
    }
  }
  layout.feathers.push_back(f);
  return layout;
}

}  // namespace plumage::test
