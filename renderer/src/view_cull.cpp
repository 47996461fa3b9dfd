#include "plumage/renderer/view_cull.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plumage {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

CurveKeep keep_all() {
  return [](const Bounds3f&) { return true; };
}

}  // namespace

std::vector<char> keep_curves(const SceneCull& cull, std::span<const Bounds3f> curve_boxes,
                              const Bounds3f& feather_bounds, float floor_z) {
  std::vector<char> keep(curve_boxes.size(), 1);
  if (!cull) return keep;
  const CurveKeep keep_box = cull(feather_bounds, floor_z);
  for (std::size_t i = 0; i < keep.size(); ++i) keep[i] = keep_box(curve_boxes[i]) ? 1 : 0;
  return keep;
}

CurveKeep view_cull(const Camera& camera, const LightSet& lights, const Bounds3f& fb, float floor_z, float margin) {
  const float top = fb.hi.z;
  if (lights.environment() || !(margin >= 0)) return keep_all();

  // XY rectangle of the view frustum between floor_z and top: the frustum's corner
  // rays cut both planes, and the frustum between them is their convex hull.
  glm::vec2 lo(kInf), hi(-kInf);
  const float W = float(camera.width()), H = float(camera.height());
  for (const glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(W, 0), glm::vec2(0, H), glm::vec2(W, H)}) {
    const Ray r = camera.generate(corner.x, corner.y);
    for (const float z : {floor_z, top}) {
      if (!(r.o.z > top) || !(r.d.z < 0)) return keep_all();
      const float t = (z - r.o.z) / r.d.z;
      const glm::vec3 p = r.o + t * r.d;
      lo = glm::min(lo, glm::vec2(p));
      hi = glm::max(hi, glm::vec2(p));
    }
  }
  const glm::vec2 grow = margin * (hi - lo);
  lo -= grow;
  hi += grow;

  // A caster at height z over a seen point at height >= floor_z, on the segment
  // toward a light, lies within (z - floor_z) x run/rise of it horizontally.
  float slope = 0;
  for (const SphereLight& l : lights.spheres()) {
    const float rise = l.centre.z - l.radius - top;
    if (!(rise > 0)) return keep_all();
    const glm::vec2 c(l.centre);
    const glm::vec2 far = glm::max(glm::abs(c - lo), glm::abs(c - hi));
    slope = std::max(slope, (glm::length(far) + l.radius) / rise);
  }
  // Directional lights are not exposed by LightSet; count() tells if there are any.
  if (lights.count() != lights.spheres().size()) return keep_all();

  return [lo, hi, slope, floor_z](const Bounds3f& b) {
    const float reach = slope * std::max(0.0f, b.hi.z - floor_z);
    return b.hi.x >= lo.x - reach && b.lo.x <= hi.x + reach && b.hi.y >= lo.y - reach && b.lo.y <= hi.y + reach;
  };
}

SceneCull view_cull_for(const ViewSpec& view, const DomeRig& rig, float margin) {
  return [view, rig, margin](const Bounds3f& fb, float floor_z) {
    // The camera and the lights render_view() will use.
    const Camera camera(view.camera, view.width, view.height, fb);
    return view_cull(camera, view_lights(fb, rig, view), fb, floor_z, margin);
  };
}

}  // namespace plumage
