#pragma once
// The Embree scene of one feather (DESIGN §4): the shaft as a round B-spline
// curve, the barbs as ray-facing flat B-spline ribbons (hair mode) or as
// normal-oriented ribbons lying in the vane (substructure mode, DESIGN §5) or as
// their rami and barbules, real round curves (explicit mode, explicit_geometry.h),
// and an optional backdrop card under the feather. Keeps, per Embree primitive, the
// feather curve and segment it came from so a hit can be shaded.
//
// The implementation is spread by concern: scene.cpp builds the curves,
// scene_queries.cpp answers rays and spawns secondary ones, substructure_scene.cpp
// holds substructure mode's ribbons and gap filter, explicit_scene.cpp explicit
// mode's curves, backdrop.cpp the card, embree_device.cpp the shared device, and
// view_cull.cpp the rule that leaves curves out.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/bounds.h"
#include "plumage/common/feather.h"
#include "plumage/renderer/backdrop.h"
#include "plumage/renderer/explicit_geometry.h"
#include "plumage/renderer/farfield.h"
#include "plumage/renderer/ray.h"
#include "plumage/renderer/ribbon_layers.h"
#include "plumage/renderer/shading_mode.h"
#include "plumage/renderer/substructure.h"
#include "plumage/renderer/surface_hit.h"

namespace plumage {

// Whether a curve, given its bounding box (radius included), goes into the BVH.
using CurveKeep = std::function<bool(const Bounds3f& curve_box)>;
// Makes the keep test once the scene knows the feather's bounds and the lowest z
// anything can be seen at (the backdrop's, or the feather's bottom). See view_cull.h.
using SceneCull = std::function<CurveKeep(const Bounds3f& feather_bounds, float floor_z)>;

struct SceneOptions {
  ShadingMode mode = ShadingMode::Hair;
  BackdropSpec backdrop;
  SceneCull cull{};  // empty = every curve is built (culling is off by default)
  // Explicit mode only: each fibre's cubic B-spline as a chain of Embree round
  // linear pieces (cones joined by spheres) that stays within kPolylineTolerance of
  // its radius from the curve, instead of Embree's round B-spline. Straight fibres
  // (a straight barb's ramus and barbules) are exact and intersect about twice as
  // fast; the far-field fit's patch uses it (farfield_fit.cpp).
  bool explicit_polylines = false;
};

// How far (relative to the fibre's radius) an explicit polyline may stray from its
// B-spline (SceneOptions::explicit_polylines).
inline constexpr float kPolylineTolerance = 0.02f;

class Scene {
 public:
  // Throws plumage::Error for a feather with no drawable curve, a curve with fewer
  // than 4 control points, non-finite or negative data, or a mode not built yet.
  Scene(const Feather& feather, const SceneOptions& options);
  // The same, taking the ribbon-layer map of another scene of this very feather
  // (ribbon_layer_map(); it depends on the feather alone) instead of drawing it again.
  Scene(const Feather& feather, const SceneOptions& options, std::shared_ptr<const RibbonLayers> layers);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // Closest hit along the ray within [tnear, tfar]; counts a ray. In substructure
  // mode the gaps between rami and barbules are rejected inside Embree unless
  // `keep_gaps` (for the structure AOV, which wants to see them).
  bool intersect(const Ray& ray, SurfaceHit& hit, bool keep_gaps = false) const;
  // Anything along the ray within [tnear, tfar]; counts a shadow ray.
  bool occluded(const Ray& ray) const;
  // A secondary ray leaving `from` in direction `d`, valid up to distance `tmax`
  // from the hit point. Handles Embree's near-origin culling of flat curves.
  Ray spawn(const SurfaceHit& from, const glm::vec3& d, float tmax = 1e30f) const;

  CurvePoint curve_point(const SurfaceHit& hit) const;
  // Where a shaft or ribbon hit lies along its feather curve: the curve's global
  // B-spline parameter t in [0, 1] (segment and u within it), root first.
  float curve_parameter(const SurfaceHit& hit) const;
  // Substructure mode, a barb hit: its ribbon coordinates, structure and frames.
  StructureSample structure_at(const SurfaceHit& hit) const;
  // Explicit mode, a barb hit: the ramus or barbule curve it landed on.
  const ExplicitFibre& explicit_fibre(const SurfaceHit& hit) const;
  // Farfield mode, a barb hit: the barb's frame with b turned to the distal side
  // (the far-field table's frame, farfield.h).
  Frame farfield_frame(const SurfaceHit& hit) const;
  // Farfield mode: what a vane's tables stand for (its substructure and a barbule
  // period per class of barbs; empty for a vane without barbs in the scene), and
  // the class of a barb hit (its index there).
  const std::vector<FarfieldGeometry>& farfield_geometries(VaneSide side) const {
    return farfield_geometry_[side == VaneSide::Right];
  }
  std::size_t farfield_class(const SurfaceHit& hit) const { return farfield_class_[hit.prim]; }
  // Explicit mode: the curves built (rami and barbules) and the bytes of their data.
  std::size_t explicit_curves() const { return explicit_fibres_.size(); }
  std::size_t explicit_bytes() const { return explicit_bytes_; }
  // A barb hit: the fraction of its ribbon that rami and barbules cover
  // (BarbSubstructure::covered_fraction), the same in substructure and explicit
  // mode; 1 in hair mode.
  float structure_coverage(const SurfaceHit& hit) const;
  // A barb hit: how many barb ribbons lie over its point seen from above
  // (RibbonLayers), in every mode; 1 for other hits and for a feather whose albedo
  // is not a texture (the map is only built for one).
  int ribbon_layers(const SurfaceHit& hit) const;
  // The feather's ribbon-layer map (null for a feather without an albedo texture).
  const std::shared_ptr<const RibbonLayers>& ribbon_layer_map() const { return ribbon_layers_; }
  const Feather& feather() const { return feather_; }
  const SceneOptions& options() const { return options_; }
  // Bounds of the feather's curves including radii (the backdrop is left out).
  const Bounds3f& feather_bounds() const { return bounds_; }
  const Bounds3f& scene_bounds() const { return scene_bounds_; }
  float backdrop_z() const { return backdrop_z_; }
  float max_barb_radius() const { return max_barb_radius_; }
  float max_radius() const { return max_radius_; }  // of every curve, the shaft's included
  // Curves left out of the BVH by SceneOptions::cull.
  std::size_t culled_curves() const { return culled_; }

