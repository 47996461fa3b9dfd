// The backdrop card (backdrop.h): a quad at backdrop_z_, centred under the
// feather, `extent` times its larger side.
#include <algorithm>

#include "embree_device.h"

namespace plumage {

void Scene::add_backdrop() {
  const glm::vec3 c = bounds_.centre(), s = bounds_.size();
  const float half = 0.5f * options_.backdrop.extent * std::max({s.x, s.y, 1e-3f});
  static const float kQuad[4][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  RTCGeometry geom = rtcNewGeometry(shared_device(), RTC_GEOMETRY_TYPE_QUAD);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
  for (int i = 0; i < 4; ++i) {
    v[3 * i + 0] = c.x + half * kQuad[i][0];
    v[3 * i + 1] = c.y + half * kQuad[i][1];
    v[3 * i + 2] = backdrop_z_;
  }
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), 1));
  for (unsigned i = 0; i < 4; ++i) idx[i] = i;
  rtcCommitGeometry(geom);
  backdrop_id_ = rtcAttachGeometry(rtc_->scene, geom);
  rtcReleaseGeometry(geom);
  scene_bounds_.lo = glm::min(bounds_.lo, glm::vec3(c.x - half, c.y - half, backdrop_z_));
  scene_bounds_.hi = glm::max(bounds_.hi, glm::vec3(c.x + half, c.y + half, backdrop_z_));
}

}  // namespace plumage
