#pragma once
// The backdrop card under the feather: the white paper or black card the photo
// was taken on, a two-sided lambertian quad just below the feather (Scene builds
// it; docs/rendering.md).
#include <glm/glm.hpp>

namespace plumage {

struct BackdropSpec {
  bool enabled = false;
  glm::vec3 albedo{0.8f};   // white paper ~0.8, black card ~0.03
  float extent = 3.0f;       // card side = extent x the feather's larger side
};

}  // namespace plumage
