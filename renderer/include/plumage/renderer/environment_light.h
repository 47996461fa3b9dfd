#pragma once
// Light from infinitely far away in every direction: a constant colour or a
// lat-long (equirectangular) image. World +Z is the zenith (the feather's dorsal
// side faces it); image column u = phi / 2pi with phi = atan2(y, x), row v = theta / pi
// with theta measured from +Z, so the top row is the zenith.
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/image.h"

namespace plumage {

struct EnvSample {
  glm::vec3 wi;
  glm::vec3 Le;
  float pdf;  // solid angle
};

class EnvironmentLight {
 public:
  explicit EnvironmentLight(const glm::vec3& radiance);
  // The image's radiance times `scale`. Throws plumage::Error (naming the file) when
  // it cannot be read or holds negative / non-finite values.
  EnvironmentLight(const std::filesystem::path& latlong, float scale = 1.0f);

  glm::vec3 Le(const glm::vec3& d) const;
  // Importance samples the image by luminance x sin(theta) (uniform sphere for a constant).
  EnvSample sample(const glm::vec2& u) const;
  float pdf(const glm::vec3& d) const;
  // A single colour in every direction (no image).
  bool is_constant() const { return image_.empty(); }
  // Luminance averaged over the sphere of directions.
  float mean_luminance() const { return mean_luminance_; }

 private:
  glm::vec3 constant_{0};
  Image image_;
  // Piecewise-constant 2D distribution over pixels: row marginal, then column conditionals.
  std::vector<float> row_cdf_, col_cdf_;  // row_cdf_: H+1; col_cdf_: H x (W+1)
  std::vector<float> weight_;              // W x H, unnormalised
  float total_ = 0;
  float mean_luminance_ = 0;
};

}  // namespace plumage
