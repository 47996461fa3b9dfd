#include "plumage/renderer/path_integrator.h"
#include "plumage/common/image.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/renderer/diffuse_bsdf.h"
#include "plumage/renderer/fibre_bsdf.h"
#include "placed_bsdf.h"

namespace plumage {
namespace {

bool finite_nonneg(const glm::vec3& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && c.x >= 0 && c.y >= 0 && c.z >= 0;
}

// One shadow ray to light i, chosen with probability `pick`: its contribution
// f cos Le / (pick pdf), MIS-weighted against BCSDF sampling (power heuristic).
glm::vec3 direct_light(const World& world, const LightSet& lights, const WorldHit& hit, const Bsdf& bsdf,
                       std::size_t i, float pick, const glm::vec2& u, PathCounters& counters) {
  const auto ls = lights.sample(i, hit.p, u);
  if (!ls || !(ls->pdf > 0) || !(pick > 0)) return glm::vec3(0);
  float pdf_bsdf = 0;
  const glm::vec3 fc = bsdf.f_cos(ls->wi, &pdf_bsdf);
  if (!(fc.x > 0 || fc.y > 0 || fc.z > 0)) return glm::vec3(0);
  const Ray shadow = world.spawn(hit, ls->wi, ls->dist * (1.0f - 1e-4f));
  ++counters.shadow_rays;
  if (world.occluded(shadow)) return glm::vec3(0);
  const float pdf = ls->pdf * pick;
  const float w = ls->delta ? 1.0f : power_heuristic(pdf, pdf_bsdf);
  return fc * ls->Le * (w / pdf);
}

// The environment has no direction to evaluate the BCSDF at: its estimate assumes
// a surface that reflects half of what falls on it, diffusely.
constexpr float kEnvironmentResponse = 0.5f / kPiF;

// Next-event estimation's choice of light at one vertex, and the probability of
// that choice for MIS when a BCSDF-sampled ray of the same vertex hits a light.
// It chooses among the first n lights (LightSet::sampled_count()); a light past
// them is never chosen and has probability 0.
// The pmf lives in per-thread buffers (Li is not re-entrant), so a path allocates nothing.
class LightChoice {
 public:
  // `max_picks`: how many lights one vertex may sample (stratified over the pmf);
  // the density MIS sees for light sampling is picks() x the pmf. More picks than
  // lights would sample a light twice per vertex: no better than one sample of
  // each (under a lone environment, measurably worse per CPU second).
  LightChoice(std::size_t n, LightPick mode, int max_picks)
      : n_(n), mode_(mode),
        picks_(mode == LightPick::All ? 1 : int(std::min<std::size_t>(std::size_t(max_picks), std::max<std::size_t>(n, 1)))) {
    thread_local std::vector<float> pmf, weights;
    pmf_ = &pmf;
    weights_ = &weights;
  }
  // Weighs every light by lum(f_cos(wi) strength) at this vertex (LightPick::Estimate).
  void estimate(const LightSet& lights, const glm::vec3& p, const Bsdf& bsdf) {
    if (n_ <= 1) return;  // one light needs no weighing: it is chosen with probability 1 either way
    thread_local LightProxies proxies;
    lights.proxies(p, proxies);
    weights_->resize(proxies.size());
    pmf_->resize(n_);
    bsdf.estimate_weights(proxies, weights_->data());
    if (proxies.environment < n_)
      (*weights_)[proxies.environment] = luminance(proxies.strength(proxies.environment)) * kEnvironmentResponse;
    light_pick_pmf(std::span<const float>(weights_->data(), n_), *pmf_);
    estimated_ = true;
  }
  float prob(std::size_t i) const {
    if (i >= n_) return 0.0f;
    if (mode_ == LightPick::All) return 1.0f;
    return float(picks_) * (estimated_ ? (*pmf_)[i] : 1.0f / float(n_));
  }
  int picks() const { return picks_; }
  std::size_t count() const { return n_; }
  std::size_t choose(float u) const {
    if (estimated_) return pick_from_pmf(*pmf_, u);
    return std::min(std::size_t(u * float(n_)), n_ - 1);
  }

