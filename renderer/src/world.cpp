// A world of placed feathers (world.h): the top-level BVH of placements, each a
// user primitive whose ray query carries the ray into the feather's frame and asks
// the feather's Scene; the card under all of them; and the secondary-ray rule.
#include "plumage/renderer/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/task_arena.h>

#include "embree_device.h"
#include "float_mode.h"
#include "plumage/common/error.h"
#include "plumage/common/scene_format.h"

namespace plumage {

namespace {
// The box around box b carried by the affine map m (its eight corners carried).
Bounds3f carried(const glm::mat4& m, const Bounds3f& b) {
  Bounds3f out;
  for (int c = 0; c < 8; ++c) out.extend(glm::vec3(m * glm::vec4(b.corner(c), 1.0f)));
  return out;
}
}  // namespace

struct World::Embree {
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
  }
};

// What a world query hands to the placements' callbacks (Embree passes our
// context pointer through).
struct WorldQuery {
  RTCIntersectContext rtc;
  const World* world;
  const Ray* ray;
  WorldHit* hit;  // intersect only

  WorldQuery(const World* w, const Ray* r, WorldHit* h) : world(w), ray(r), hit(h) { rtcInitIntersectContext(&rtc); }

  static void bounds(const RTCBoundsFunctionArguments* args) {
    const auto* w = static_cast<const World*>(args->geometryUserPtr);
    const Bounds3f out = w->placement_bounds(args->primID);
    RTCBounds* o = args->bounds_o;
    o->lower_x = out.lo.x, o->lower_y = out.lo.y, o->lower_z = out.lo.z;
    o->upper_x = out.hi.x, o->upper_y = out.hi.y, o->upper_z = out.hi.z;
  }

  static void intersect(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    auto* q = reinterpret_cast<WorldQuery*>(args->context);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    const World& w = *q->world;
    const std::uint32_t k = args->primID;
    const World::Placed& p = w.placed_[k];
    Ray local = w.to_local(*q->ray, k);
    local.tfar = rh->ray.tfar * p.inv_scale;  // nothing beyond the closest hit so far
    SurfaceHit h;
    if (!w.feathers_[p.feather].scene->intersect(local, h)) return;
    const float t = std::min(h.t * p.scale, rh->ray.tfar);
    rh->ray.tfar = t;
    rh->hit.geomID = args->geomID;
    rh->hit.primID = k;
    q->hit->local = h;
    q->hit->placement = k;
  }

  static void occluded(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    auto* q = reinterpret_cast<WorldQuery*>(args->context);
    auto* r = reinterpret_cast<RTCRay*>(args->ray);
    const World& w = *q->world;
    const std::uint32_t k = args->primID;
    const World::Placed& p = w.placed_[k];
    const Ray local = w.to_local(*q->ray, k);
    if (w.feathers_[p.feather].scene->occluded(local)) r->tfar = -std::numeric_limits<float>::infinity();
  }
};

World::World(const Scene& scene, const FibreMaterial& material)
    : feathers_{{&scene, &material}}, backdrop_(scene.options().backdrop), bounds_(scene.feather_bounds()),
      backdrop_z_(scene.backdrop_z()) {
  placed_.push_back({0, glm::mat4(1.0f), glm::mat4(1.0f), glm::mat3(1.0f), glm::mat3(1.0f), 1.0f, 1.0f, false});
}

