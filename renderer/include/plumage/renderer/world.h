#pragma once
// What the path integrator traces: one feather's Scene, or many feathers placed in
// one scene (a wing, a sheet; docs/scene-format.md). Each distinct feather is a
// Scene built once, with its own material; a placement puts it into the world by a
// similarity transform (rotation, uniform scale, mirroring, translation). The
// placements are the primitives of a top-level Embree BVH; a ray that reaches one
// is carried into the feather's own frame and traced there against the feather's
// Scene, so every rule a Scene applies (gap filters, the skip of the fibre a ray
// left, near-origin culling margins) holds unchanged inside each placement, and
// memory and build time grow with the distinct feathers, not the placements.
//
// Shading happens in the feather's frame too: the integrator turns the outgoing
// direction into it and wraps the feather's Bsdf so that it answers in world
// directions (placed_bsdf.h). A similarity's rotation keeps angles and solid
// angles, so this is exact; shear and unequal scales are refused.
//
// With one feather (the first constructor) no top-level BVH is built and every
// query goes straight to the Scene: images are those of the Scene alone, bit for bit.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/bounds.h"
#include "plumage/renderer/backdrop.h"
#include "plumage/renderer/fibre_material.h"
#include "plumage/renderer/ray.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/surface_hit.h"

namespace plumage {

// A distinct feather: its Scene (built without a backdrop: the world lays one card
// under all placements) and the material its fibres are made of.
struct WorldFeather {
  const Scene* scene = nullptr;
  const FibreMaterial* material = nullptr;
};

// A placement: feather `feather` (an index into the world's feathers) moved by
// `to_world`, whose linear part must be a similarity (scene_format.h, similarity_of).
struct WorldPlacement {
  std::uint32_t feather = 0;
  glm::mat4 to_world{1.0f};
};

// What World::intersect found. `local` is the hit as the placement's Scene reports
// it, in the feather's own frame (its p, ng and curve queries); t and p are the
// world ray's distance and point. The backdrop of a world is hit in world space
// (placement kNoId).
struct WorldHit {
  SurfaceHit local;
  std::uint32_t placement = 0;
  float t = 0;
  glm::vec3 p{0};
};

class World {
 public:
  // One feather, no instancing: queries go to `scene`, whose own backdrop is the card.
  World(const Scene& scene, const FibreMaterial& material);
  // Many. Throws plumage::Error for no placement, a feather index out of range, a
  // transform that is not a similarity, a feather Scene built with a backdrop.
  // Feathers may be built in different shading modes (`--shading auto` shades a
  // feather's near placements in substructure mode and its far ones in farfield
  // mode: two Scenes of one feather). `backdrop` lies under all placements
  // (backdrop.h's rules, on the world bounds). The scenes and materials must outlive
  // the world.
  World(std::vector<WorldFeather> feathers, std::vector<WorldPlacement> placements, const BackdropSpec& backdrop);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  bool intersect(const Ray& ray, WorldHit& hit) const;
  bool occluded(const Ray& ray) const;
  // A secondary ray leaving `from` along world direction d, valid up to tmax.
  Ray spawn(const WorldHit& from, const glm::vec3& d, float tmax = 1e30f) const;

  const std::vector<WorldFeather>& feathers() const { return feathers_; }
  std::size_t placement_count() const { return placed_.size(); }
  // What the placements themselves hold (their transforms), in bytes.
  std::size_t placement_bytes() const { return placed_.size() * sizeof(Placed); }
  // The distinct feather a placement (or a feather hit) shows.
  std::uint32_t placed_feather(std::uint32_t placement) const { return placed_[placement].feather; }
  const WorldFeather& feather_of(const WorldHit& hit) const { return feathers_[placed_[hit.placement].feather]; }
  // The rotation (its determinant -1 for a mirror) that turns the placement's local
  // directions into world ones, or null for a placement that turns nothing (the
  // single-feather world, or an identity linear part).
  const glm::mat3* rotation(std::uint32_t placement) const {
    const Placed& p = placed_[placement];
    return p.turns ? &p.rotation : nullptr;
  }
  // A placement's world box (its feather's bounds carried by its transform) and scale.
  Bounds3f placement_bounds(std::uint32_t placement) const;
  float placement_scale(std::uint32_t placement) const { return placed_[placement].scale; }
  // The world bounds of every placed feather, radii included (the card left out).
  const Bounds3f& bounds() const { return bounds_; }
  const BackdropSpec& backdrop() const { return backdrop_; }
  // The card's height, centre (x, y) and half side (meaningful when backdrop().enabled).
  float backdrop_z() const { return backdrop_z_; }
  glm::vec2 backdrop_centre() const { return backdrop_centre_; }
  float backdrop_half_side() const { return backdrop_half_; }

 private:
  struct Placed {
    std::uint32_t feather;
    glm::mat4 to_world, from_world;
    glm::mat3 rotation, rotation_t;  // local -> world directions, and back
    float scale, inv_scale;
    bool turns;  // rotation is not the identity
  };
  struct Embree;
  friend struct WorldQuery;

  bool hit_backdrop(const Ray& ray, float tmax, float& t) const;
  Ray to_local(const Ray& ray, std::uint32_t placement) const;

  std::vector<WorldFeather> feathers_;
  std::vector<Placed> placed_;
  std::unique_ptr<Embree> rtc_;  // null for the single-feather world
  BackdropSpec backdrop_;
  Bounds3f bounds_;
  float backdrop_z_ = 0, backdrop_half_ = 0;
  glm::vec2 backdrop_centre_{0};
  float spawn_back_ = 0;  // how far behind its origin every world secondary ray starts (world mm)
  float spawn_eps_ = 0;
};

}  // namespace plumage