 private:
  std::size_t n_;
  LightPick mode_;
  int picks_;
  bool estimated_ = false;
  std::vector<float>*pmf_, *weights_;
};

}  // namespace

PathIntegrator::PathIntegrator(const Scene& scene, const LightSet& lights, const FibreMaterial& material,
                               const IntegratorSettings& settings)
    : own_world_(std::make_unique<const World>(scene, material)), world_(*own_world_), lights_(lights),
      settings_(settings), bsdf_pdf_needed_(lights.hit_by_sampled_rays()) {
  make_shadings();
}

PathIntegrator::PathIntegrator(const World& world, const LightSet& lights, const IntegratorSettings& settings)
    : world_(world), lights_(lights), settings_(settings), bsdf_pdf_needed_(lights.hit_by_sampled_rays()) {
  make_shadings();
}

void PathIntegrator::make_shadings() {
  if (settings_.light_picks < 1) throw Error("light picks per vertex must be at least 1");
  for (const WorldFeather& f : world_.feathers())
    barbs_.push_back(make_barb_shading({*f.scene, *f.material, bsdf_pdf_needed_}));
}

// A barb is shaded by its mode's model; the shaft and down barbs are round fibres
// and the card a diffuse surface in every mode. A placed feather is shaded in its own frame.
const Bsdf& PathIntegrator::bsdf_at(const WorldHit& hit, const glm::vec3& wo, BsdfSlot& slot, BsdfSlot& local) const {
  if (hit.local.kind == HitKind::Backdrop)
    return slot.emplace<DiffuseBsdf>(safe_normalize(hit.local.ng), wo, world_.backdrop().albedo);
  const glm::mat3* turn = world_.rotation(hit.placement);
  const glm::vec3 wl = turn ? glm::transpose(*turn) * wo : wo;
  BsdfSlot& target = turn ? local : slot;
  const WorldFeather& f = world_.feather_of(hit);
  const bool down = hit.local.kind == HitKind::Down;
  const Bsdf& b = hit.local.kind == HitKind::Barb
                      ? barbs_[world_.placed_feather(hit.placement)]->at(hit.local, wl, target)
                      : target.emplace<FibreBsdf>(
                            down ? down_fibre_frame_at(*f.scene, hit.local, wl) : round_fibre_frame_at(*f.scene, hit.local, wl),
                            down ? f.material->at_down(hit.local.p)
                                 : f.material->at_shaft(hit.local.p, f.scene->curve_parameter(hit.local)),
                            wl, bsdf_pdf_needed_);
  if (!turn) return b;
  return slot.emplace<PlacedBsdf>(b, *turn);
}

glm::vec3 PathIntegrator::Li(Ray ray, PixelSampler& sampler, PathCounters& counters) const {
  glm::vec3 L(0), beta(1);
  // The selection pmf at the last vertex (MIS needs it on a light hit).
  LightChoice pick(lights_.count(), settings_.light_pick, settings_.light_picks);
  float prev_pdf = 0;      // pdf of the BCSDF sample that made `ray`
  bool from_camera = true; // no MIS for what the camera sees directly
  for (int depth = 0;; ++depth) {
    WorldHit hit;
    const bool found = world_.intersect(ray, hit);
    ++counters.rays;
    // Secondary rays start behind their true origin (Scene::spawn); lights are
    // intersected from the true origin so their pdfs match light sampling.
    const glm::vec3 origin = ray.o + ray.tnear * ray.d;
    const float surface_t = found ? hit.t - ray.tnear : std::numeric_limits<float>::infinity();
    if (auto lh = lights_.intersect_spheres(origin, ray.d, surface_t)) {
      const float w = from_camera ? 1.0f : power_heuristic(prev_pdf, lh->pdf * pick.prob(lh->light));
      L += beta * lh->Le * w;
      break;
    }
    if (!found) {
      float pdf_env = 0;
      const glm::vec3 Le = lights_.environment_Le(ray.d, &pdf_env);
      const float pick_env = pick.prob(lights_.environment_index());  // 0 for a constant environment
      const float w = from_camera || !(pdf_env > 0) || !(pick_env > 0) ? 1.0f
                                                                       : power_heuristic(prev_pdf, pdf_env * pick_env);
      L += beta * Le * w;
      break;
    }
    ++counters.hits;
    if (depth >= settings_.max_depth) break;

    const glm::vec3 wo = -ray.d;
    BsdfSlot slot, local_slot;
    const Bsdf& bsdf = bsdf_at(hit, wo, slot, local_slot);

    // Next-event estimation (settings_.light_pick): one light chosen uniformly or
    // by its estimate, or every light; one shadow ray each. A constant
    // environment is left to BCSDF sampling where that follows f cos.
    const glm::vec4 ul = sampler.next4();
    const std::size_t n_lights = bsdf.samples_like_f_cos() ? lights_.sampled_count() : lights_.count();
    if (n_lights != pick.count()) pick = LightChoice(n_lights, settings_.light_pick, settings_.light_picks);
    if (n_lights > 0) {
      if (settings_.light_pick == LightPick::All) {
        glm::vec4 u = ul;
        for (std::size_t i = 0; i < n_lights; ++i) {
          if (i > 0) u = sampler.next4();
          L += beta * direct_light(world_, lights_, hit, bsdf, i, 1.0f, {u.y, u.z}, counters);
        }
      } else {
        if (settings_.light_pick == LightPick::Estimate) pick.estimate(lights_, hit.p, bsdf);
        const int picks = pick.picks();
        // Stratified over the pmf: pick k takes u in [k/picks, (k+1)/picks).
        for (int k = 0; k < picks; ++k) {
          const glm::vec2 us = k > 0 ? sampler.next2() : glm::vec2(ul.y, ul.z);
          const std::size_t i = pick.choose((ul.x + float(k)) / float(picks));
          L += beta * direct_light(world_, lights_, hit, bsdf, i, pick.prob(i), us, counters);
        }
      }
    }

    // Continue the path by sampling the BCSDF.
    const glm::vec4 ub = sampler.next4();
    const std::optional<BsdfSample> bs = bsdf.sample(ub);
    if (!bs) break;
    beta *= bs->weight;
    prev_pdf = bs->pdf;
    from_camera = false;
    if (depth + 1 >= settings_.rr_depth) {
      // Russian roulette on the throughput, unbiased by the 1/q boost.
      const float q = std::fmin(0.95f, std::max({beta.x, beta.y, beta.z}));
      if (!(ul.w < q)) break;
      beta /= q;
    }
    if (!(beta.x > 0 || beta.y > 0 || beta.z > 0)) break;
    ray = world_.spawn(hit, bs->wi);
  }
  if (!finite_nonneg(L)) {
    ++counters.bad_samples;
    return glm::vec3(0);
  }
  return L;
}

}  // namespace plumage
