#include "plumage/renderer/film.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace plumage {

float border_luminance(const Image& img) {
  if (img.empty() || img.width < 1 || img.height < 1) return 0.0f;
  std::vector<float> lum;
  const auto add = [&](int x, int y) {
    const glm::vec3 c = img.rgb(x, y);
    lum.push_back(0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z);
  };
  for (int x = 0; x < img.width; ++x) {
    add(x, 0);
    add(x, img.height - 1);
  }
  for (int y = 1; y + 1 < img.height; ++y) {
    add(0, y);
    add(img.width - 1, y);
  }
  const auto mid = lum.begin() + std::ptrdiff_t(lum.size() / 2);
  std::nth_element(lum.begin(), mid, lum.end());
  return *mid;
}

Film::Film(int width, int height) : image_(width, height, 3) {}

Image Film::developed(float exposure) const {
  Image out = image_;
  const float k = std::exp2(exposure);
  for (float& v : out.pixels) v *= k;
  return out;
}

void Film::write(const std::filesystem::path& path, float exposure) const { write_image(path, developed(exposure)); }

}  // namespace plumage
