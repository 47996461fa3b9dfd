#include "plumage/renderer/film.h"
#include "plumage/common/image.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "plumage/common/error.h"

namespace plumage {

float border_luminance(const Image& img) {
  if (img.empty() || img.width < 1 || img.height < 1) return 0.0f;
  std::vector<float> lum;
  const auto add = [&](int x, int y) {
    const glm::vec3 c = img.rgb(x, y);
    lum.push_back(luminance(c));
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

Film::Film(int width, int height, bool with_variance)
    : image_(width, height, 3), variance_(with_variance ? Image(width, height, 3) : Image()) {}

namespace {
// `img` times k, each value kept within ±FLT_MAX and a NaN product read as 0, so
// that no written image holds Inf or NaN.
Image scaled(const Image& img, float k) {
  Image out = img;
  for (float& v : out.pixels) {
    const float s = v * k;
    v = std::isnan(s) ? 0.0f : std::clamp(s, -FLT_MAX, FLT_MAX);
  }
  return out;
}
}  // namespace

Image Film::developed(float exposure) const {
  const float k = std::exp2(exposure);
  if (!std::isfinite(k))
    throw Error("exposure " + std::to_string(exposure) + " stops scales pixels by a factor a float cannot hold; "
                "give a finite exposure in [-64, 64]");
  return scaled(image_, k);
}

Image Film::developed_variance(float exposure) const {
  if (variance_.empty() && width() > 0 && height() > 0)
    throw Error("the film was rendered without its variance (RenderSettings::keep_variance)");
  return scaled(variance_, std::exp2(2 * exposure));
}

void Film::write(const std::filesystem::path& path, float exposure) const { write_image(path, developed(exposure)); }

}  // namespace plumage
