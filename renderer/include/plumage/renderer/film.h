#pragma once
// The film: per-pixel mean of the radiance samples, then exposure (a factor
// 2^exposure) on the way out. EXR keeps linear floats; PNG is sRGB (write_image).
#include <filesystem>

#include <glm/glm.hpp>

#include "plumage/common/image.h"

namespace plumage {

// The median luminance (Rec. 709, linear) of an image's outermost rows and
// columns: the level of the card a photo was taken on. 0 for an empty image.
float border_luminance(const Image& img);

class Film {
 public:
  // `with_variance`: the film also holds each pixel's variance of the mean.
  Film(int width, int height, bool with_variance = false);
  // Each pixel is written by one tile only, so no locking.
  void set(int x, int y, const glm::vec3& mean_radiance) { image_.set_rgb(x, y, mean_radiance); }
  // Per channel, the variance of the pixel's mean (the samples' variance over
  // their count; 0 where fewer than two samples were taken).
  void set_variance(int x, int y, const glm::vec3& variance_of_mean) {
    if (!variance_.empty()) variance_.set_rgb(x, y, variance_of_mean);
  }
  int width() const { return image_.width; }
  int height() const { return image_.height; }
  // The image scaled by 2^exposure, each value kept within ±FLT_MAX so that no
  // written image holds Inf. Throws plumage::Error when 2^exposure is not finite.
  Image developed(float exposure) const;
  void write(const std::filesystem::path& path, float exposure) const;
  // The variances scaled as developed() scales the means (by 4^exposure). Throws
  // plumage::Error for a film made without them.
  Image developed_variance(float exposure) const;

 private:
  Image image_;
  Image variance_;
};

}  // namespace plumage