  // For the benchmark that compares against bare Embree: the committed RTCScene.
  void* embree_scene() const;

 private:
  struct Primitive {
    std::uint32_t curve;     // feather curve
    std::uint32_t first_cp;  // index of the segment's first control point in the geometry's vertices
    std::uint32_t fibre;     // the Embree curve it is a segment of (= curve, but for explicit barbules)
  };
  struct CurveGeometry {
    std::uint32_t id = kNoId;
    std::vector<glm::vec4> vertices;  // x, y, z, radius
    std::vector<std::uint32_t> indices;
    std::vector<Primitive> prims;
    bool linear = false;  // two vertices per primitive (round linear), else four (cubic B-spline)
    std::vector<std::uint8_t> flags;  // linear: per primitive, which neighbours it joins (RTCCurveFlags)
    // Which filter lets rays through the geometry's empty space: substructure's gaps,
    // the far-field transmittance, a down barb's open tube; none (every hit counts).
    enum class Filter { None, Gaps, Farfield, Down } filter = Filter::None;
  };
  struct Embree;

  // Substructure mode, per barb primitive: the vane's substructure, where the
  // segment's arc-length samples start in arc_s_, and the barb's length.
  struct RibbonSegment {
    const BarbSubstructure* vane;
    std::uint32_t arc;
    float length;
  };
  static constexpr int kArcSamples = 8;  // per segment; linear in between

  void add_curves(CurveGeometry& g, CurveKind kind, int rtc_type);
  // The down barbs' tubes and their pass-through filter (down_scene.cpp).
  void build_down();
  // Appends to the linear geometry `g` the curve of `segments` B-spline segments
  // whose control points (x, y, z, radius) start at `cps` as one chain of round
  // linear pieces within kPolylineTolerance of it (explicit_scene.cpp).
  void append_polyline(CurveGeometry& g, const glm::vec4* cps, std::size_t segments, std::uint32_t curve,
                       std::uint32_t fibre);
  void commit_curves(CurveGeometry& g, int rtc_type);
  // One BarbSubstructure per vane that has barbs, validated (`what` names the mode).
  void make_vanes(const char* what);
  const BarbSubstructure& vane_of(std::uint32_t curve) const;
  void build_substructure(const char* what);
  void build_explicit();
  void build_farfield();
  // s and w of a point on a barb ribbon; the barb's frame too when `full_frame`.
  StructureSample ribbon_point(std::uint32_t prim, float u, const glm::vec3& p, bool full_frame) const;
  void add_backdrop();
  const CurveGeometry* curve_geometry(std::uint32_t geom) const;
  friend struct SceneFilter;
  friend struct SubstructureFilter;
  friend struct FarfieldFilter;
  friend struct DownFilter;

  Feather feather_;
  SceneOptions options_;
  std::unique_ptr<Embree> rtc_;
  // shaft_: the shaft, a round fibre; down_: the down barbs (CurveKind::Down),
  // round tubes their fibres fill to Feather::down_cover (down_scene.cpp), in every
  // mode; barbs_: the pennaceous barbs in the mode's geometry (BarbGeometry).
  CurveGeometry shaft_, down_, barbs_;
  std::uint32_t backdrop_id_ = kNoId;
  Bounds3f bounds_, scene_bounds_;
  float backdrop_z_ = 0;
  float max_barb_radius_ = 0;
  float spawn_eps_ = 0;  // spawn's margin: a few float ulps at the scene's coordinates
  float max_radius_ = 0;
  std::optional<BarbSubstructure> left_, right_;
  std::vector<RibbonSegment> ribbon_segments_;
  std::vector<float> arc_s_;
  std::vector<glm::vec3> barb_normals_;
  std::vector<ExplicitFibre> explicit_fibres_;  // explicit mode; control points live in barbs_
  std::size_t explicit_bytes_ = 0;
  std::shared_ptr<const RibbonLayers> ribbon_layers_;
  std::vector<float> explicit_coverage_;  // explicit mode: per feather curve, the ribbon coverage substructure mode gives it
  std::vector<FarfieldGeometry> farfield_geometry_[2];               // farfield mode: left, right, per class
  std::vector<std::shared_ptr<const FarfieldModel>> farfield_T_[2];  // their straight transmittance
  std::vector<std::uint8_t> farfield_class_;                         // per barb primitive
  std::vector<char> keep_;  // per feather curve: in the BVH
  std::vector<std::uint32_t> first_cp_;  // per feather curve in a shaft or ribbon geometry: its first vertex there
  std::size_t culled_ = 0;
};

}  // namespace plumage
