#include "plumage/renderer/environment_light.h"
#include "plumage/common/image.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"

namespace plumage {
namespace {

// Index i with cdf[i] <= x < cdf[i+1] in a non-decreasing table of n+1 entries.
int find_interval(const float* cdf, int n, float x) {
  const float* it = std::upper_bound(cdf, cdf + n + 1, x);
  return std::clamp(int(it - cdf) - 1, 0, n - 1);
}

}  // namespace

EnvironmentLight::EnvironmentLight(const glm::vec3& radiance) : constant_(radiance) {
  if (!(radiance.x >= 0 && radiance.y >= 0 && radiance.z >= 0) || !std::isfinite(radiance.x + radiance.y + radiance.z))
    throw Error("environment colour must be finite and non-negative");
  mean_luminance_ = luminance(radiance);
}

EnvironmentLight::EnvironmentLight(const std::filesystem::path& latlong, float scale)
    : image_(read_image(latlong)) {
  const int W = image_.width, H = image_.height;
  if (W < 2 || H < 1) throw Error(Location{latlong.string()}, "environment map is too small (need at least 2x1 pixels)");
  weight_.resize(std::size_t(W) * H);
  for (int y = 0; y < H; ++y) {
    const float sin_t = std::sin(kPiF * (y + 0.5f) / H);
    for (int x = 0; x < W; ++x) {
      glm::vec3 c = image_.rgb(x, y) * scale;
      if (!(c.x >= 0 && c.y >= 0 && c.z >= 0) || !std::isfinite(c.x + c.y + c.z))
        throw Error(Location{latlong.string()}, "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                    ") is negative or not finite; an environment map holds radiance >= 0");
      image_.set_rgb(x, y, c);
      weight_[std::size_t(y) * W + x] = luminance(c) * sin_t;
    }
  }
  col_cdf_.assign(std::size_t(H) * (W + 1), 0.0f);
  row_cdf_.assign(H + 1, 0.0f);
  for (int y = 0; y < H; ++y) {
    float* cdf = &col_cdf_[std::size_t(y) * (W + 1)];
    for (int x = 0; x < W; ++x) cdf[x + 1] = cdf[x] + weight_[std::size_t(y) * W + x];
    row_cdf_[y + 1] = row_cdf_[y] + cdf[W];
  }
  total_ = row_cdf_[H];
  double solid = 0;  // sum of the pixels' sin(theta), the weights' solid-angle measure
  for (int y = 0; y < H; ++y) solid += double(W) * std::sin(kPiF * (y + 0.5f) / H);
  mean_luminance_ = solid > 0 ? float(double(total_) / solid) : 0.0f;
}

glm::vec3 EnvironmentLight::Le(const glm::vec3& d) const {
  if (image_.empty()) return constant_;
  const float theta = std::acos(std::clamp(d.z, -1.0f, 1.0f));
  float phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * kPiF;
  const int x = std::clamp(int(phi / (2 * kPiF) * image_.width), 0, image_.width - 1);
  const int y = std::clamp(int(theta / kPiF * image_.height), 0, image_.height - 1);
  return image_.rgb(x, y);
}

EnvSample EnvironmentLight::sample(const glm::vec2& u) const {
  if (image_.empty() || !(total_ > 0)) {
    // Uniform sphere.
    const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    const float phi = 2 * kPiF * u.y;
    const glm::vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
    return {wi, Le(wi), 1.0f / (4 * kPiF)};
  }
  const int W = image_.width, H = image_.height;
  const float ry = u.y * total_;
  const int y = find_interval(row_cdf_.data(), H, ry);
  const float* cdf = &col_cdf_[std::size_t(y) * (W + 1)];
  const float row_total = cdf[W];
  const float rx = u.x * row_total;
  const int x = find_interval(cdf, W, rx);
  // Continuous position inside the chosen pixel.
  const float fy = (ry - row_cdf_[y]) / std::fmax(row_cdf_[y + 1] - row_cdf_[y], 1e-30f);
  const float fx = (rx - cdf[x]) / std::fmax(cdf[x + 1] - cdf[x], 1e-30f);
  const float theta = kPiF * (y + std::clamp(fy, 0.0f, 1.0f)) / H;
  const float phi = 2 * kPiF * (x + std::clamp(fx, 0.0f, 1.0f)) / W;
  const float st = std::sin(theta);
  const glm::vec3 wi{st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
  return {wi, image_.rgb(x, y), pdf(wi)};
}

float EnvironmentLight::pdf(const glm::vec3& d) const {
  if (image_.empty() || !(total_ > 0)) return 1.0f / (4 * kPiF);
  const float theta = std::acos(std::clamp(d.z, -1.0f, 1.0f));
  const float st = std::sin(theta);
  if (!(st > 0)) return 0.0f;
  float phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * kPiF;
  const int x = std::clamp(int(phi / (2 * kPiF) * image_.width), 0, image_.width - 1);
  const int y = std::clamp(int(theta / kPiF * image_.height), 0, image_.height - 1);
  // Density over the unit (u, v) square, then d(omega) = 2 pi^2 sin(theta) du dv.
  const float p_uv = weight_[std::size_t(y) * image_.width + x] / total_ * float(image_.width) * float(image_.height);
  return p_uv / (2 * kPiF * kPiF * st);
}

}  // namespace plumage
