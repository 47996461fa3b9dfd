#include "plumage/renderer/film.h"

#include <cmath>

namespace plumage {

Film::Film(int width, int height) : image_(width, height, 3) {}

Image Film::developed(float exposure) const {
  Image out = image_;
  const float k = std::exp2(exposure);
  for (float& v : out.pixels) v *= k;
  return out;
}

void Film::write(const std::filesystem::path& path, float exposure) const { write_image(path, developed(exposure)); }

}  // namespace plumage
