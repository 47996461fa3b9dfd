#include "plumage/renderer/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "plumage/common/error.h"
#include "plumage/common/number_text.h"

namespace plumage {

Camera::Camera(const CameraSpec& spec, int width, int height, const Bounds3f& fb)
    : proj_(spec.projection), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
    throw Error("resolution " + std::to_string(width) + "x" + std::to_string(height) +
                " is not usable; give WxH with both in 1..65536");
  if (!(spec.fov_deg > 0 && spec.fov_deg < 180))
    throw Error("--fov must lie strictly between 0 and 180 degrees");
  const float aspect = float(width) / float(height);
  const glm::vec3 size = glm::max(fb.size(), glm::vec3(1e-3f));
  const glm::vec3 target = spec.look_at.value_or(fb.centre());
  const float fit = 1.0f + 2.0f * std::clamp(spec.margin, 0.0f, 10.0f);
  // Visible height that holds the feather's XY extent at the chosen aspect ratio.
  const float need_h = std::max(size.y, size.x / aspect) * fit;
  const float tan_half = std::tan(0.5f * spec.fov_deg * std::numbers::pi_v<float> / 180.0f);

  if (spec.position) {
    eye_ = *spec.position;
  } else {
    // Top view: far enough that the top of the feather's box fills need_h.
    const float dist = proj_ == Projection::Perspective ? 0.5f * need_h / tan_half : 2.0f * std::max({size.x, size.y, size.z});
    eye_ = glm::vec3(target.x, target.y, fb.hi.z + dist);
  }
  // Name the real culprit before the view vectors turn into Inf or NaN below.
  const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const auto text = [](const glm::vec3& v) { return num(v.x) + "," + num(v.y) + "," + num(v.z); };
  // Beyond this a ray's origin holds no precision for the feather (and Embree's
  // traversal asserts on coordinates near the float limit).
  constexpr float kFarthest = 1e18f;
  const auto near = [&](const glm::vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}) <= kFarthest; };
  if (!finite(fb.lo) || !finite(fb.hi) || !std::isfinite(need_h) || glm::length(size) > kFarthest || !near(fb.lo) ||
      !near(fb.hi))
    throw Error("the feather's bounding box (" + text(fb.lo) + " to " + text(fb.hi) +
                " mm) is too large to frame; check the curve file's coordinates");
  if (!finite(target) || !finite(eye_) || !finite(target - eye_) || !std::isfinite(glm::length(target - eye_)) ||
      !near(target) || !near(eye_))
    throw Error(spec.position || spec.look_at
                    ? "--camera-pos/--look-at are too far out to render from; give points within 1e18 mm"
                    : "--fov " + num(spec.fov_deg) + " is too narrow to frame the feather from within 1e18 mm");
  const glm::vec3 view = target - eye_;
  if (!(glm::length(view) > 0)) throw Error("--camera-pos and --look-at are the same point");
  fwd_ = glm::normalize(view);
  const glm::vec3 side = glm::cross(fwd_, spec.up);
  if (!(glm::length(side) > 1e-6f)) throw Error("--up is parallel to the view direction; pick another up vector");
  right_ = glm::normalize(side);
  up_ = glm::cross(right_, fwd_);

  if (proj_ == Projection::Perspective) {
    half_h_ = tan_half;
  } else {
    half_h_ = 0.5f * (spec.ortho_height > 0 ? spec.ortho_height : need_h);
  }
  half_w_ = half_h_ * aspect;
}

Ray Camera::generate(float x, float y) const {
  // Film coordinates in [-1,1], +y up.
  const float sx = 2.0f * x / float(width_) - 1.0f;
  const float sy = 1.0f - 2.0f * y / float(height_);
  Ray r;
  if (proj_ == Projection::Perspective) {
    r.o = eye_;
    r.d = glm::normalize(fwd_ + sx * half_w_ * right_ + sy * half_h_ * up_);
  } else {
    r.o = eye_ + sx * half_w_ * right_ + sy * half_h_ * up_;
    r.d = fwd_;
  }
  return r;
}

float Camera::pixel_footprint(const Bounds3f& box) const {
  const float per_pixel = 2.0f * half_h_ / float(height_);
  if (proj_ == Projection::Orthographic) return per_pixel;
  // Depth along the view direction is linear, so over a box it is least at a corner.
  float depth = std::numeric_limits<float>::infinity();
  for (int c = 0; c < 8; ++c) depth = std::min(depth, glm::dot(box.corner(c) - eye_, fwd_));
  return std::max(depth, 0.0f) * per_pixel;
}

}  // namespace plumage
