#pragma once
// The Embree scene of one feather (DESIGN §4): the shaft as a round B-spline
// curve, the barbs as ray-facing flat B-spline ribbons (hair mode), and an
// optional backdrop card under the feather. Keeps, per Embree primitive, the
// feather curve and segment it came from so a hit can be shaded.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"
#include "plumage/renderer/ray.h"
#include "plumage/renderer/shading_mode.h"

namespace plumage {

struct BackdropSpec {
  bool enabled = false;
  glm::vec3 albedo{0.8f};   // white paper ~0.8, black card ~0.03
  float extent = 3.0f;       // card side = extent x the feather's larger side
};

struct SceneOptions {
  ShadingMode mode = ShadingMode::Hair;
  BackdropSpec backdrop;
};

enum class HitKind { None, Shaft, Barb, Backdrop };

struct SurfaceHit {
  HitKind kind = HitKind::None;
  float t = 0;
  glm::vec3 p{0};              // hit point (world, mm)
  glm::vec3 ng{0, 0, 1};       // Embree's geometric normal (unnormalised)
  float u = 0, v = 0;          // Embree's hit coordinates (curves: u within the segment)
  std::uint32_t geom = kNoId;
  std::uint32_t prim = kNoId;
  std::uint32_t curve = kNoId; // index into Feather::curves (fibres only)
};

// The centreline of a curve segment at local u: position, unnormalised tangent, radius.
struct CurvePoint {
  glm::vec3 p, dp;
  float radius;
};

struct AxisBox {
  glm::vec3 lo{0}, hi{0};
  glm::vec3 centre() const { return 0.5f * (lo + hi); }
  glm::vec3 size() const { return hi - lo; }
};

class Scene {
 public:
  // Throws plumage::Error for a feather with no drawable curve, a curve with fewer
  // than 4 control points, non-finite or negative data, or a mode not built yet.
  Scene(const Feather& feather, const SceneOptions& options);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // Closest hit along the ray within [tnear, tfar]; counts a ray.
  bool intersect(const Ray& ray, SurfaceHit& hit) const;
  // Anything along the ray within [tnear, tfar]; counts a shadow ray.
  bool occluded(const Ray& ray) const;
  // A secondary ray leaving `from` in direction `d`, valid up to distance `tmax`
  // from the hit point. Handles Embree's near-origin culling of flat curves.
  Ray spawn(const SurfaceHit& from, const glm::vec3& d, float tmax = 1e30f) const;

  CurvePoint curve_point(const SurfaceHit& hit) const;
  const Feather& feather() const { return feather_; }
  const SceneOptions& options() const { return options_; }
  // Bounds of the feather's curves including radii (the backdrop is left out).
  const AxisBox& feather_bounds() const { return bounds_; }
  const AxisBox& scene_bounds() const { return scene_bounds_; }
  float backdrop_z() const { return backdrop_z_; }
  float max_barb_radius() const { return max_barb_radius_; }

  // For the benchmark that compares against bare Embree: the committed RTCScene.
  void* embree_scene() const;

 private:
  struct Primitive {
    std::uint32_t curve;     // feather curve
    std::uint32_t first_cp;  // index of the segment's first control point in the geometry's vertices
  };
  struct CurveGeometry {
    std::uint32_t id = kNoId;
    std::vector<glm::vec4> vertices;  // x, y, z, radius
    std::vector<std::uint32_t> indices;
    std::vector<Primitive> prims;
  };
  struct Embree;

  void add_curves(CurveGeometry& g, CurveKind kind, int rtc_type);
  void add_backdrop();
  const CurveGeometry* curve_geometry(std::uint32_t geom) const;
  friend struct SceneFilter;

  Feather feather_;
  SceneOptions options_;
  std::unique_ptr<Embree> rtc_;
  CurveGeometry shaft_, barbs_;
  std::uint32_t backdrop_id_ = kNoId;
  AxisBox bounds_, scene_bounds_;
  float backdrop_z_ = 0;
  float max_barb_radius_ = 0;
  float max_radius_ = 0;
};

}  // namespace plumage