World::World(std::vector<WorldFeather> feathers, std::vector<WorldPlacement> placements, const BackdropSpec& backdrop)
    : feathers_(std::move(feathers)), rtc_(std::make_unique<Embree>()), backdrop_(backdrop) {
  if (feathers_.empty() || placements.empty()) throw Error("a scene of feathers needs a feather and a placement");
  for (std::size_t i = 0; i < feathers_.size(); ++i) {
    const WorldFeather& f = feathers_[i];
    if (!f.scene || !f.material) throw Error("feather " + std::to_string(i) + " of the world has no scene or material");
    if (f.scene->options().backdrop.enabled)
      throw Error("feather " + std::to_string(i) + "'s scene has a backdrop of its own; the world lays one card under all");
  }
  float max_back = 0;    // the largest spawn margin of any placement, world mm
  float max_radius = 0;  // the largest curve radius of any placement, world mm
  for (std::size_t i = 0; i < placements.size(); ++i) {
    const WorldPlacement& wp = placements[i];
    if (wp.feather >= feathers_.size())
      throw Error("placement " + std::to_string(i) + " names feather " + std::to_string(wp.feather) + " of " +
                  std::to_string(feathers_.size()));
    const std::optional<Similarity> sim = similarity_of(wp.to_world);
    if (!sim)
      throw Error("placement " + std::to_string(i) +
                  ": the transform must be a rotation, one scale above 0 and a translation (mirroring allowed)");
    Placed p;
    p.feather = wp.feather;
    p.to_world = wp.to_world;
    p.rotation = sim->rotation;
    p.rotation_t = glm::transpose(sim->rotation);
    p.scale = sim->scale;
    p.inv_scale = 1.0f / sim->scale;
    p.turns = sim->rotation != glm::mat3(1.0f);
    // The inverse of x -> s R x + t: y -> R^T (y - t) / s.
    const glm::mat3 inv = p.rotation_t * p.inv_scale;
    p.from_world = glm::mat4(inv);
    p.from_world[3] = glm::vec4(-(inv * glm::vec3(wp.to_world[3])), 1.0f);
    placed_.push_back(p);

    const Scene& s = *feathers_[p.feather].scene;
    bounds_.extend(placement_bounds(std::uint32_t(i)));
    max_back = std::max(max_back, p.scale * 2.05f * s.max_barb_radius());
    max_radius = std::max(max_radius, p.scale * s.max_radius());
  }
  const glm::vec3 size = bounds_.size();
  if (backdrop_.enabled) {
    // backdrop.h's Feather rule on the world bounds (a world has no single vane to
    // lay it under): four of the largest placed radius below the lowest point, at
    // least a thousandth of the larger side.
    backdrop_z_ = bounds_.lo.z - std::max(4.0f * max_radius, 1e-3f * std::max(size.x, size.y));
    backdrop_half_ = 0.5f * backdrop_.extent * std::max({size.x, size.y, 1e-3f});
    backdrop_centre_ = {bounds_.centre().x, bounds_.centre().y};
  }
  float reach = 1.0f;
  for (int a = 0; a < 3; ++a) reach = std::max({reach, std::fabs(bounds_.lo[a]), std::fabs(bounds_.hi[a])});
  if (backdrop_.enabled)
    reach = std::max({reach, std::fabs(backdrop_centre_.x) + backdrop_half_, std::fabs(backdrop_centre_.y) + backdrop_half_,
                      std::fabs(backdrop_z_)});
  spawn_eps_ = 1e-5f * reach;
  spawn_back_ = max_back + spawn_eps_;

  rtc_->scene = rtcNewScene(shared_device());
  RTCGeometry geom = rtcNewGeometry(shared_device(), RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, unsigned(placed_.size()));
  rtcSetGeometryUserData(geom, this);
  rtcSetGeometryBoundsFunction(geom, &WorldQuery::bounds, this);
  rtcSetGeometryIntersectFunction(geom, &WorldQuery::intersect);
  rtcSetGeometryOccludedFunction(geom, &WorldQuery::occluded);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(rtc_->scene, geom);
  rtcReleaseGeometry(geom);
  {
    tbb::task_arena build_arena;  // as Scene's build: FTZ/DAZ for the build only (float_mode.h)
    build_arena.initialize();
    const detail::FtzDazScope ftz_daz;
    build_arena.execute([&] { rtcCommitScene(rtc_->scene); });
  }
  throw_if_device_error("building the scene of placed feathers");
}

World::~World() = default;

Ray World::to_local(const Ray& ray, std::uint32_t k) const {
  // x = s R y + t carries the world ray o + t d to F(o) + (t / s) R^T d: the same
  // point at local distance t / s along a unit direction.
  const Placed& p = placed_[k];
  Ray local;
  local.o = glm::vec3(p.from_world * glm::vec4(ray.o, 1.0f));
  local.d = p.rotation_t * ray.d;
  local.tnear = ray.tnear * p.inv_scale;
  local.tfar = ray.tfar * p.inv_scale;
  if (ray.skip_placement == k) {
    local.skip_geom = ray.skip_geom;
    local.skip_curve = ray.skip_curve;
    local.skip_until = ray.skip_until * p.inv_scale;
  }
  return local;
}

