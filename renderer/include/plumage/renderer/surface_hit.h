#pragma once
// What a ray query found: the kind of surface, where, and which Embree primitive
// and feather curve it belongs to (Scene::intersect fills it; Scene::spawn starts
// the next ray from it).
#include <cstdint>

#include <glm/glm.hpp>

#include "plumage/renderer/ray.h"

namespace plumage {

// Down: a down barb (CurveKind::Down), a round tube its fibres partly fill.
enum class HitKind { None, Shaft, Barb, Down, Backdrop };

struct SurfaceHit {
  HitKind kind = HitKind::None;
  float t = 0;
  glm::vec3 p{0};              // hit point (world, mm)
  glm::vec3 ng{0, 0, 1};       // Embree's geometric normal (unnormalised)
  float u = 0, v = 0;          // Embree's hit coordinates (curves: u within the segment)
  std::uint32_t geom = kNoId;
  std::uint32_t prim = kNoId;
  std::uint32_t curve = kNoId; // index into Feather::curves (fibres only; explicit mode: the barb)
};

// The centreline of a curve segment at local u: position, unnormalised tangent, radius.
struct CurvePoint {
  glm::vec3 p, dp;
  float radius;
};

}  // namespace plumage
