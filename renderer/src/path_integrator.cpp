#include "plumage/renderer/path_integrator.h"
#include "plumage/common/image.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/renderer/fibre_frame.h"

namespace plumage {
namespace {

bool finite_nonneg(const glm::vec3& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && c.x >= 0 && c.y >= 0 && c.z >= 0;
}

// How a hit scatters light, in a form both shading models share.
struct Scatter {
  virtual ~Scatter() = default;
  // f(wo, wi) times the projection cosine, and the pdf sample() would give wi.
  virtual glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const = 0;
  // A direction, its throughput weight f cos / pdf and pdf; false when none.
  virtual bool sample(const glm::vec4& u, glm::vec3* wi, glm::vec3* weight, float* pdf) const = 0;
  // Weighs every light for the choice of light only: w[i] = lum(strength_i x
  // f cos(wi_i)) over the proxies, f cos exact or a cheaper approximation of it.
  // The environment's entry is the caller's (it has no single direction).
  virtual void estimate_weights(const LightProxies& lp, float* w) const {
    float pdf;
    for (std::size_t i = 0; i < lp.size(); ++i) w[i] = luminance(lp.strength(i) * f_cos(lp.wi(i), &pdf));
  }
  // Whether sample() follows f cos closely enough that a constant environment is
  // left to it alone (LightSet::sampled_count()).
  virtual bool samples_like_f_cos() const { return true; }
};

// Lambertian card, seen from either side.
struct DiffuseScatter final : Scatter {
  glm::vec3 n, albedo;
  DiffuseScatter(const glm::vec3& normal, const glm::vec3& wo, const glm::vec3& a)
      : n(glm::dot(normal, wo) < 0 ? -normal : normal), albedo(a) {}
  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override {
    const float c = glm::dot(wi, n);
    *pdf = c > 0 ? c / kPiF : 0.0f;
    return c > 0 ? albedo * (c / kPiF) : glm::vec3(0);
  }
  void estimate_weights(const LightProxies& lp, float* w) const override {
    weigh(lp.size(), lp.x.data(), lp.y.data(), lp.z.data(), lp.r.data(), lp.g.data(), lp.b.data(), n,
          albedo / kPiF, w);
  }
  // A plain loop over pointers, which GCC vectorises: lum(strength f cos).
  static void weigh(std::size_t count, const float* x, const float* y, const float* z, const float* r, const float* g,
                    const float* b, glm::vec3 n, glm::vec3 f, float* __restrict w) {
    const float kr = kLumR * f.x, kg = kLumG * f.y, kb = kLumB * f.z;
    for (std::size_t i = 0; i < count; ++i) {
      const float c = x[i] * n.x + y[i] * n.y + z[i] * n.z;
      w[i] = std::max(c, 0.0f) * (kr * r[i] + kg * g[i] + kb * b[i]);
    }
  }
  bool sample(const glm::vec4& u, glm::vec3* wi, glm::vec3* weight, float* pdf) const override {
    // Cosine-weighted hemisphere (Malley's method).
    const float r = std::sqrt(u.x), phi = 2 * kPiF * u.y;
    const float z = std::sqrt(std::fmax(0.0f, 1.0f - u.x));
    const Frame f = frame_from_normal(n);
    *wi = glm::normalize(f.to_world({r * std::cos(phi), r * std::sin(phi), z}));
    *pdf = z / kPiF;
    *weight = albedo;
    return z > 0;
  }
};

// A fibre hit: the hair BCSDF in the fibre frame. Its cosine is that of the
// longitudinal angle, cos(theta_i) = sqrt(1 - wi.x^2) (Chiang et al. 2016 eq. 2; bcsdf_cos).
struct FibreScatter final : Scatter {
  FibreFrame ff;
  glm::vec3 wo_local;
  HairBCSDF bcsdf;
  bool pdf_needed;  // false: sample() weighs by lobe selection and gives no pdf (no MIS on its rays)
  FibreScatter(const FibreFrame& frame, const HairParams& params, const glm::vec3& wo, bool pdf_needed)
      : ff(frame), wo_local(frame.frame.to_local(wo)), bcsdf(params, frame.h, wo_local), pdf_needed(pdf_needed) {}
  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override {
    const glm::vec3 wl = ff.frame.to_local(wi);
    return bcsdf.f_pdf(wo_local, wl, pdf) * bcsdf_cos(wl);
  }
  // The float estimate (HairBCSDF::f_cos_estimate) in the fibre frame, over
  // per-thread buffers (Li is not re-entrant).
  void estimate_weights(const LightProxies& lp, float* w) const override {
    thread_local std::vector<float> buf;
    const std::size_t n = lp.size();
    buf.resize(6 * n);
    float *lx = buf.data(), *ly = lx + n, *lz = ly + n;
    to_frame(n, lp.x.data(), lp.y.data(), lp.z.data(), ff.frame, lx, ly, lz);
    float* const resp[3] = {lz + n, lz + 2 * n, lz + 3 * n};
    bcsdf.f_cos_estimate(wo_local, n, lx, ly, lz, resp);
    weigh(n, lp.r.data(), lp.g.data(), lp.b.data(), resp[0], resp[1], resp[2], w);
  }
  // Plain loops over pointers, which GCC vectorises.
  static void to_frame(std::size_t n, const float* x, const float* y, const float* z, Frame f, float* __restrict lx,
                       float* __restrict ly, float* __restrict lz) {
    for (std::size_t i = 0; i < n; ++i) {
      lx[i] = x[i] * f.t.x + y[i] * f.t.y + z[i] * f.t.z;
      ly[i] = x[i] * f.b.x + y[i] * f.b.y + z[i] * f.b.z;
      lz[i] = x[i] * f.n.x + y[i] * f.n.y + z[i] * f.n.z;
    }
  }
  static void weigh(std::size_t n, const float* r, const float* g, const float* b, const float* fr, const float* fg,
                    const float* fb, float* __restrict w) {
    for (std::size_t i = 0; i < n; ++i) w[i] = kLumR * r[i] * fr[i] + kLumG * g[i] * fg[i] + kLumB * b[i] * fb[i];
  }
  bool sample(const glm::vec4& u, glm::vec3* wi, glm::vec3* weight, float* pdf) const override {
    if (!pdf_needed) {
      const auto s = bcsdf.sample_throughput(wo_local, {u.x, u.y}, {u.z, u.w});
      if (!s) return false;
      *wi = glm::normalize(ff.frame.to_world(s->wi));
      *pdf = 0;
      *weight = s->weight;
      return true;
    }
    const auto s = bcsdf.sample(wo_local, {u.x, u.y}, {u.z, u.w});
    if (!s || !(s->pdf > 0)) return false;
    *wi = glm::normalize(ff.frame.to_world(s->wi));
    *pdf = s->pdf;
    *weight = s->f * (bcsdf_cos(s->wi) / s->pdf);
    return true;
  }
};

// A far-field ribbon hit (farfield.h): the vane's table in the barb's frame, given
// that the ray was not let through.
struct FarfieldScatter final : Scatter {
  const FarfieldModel& model;
  Frame frame;
  FarfieldModel::Outgoing out;  // what depends on wo alone, once per hit
  FarfieldScatter(const FarfieldModel& m, const Frame& f, const glm::vec3& wo)
      : model(m), frame(f), out(m.outgoing(f.to_local(wo))) {}
  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override {
    return model.f_cos(out, frame.to_local(wi), pdf);
  }
  // Values only (no pdfs): next-event estimation's weighing of every light.
  void estimate_weights(const LightProxies& lp, float* w) const override {
    for (std::size_t i = 0; i < lp.size(); ++i)
      w[i] = luminance(lp.strength(i) * model.f_cos(out, frame.to_local(lp.wi(i)), nullptr));
  }
  // Its sampling is uniform within a table bin while f cos interpolates between
  // bins: it keeps light sampling of a constant environment too.
  bool samples_like_f_cos() const override { return false; }
  bool sample(const glm::vec4& u, glm::vec3* wi, glm::vec3* weight, float* pdf) const override {
    glm::vec3 wl;
    if (!model.sample(out, {u.x, u.y, u.z}, &wl, weight, pdf)) return false;
    *wi = glm::normalize(frame.to_world(wl));
    return true;
  }
};

// One shadow ray to light i, chosen with probability `pick`: its contribution
// f cos Le / (pick pdf), MIS-weighted against BCSDF sampling (power heuristic).
glm::vec3 direct_light(const Scene& scene, const LightSet& lights, const SurfaceHit& hit, const Scatter& bsdf,
                       std::size_t i, float pick, const glm::vec2& u, PathCounters& counters) {
  const auto ls = lights.sample(i, hit.p, u);
  if (!ls || !(ls->pdf > 0) || !(pick > 0)) return glm::vec3(0);
  float pdf_bsdf = 0;
  const glm::vec3 fc = bsdf.f_cos(ls->wi, &pdf_bsdf);
  if (!(fc.x > 0 || fc.y > 0 || fc.z > 0)) return glm::vec3(0);
  const Ray shadow = scene.spawn(hit, ls->wi, ls->dist * (1.0f - 1e-4f));
  ++counters.shadow_rays;
  if (scene.occluded(shadow)) return glm::vec3(0);
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
  void estimate(const LightSet& lights, const glm::vec3& p, const Scatter& bsdf) {
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

// Hair mode shades a barb as one fibre across its ribbon; substructure mode shades
// the ramus or barbule the hit landed on, in its own frame (Baron et al. 2021, Eq. 1).
FibreFrame PathIntegrator::fibre_frame_at(const SurfaceHit& hit, const glm::vec3& wo) const {
  if (hit.kind == HitKind::Barb && scene_.options().mode == ShadingMode::Substructure) {
    const StructureSample ss = scene_.structure_at(hit);
    return structure_fibre_frame(ss.frame, ss.hit.h, wo);
  }
  const CurvePoint cp = scene_.curve_point(hit);
  // Explicit mode's rami and barbules are round curves, shaded like the shaft.
  return hit.kind == HitKind::Barb && scene_.options().mode != ShadingMode::Explicit
             ? flat_fibre_frame(cp.dp, wo, hit.v)
             : round_fibre_frame(cp.dp, wo, cp.p, cp.radius, hit.p);
}

PathIntegrator::PathIntegrator(const Scene& scene, const LightSet& lights, const FibreMaterial& material,
                               const IntegratorSettings& settings)
    : scene_(scene), lights_(lights), material_(material), settings_(settings),
      bsdf_pdf_needed_(lights.hit_by_sampled_rays()) {
  if (settings_.light_picks < 1) throw Error("light picks per vertex must be at least 1");
  if (scene_.options().mode == ShadingMode::Farfield) {
    // One table per vane and barb class, for the material where the feather's
    // middle is (a texture's variation over the feather is not fitted).
    const HairParams hp = material_.at(scene_.feather_bounds().centre());
    for (VaneSide side : {VaneSide::Left, VaneSide::Right})
      for (const FarfieldGeometry& g : scene_.farfield_geometries(side))
        farfield_[side == VaneSide::Right].push_back(farfield_model(g, &hp));
  }
}

glm::vec3 PathIntegrator::Li(Ray ray, PixelSampler& sampler, PathCounters& counters) const {
  glm::vec3 L(0), beta(1);
  // The selection pmf at the last vertex (MIS needs it on a light hit).
  LightChoice pick(lights_.count(), settings_.light_pick, settings_.light_picks);
  float prev_pdf = 0;      // pdf of the BCSDF sample that made `ray`
  bool from_camera = true; // no MIS for what the camera sees directly
  for (int depth = 0;; ++depth) {
    SurfaceHit hit;
    const bool found = scene_.intersect(ray, hit);
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
    std::optional<DiffuseScatter> diffuse;
    std::optional<FibreScatter> fibre;
    std::optional<FarfieldScatter> farfield;
    const Scatter* bsdf;
    if (hit.kind == HitKind::Barb && scene_.options().mode == ShadingMode::Farfield) {
      const bool right = scene_.feather().curves[hit.curve].side == VaneSide::Right;
      bsdf = &farfield.emplace(*farfield_[right][scene_.farfield_class(hit)], scene_.farfield_frame(hit), wo);
    } else if (hit.kind == HitKind::Backdrop) {
      bsdf = &diffuse.emplace(safe_normalize(hit.ng), wo, scene_.options().backdrop.albedo);
    } else {
      bsdf = &fibre.emplace(fibre_frame_at(hit, wo),
                            hit.kind == HitKind::Shaft
                                ? material_.at_shaft(hit.p)
                                : material_.at(hit.p, scene_.structure_coverage(hit), scene_.ribbon_layers(hit)),
                            wo, bsdf_pdf_needed_);
    }

    // Next-event estimation (settings_.light_pick): one light chosen uniformly or
    // by its estimate, or every light; one shadow ray each. A constant
    // environment is left to BCSDF sampling where that follows f cos.
    const glm::vec4 ul = sampler.next4();
    const std::size_t n_lights = bsdf->samples_like_f_cos() ? lights_.sampled_count() : lights_.count();
    if (n_lights != pick.count()) pick = LightChoice(n_lights, settings_.light_pick, settings_.light_picks);
    if (n_lights > 0) {
      if (settings_.light_pick == LightPick::All) {
        glm::vec4 u = ul;
        for (std::size_t i = 0; i < n_lights; ++i) {
          if (i > 0) u = sampler.next4();
          L += beta * direct_light(scene_, lights_, hit, *bsdf, i, 1.0f, {u.y, u.z}, counters);
        }
      } else {
        if (settings_.light_pick == LightPick::Estimate) pick.estimate(lights_, hit.p, *bsdf);
        const int picks = pick.picks();
        // Stratified over the pmf: pick k takes u in [k/picks, (k+1)/picks).
        for (int k = 0; k < picks; ++k) {
          const glm::vec2 us = k > 0 ? sampler.next2() : glm::vec2(ul.y, ul.z);
          const std::size_t i = pick.choose((ul.x + float(k)) / float(picks));
          L += beta * direct_light(scene_, lights_, hit, *bsdf, i, pick.prob(i), us, counters);
        }
      }
    }

    // Continue the path by sampling the BCSDF.
    const glm::vec4 ub = sampler.next4();
    glm::vec3 wi, weight;
    float pdf;
    if (!bsdf->sample(ub, &wi, &weight, &pdf)) break;
    beta *= weight;
    prev_pdf = pdf;
    from_camera = false;
    if (depth + 1 >= settings_.rr_depth) {
      // Russian roulette on the throughput, unbiased by the 1/q boost.
      const float q = std::fmin(0.95f, std::max({beta.x, beta.y, beta.z}));
      if (!(ul.w < q)) break;
      beta /= q;
    }
    if (!(beta.x > 0 || beta.y > 0 || beta.z > 0)) break;
    ray = scene_.spawn(hit, wi);
  }
  if (!finite_nonneg(L)) {
    ++counters.bad_samples;
    return glm::vec3(0);
  }
  return L;
}

}  // namespace plumage