bool World::hit_backdrop(const Ray& ray, float tmax, float& t) const {
  if (!backdrop_.enabled || ray.d.z == 0) return false;
  t = (backdrop_z_ - ray.o.z) / ray.d.z;
  if (!(t >= ray.tnear && t <= tmax)) return false;
  if (ray.skip_placement == kWorldCard && t < ray.skip_until) return false;
  const glm::vec3 p = ray.o + t * ray.d;
  return std::fabs(p.x - backdrop_centre_.x) <= backdrop_half_ && std::fabs(p.y - backdrop_centre_.y) <= backdrop_half_;
}

bool World::intersect(const Ray& ray, WorldHit& hit) const {
  if (!rtc_) {
    const bool found = feathers_.front().scene->intersect(ray, hit.local);
    hit.placement = 0;
    hit.t = hit.local.t;
    hit.p = hit.local.p;
    return found;
  }
  float t_card = 0;
  const bool card = hit_backdrop(ray, ray.tfar, t_card);
  WorldQuery q(this, &ray, &hit);
  RTCRayHit rh = rtc_ray_hit(ray);
  if (card) rh.ray.tfar = t_card;  // nothing beyond the card
  rtcIntersect1(rtc_->scene, &q.rtc, &rh);
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    hit.t = rh.ray.tfar;
    hit.p = ray.o + hit.t * ray.d;
    return true;
  }
  if (!card) {
    hit.local.kind = HitKind::None;
    return false;
  }
  hit.local = SurfaceHit{};
  hit.local.kind = HitKind::Backdrop;
  hit.local.t = t_card;
  hit.local.p = ray.o + t_card * ray.d;
  hit.local.ng = {0, 0, 1};
  hit.placement = kWorldCard;
  hit.t = t_card;
  hit.p = hit.local.p;
  return true;
}

bool World::occluded(const Ray& ray) const {
  if (!rtc_) return feathers_.front().scene->occluded(ray);
  float t_card = 0;
  if (hit_backdrop(ray, ray.tfar, t_card)) return true;
  WorldQuery q(this, &ray, nullptr);
  RTCRay r = rtc_ray(ray);
  rtcOccluded1(rtc_->scene, &q.rtc, &r);
  return r.tfar < 0;
}

// Every world secondary ray starts spawn_back_ behind its hit (the largest margin
// any placement's Scene::spawn uses, in world mm), so that Embree's near-origin
// culling drops no neighbouring feather's barb either; the fibre it left is skipped
// for as far as that feather's Scene::spawn says, scaled to the world.
Ray World::spawn(const WorldHit& from, const glm::vec3& d, float tmax) const {
  if (!rtc_) return feathers_.front().scene->spawn(from.local, d, tmax);
  Ray r;
  r.d = d;
  if (from.local.kind == HitKind::Backdrop) {
    r.o = from.p - spawn_back_ * d;
    r.tnear = spawn_back_;
    r.tfar = spawn_back_ + tmax;
    r.skip_placement = kWorldCard;
    r.skip_until = spawn_back_ + 4 * spawn_eps_;
    return r;
  }
  const Placed& p = placed_[from.placement];
  const Ray local = feathers_[p.feather].scene->spawn(from.local, p.rotation_t * d, tmax * p.inv_scale);
  const float back = std::max(spawn_back_, local.tnear * p.scale);
  r.o = from.p - back * d;
  r.tnear = back;
  r.tfar = back + tmax;
  r.skip_geom = local.skip_geom;
  r.skip_curve = local.skip_curve;
  r.skip_until = back + (local.skip_until - local.tnear) * p.scale + 4 * spawn_eps_;
  r.skip_placement = from.placement;
  return r;
}

Bounds3f World::placement_bounds(std::uint32_t placement) const {
  const Placed& p = placed_[placement];
  return carried(p.to_world, feathers_[p.feather].scene->feather_bounds());
}

}  // namespace plumage
