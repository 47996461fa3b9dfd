#pragma once
// What the files implementing Scene share about Embree (private to the renderer):
// the one device of the process, its error check, the RTCScene a Scene owns, the
// ray-id bit that keeps substructure gaps, and the gap filter's hooks.
#include <embree3/rtcore.h>

#include <bit>
#include <cstdint>

#include "plumage/renderer/sampler.h"
#include "plumage/renderer/scene.h"

namespace plumage {

// One Embree device serves the whole process (creating one starts a thread pool).
// Throws plumage::Error when the CPU is not supported.
RTCDevice shared_device();
// Throws plumage::Error "<during>: Embree error N: ..." if the device reported one.
void throw_if_device_error(const char* during);

struct Scene::Embree {
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
  }
};

// A filter function's candidate i: its ray's origin and direction, and (Embree
// stores it in tfar during filtering) the candidate hit's distance.
struct FilterCandidate {
  glm::vec3 o, d;
  float t;
  FilterCandidate(const RTCFilterFunctionNArguments* args, unsigned i)
      : o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
          RTCRayN_org_z(args->ray, args->N, i)),
        d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
          RTCRayN_dir_z(args->ray, args->N, i)),
        t(RTCRayN_tfar(args->ray, args->N, i)) {}
  glm::vec3 point() const { return o + t * d; }
  // A uniform number in [0, 1) for this candidate on primitive `prim`: the same for
  // the same ray and candidate, whoever asks, and independent between rays (a hash
  // of the ray, the primitive and the candidate's distance). Stochastic
  // pass-through filters decide with it.
  float uniform(std::uint32_t prim) const {
    std::uint32_t h = hash_combine(std::bit_cast<std::uint32_t>(o.x), std::bit_cast<std::uint32_t>(o.y));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(o.z));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(d.x));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(d.y));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(d.z));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(t));
    return to_unit(hash_combine(h, prim));
  }
};

// The RTCRay of a plumage Ray (its origin, direction and [tnear, tfar]), all
// masks on, with ray id `id`.
inline RTCRay rtc_ray(const Ray& ray, unsigned id = 0) {
  RTCRay r;
  r.org_x = ray.o.x, r.org_y = ray.o.y, r.org_z = ray.o.z;
  r.dir_x = ray.d.x, r.dir_y = ray.d.y, r.dir_z = ray.d.z;
  r.tnear = ray.tnear;
  r.tfar = ray.tfar;
  r.time = 0;
  r.mask = 0xffffffffu;
  r.id = id;
  r.flags = 0;
  return r;
}

// The same with an empty hit, for rtcIntersect1.
inline RTCRayHit rtc_ray_hit(const Ray& ray, unsigned id = 0) {
  RTCRayHit rh;
  rh.ray = rtc_ray(ray, id);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

// Ray id bit: keep hits in the gaps (the structure AOV wants to see them).
inline constexpr unsigned kKeepGapsId = 1u;

// Substructure mode (substructure_scene.cpp): installs the gap filter on a
// normal-oriented barb geometry, and adds the rejections this thread's queries
// tallied to the shared counter (called once per query).
void attach_gap_filter(RTCGeometry geom, const Scene* scene);
void flush_gap_rejections();
// Farfield mode (farfield_scene.cpp): installs the stochastic pass-through filter.
void attach_farfield_filter(RTCGeometry geom, const Scene* scene);
// Down barbs (down_scene.cpp): installs the filter that lets a ray through a down
// barb's tube where its fibres do not fill it.
void attach_down_filter(RTCGeometry geom, const Scene* scene);

}  // namespace plumage
