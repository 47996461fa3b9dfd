// Numerical stress (issue 7): the hair BCSDF over millions of random and
// adversarial inputs, and tiny renders, in hair and substructure mode, of
// degenerate curves (coincident control points, zero and huge radii, far from the
// origin, extremely thin ribbons).
// 10^6 BCSDF inputs by default; PLUMAGE_STRESS=1 (scripts/sanitize.sh) runs 10^7.
#include <gtest/gtest.h>
#include <xmmintrin.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "fibre_sampling.h"
#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/hair_bcsdf.h"
#include "plumage/renderer/render.h"
#include "render_test_feather.h"

using namespace plumage;

namespace {

constexpr float kDenorm = std::numeric_limits<float>::denorm_min();

bool full_stress() {
  const char* s = std::getenv("PLUMAGE_STRESS");
  return s && std::string(s) == "1";
}

// test::Rng (splitmix64): the same stream on every platform; one per block of
// inputs, so the inputs do not depend on how TBB schedules the blocks.
using test::direction;
using test::Rng;

// Mostly the hard cases: theta = +-90 degrees exactly and within ulps of it, the
// normal plane, denormal components, and the fibre's y axis (h's direction).
glm::vec3 adversarial_direction(Rng& rng) {
  const float sgn = (rng.bits() & 1) ? 1.0f : -1.0f;
  switch (rng.bits() % 8) {
    case 0: return {sgn, 0.0f, 0.0f};
    case 1: return {sgn, kDenorm, -kDenorm};
    case 2: return direction(sgn * (1.0 - std::ldexp(1.0, -int(rng.bits() % 50))), rng.range(-kPi, kPi));
    case 3: return {kDenorm * sgn, 0.0f, 1.0f};
    case 4: return {0.0f, sgn, kDenorm};
    case 5: return direction(0.0, rng.range(-kPi, kPi));
    default: return direction(rng.range(-1, 1), rng.range(-kPi, kPi));
  }
}

HairParams adversarial_params(Rng& rng) {
  // beta below, at and above the 0.001 clamp and at 1; eta at and near 1.
  const float betas[] = {kDenorm, 1e-30f, 1e-4f, 0.001f, 0.0010001f, 0.3f, std::nextafter(1.0f, 0.0f), 1.0f};
  const float etas[] = {1.0f, std::nextafter(1.0f, 2.0f), 1.0001f, 1.01f, 1.55f, 2.5f};
  const float sigmas[] = {0.0f, kDenorm, 1e-6f, 0.5f, 5.0f, 1e3f, 1e30f, FLT_MAX};
  HairParams p;
  p.beta_m = rng.bits() % 4 ? rng.pick(betas) : float(std::pow(10.0, rng.range(-3, 0)));
  p.beta_n = rng.bits() % 4 ? rng.pick(betas) : float(std::pow(10.0, rng.range(-3, 0)));
  p.eta = rng.pick(etas);
  const float alphas[] = {0.0f, -0.0f, kDenorm, 2.0f, -45.0f, 45.0f};
  p.alpha_deg = rng.bits() % 2 ? rng.pick(alphas) : float(rng.range(-45, 45));
  for (int c = 0; c < 3; ++c) p.sigma_a[c] = rng.pick(sigmas);
  return p;
}

float adversarial_h(Rng& rng) {
  const float hs[] = {-1.0f, 1.0f, 0.0f, -0.0f, kDenorm, -kDenorm, std::nextafter(1.0f, 0.0f),
                      std::nextafter(-1.0f, 0.0f), 1.5f, -FLT_MAX};
  return rng.bits() % 2 ? rng.pick(hs) : float(rng.range(-1, 1));
}

bool finite_nonneg(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0 && v.y >= 0 && v.z >= 0;
}
bool positive(const glm::vec3& v) { return v.x > 0 || v.y > 0 || v.z > 0; }

std::string describe(const HairParams& p, float h, const glm::vec3& wo, const glm::vec3& wi) {
  std::ostringstream s;
  s.precision(9);
  s << "beta_m=" << p.beta_m << " beta_n=" << p.beta_n << " alpha=" << p.alpha_deg << " eta=" << p.eta
    << " sigma_a=(" << p.sigma_a.x << "," << p.sigma_a.y << "," << p.sigma_a.z << ") h=" << h << " wo=(" << wo.x
    << "," << wo.y << "," << wo.z << ") wi=(" << wi.x << "," << wi.y << "," << wi.z << ")";
  return s.str();
}

// Failures of one kind: how many, and the first input that showed it.
struct Tally {
  std::atomic<std::int64_t> count{0};
  std::mutex m;
  std::string first;
  void fail(const std::string& what) {
    if (count++ == 0) {
      std::lock_guard<std::mutex> lock(m);
      first = what;
    }
  }
};

// Sets the SSE flush-to-zero and denormals-are-zero bits for its lifetime. The
// renderer runs in that mode once Embree is up (building a Scene turns both on in
// the calling thread and leaves them on), so the BCSDF must hold up in both.
class DenormalMode {
 public:
  explicit DenormalMode(bool flush) : saved_(_mm_getcsr()) {
    constexpr unsigned kFtzDaz = 0x8040;
    _mm_setcsr(flush ? (saved_ | kFtzDaz) : (saved_ & ~kFtzDaz));
  }
  ~DenormalMode() { _mm_setcsr(saved_); }
  DenormalMode(const DenormalMode&) = delete;
  DenormalMode& operator=(const DenormalMode&) = delete;

 private:
  unsigned saved_;
};

// From the bits: under denormals-are-zero, fpclassify's comparisons see a zero.
bool denormal(float x) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
  return (bits & 0x7f800000u) == 0 && (bits & 0x007fffffu) != 0;
}

}  // namespace

TEST(StressHairBCSDF, FiniteNonNegativeAndPdfWhereverF) {
  const std::int64_t n = full_stress() ? 10'000'000 : 1'000'000;
  constexpr std::int64_t kBlock = 4096;
  Tally bad_f, bad_pdf, pdf_zero, bad_sample, bad_ctor;
  std::atomic<std::int64_t> evaluated{0}, sampled{0}, nonzero{0};
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, (n + kBlock - 1) / kBlock), [&](const auto& r) {
    for (std::int64_t b = r.begin(); b != r.end(); ++b) {
      const bool flush = b % 2 == 1;
      const DenormalMode mode(flush);
      Rng rng(0xB0C5DF00ull + std::uint64_t(b));
      std::int64_t local_eval = 0, local_sampled = 0, local_nonzero = 0;
      for (std::int64_t k = b * kBlock; k < std::min(n, (b + 1) * kBlock); k += 8) {
        // A BCSDF instance costs a setup; eight direction pairs share one.
        const HairParams p = adversarial_params(rng);
        const float h = adversarial_h(rng);
        std::optional<HairBCSDF> made;
        try {
          made.emplace(p, h);
        } catch (const Error& e) {
          // With denormals-are-zero a denormal beta is 0, which validate() rejects.
          if (!(flush && (denormal(p.beta_m) || denormal(p.beta_n)))) bad_ctor.fail(e.what());
          continue;
        }
        const HairBCSDF& bcsdf = *made;
        for (int j = 0; j < 8; ++j) {
          const glm::vec3 wo = adversarial_direction(rng), wi = adversarial_direction(rng);
          const glm::vec3 f = bcsdf.f(wo, wi);
          const float pdf = bcsdf.pdf(wo, wi);
          ++local_eval;
          if (!finite_nonneg(f)) bad_f.fail(describe(p, h, wo, wi));
          if (!(std::isfinite(pdf) && pdf >= 0)) bad_pdf.fail(describe(p, h, wo, wi));
          if (positive(f)) {
            ++local_nonzero;
            if (!(pdf > 0)) pdf_zero.fail(describe(p, h, wo, wi));
          }
          const auto s = bcsdf.sample(wo, {rng.uniformf(), rng.uniformf()}, {rng.uniformf(), rng.uniformf()});
          if (!s) continue;
          ++local_sampled;
          const bool ok = finite_nonneg(s->f) && std::isfinite(s->pdf) && s->pdf > 0 &&
                          std::isfinite(s->wi.x + s->wi.y + s->wi.z) && std::abs(glm::length(s->wi) - 1.0f) < 1e-5f;
          if (!ok) bad_sample.fail(describe(p, h, wo, s->wi));
        }
      }
      evaluated += local_eval;
      sampled += local_sampled;
      nonzero += local_nonzero;
    }
  });
  EXPECT_GT(evaluated.load(), n * 8 / 10) << "too many inputs skipped";
  // The inputs must exercise the lobes, not just return zero.
  EXPECT_GT(nonzero.load(), evaluated.load() / 4);
  EXPECT_GT(sampled.load(), evaluated.load() / 2);
  EXPECT_EQ(bad_ctor.count.load(), 0) << "valid parameters rejected, first: " << bad_ctor.first;
  EXPECT_EQ(bad_f.count.load(), 0) << "f not finite or negative, first: " << bad_f.first;
  EXPECT_EQ(bad_pdf.count.load(), 0) << "pdf not finite or negative, first: " << bad_pdf.first;
  EXPECT_EQ(pdf_zero.count.load(), 0) << "pdf = 0 where f > 0, first: " << pdf_zero.first;
  EXPECT_EQ(bad_sample.count.load(), 0) << "bad sample, first: " << bad_sample.first;
}

// --- degenerate geometry -----------------------------------------------------------

namespace {

struct Shot {
  Image image;
  std::int64_t bad_samples = 0;  // the renderer's own NaN/Inf counter (--stats)
  int nan_pixels = 0;
};

std::int64_t bad_sample_counter() {
  const auto snap = stats_snapshot();
  const auto it = snap.find("Renderer/NaN or Inf samples dropped");
  return it == snap.end() ? 0 : std::int64_t(it->second);
}

// A top view (orthographic, looking down -Z) of `feather` centred on `centre`,
// `height` mm tall, lit by a distant light from above-front; direct light only
// unless `depth` says otherwise, so a dark pixel on a fibre means a shadow.
Shot shoot(const Feather& feather, const glm::vec3& centre, float height, int px, int spp, int depth = 1,
           bool environment = false, ShadingMode mode = ShadingMode::Hair) {
  SceneOptions so;
  so.mode = mode;
  const Scene scene(feather, so);
  LightSet lights;
  lights.add(DirectionalLight{glm::normalize(glm::vec3(0.0f, -0.3f, 1.0f)), glm::vec3(3.0f)});
  if (environment) lights.set_environment(EnvironmentLight(glm::vec3(0.5f)));
  const FibreMaterial material(HairParams{});
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{depth, 3});
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = centre + glm::vec3(0, 0, 50);
  cs.look_at = centre;
  cs.ortho_height = height;
  const Camera camera(cs, px, px, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = spp;
  rs.progress = false;
  rs.seed = 3;
  const std::int64_t before = bad_sample_counter();
  Shot shot;
  shot.image = render(camera, integrator, rs).developed(0);
  shot.bad_samples = bad_sample_counter() - before;
  for (float v : shot.image.pixels)
    if (!std::isfinite(v)) ++shot.nan_pixels;
  return shot;
}

// Both vanes get barbules (DESIGN §5), so substructure mode has something to find.
Feather with_substructure(Feather f) {
  SubstructureParams p;
  p.barbules_per_side = 40;
  p.ramus_radius = 0.04f;
  p.barbule_radius = 0.01f;
  p.elevation_deg = 45;
  p.azimuth_deg = 10;
  p.hooked_fraction = 0.2f;
  p.ribbon_width = 0.4f;
  f.left = f.right = p;
  return f;
}

// Hair mode draws barbs at the vane's ribbon width when one is given (DESIGN §4),
// so it gets the curves' own radii only without substructure parameters.
Feather for_mode(const Feather& f, ShadingMode m) { return m == ShadingMode::Hair ? f : with_substructure(f); }

const char* name(ShadingMode m) { return to_string(m); }
constexpr ShadingMode kModes[] = {ShadingMode::Hair, ShadingMode::Substructure, ShadingMode::Explicit,
                                  ShadingMode::Farfield};

// A feather whose every curve is moved by `offset`.
Feather moved(Feather f, const glm::vec3& offset) {
  for (Curve& c : f.curves)
    for (auto& cp : c.points) cp.p += offset;
  return f;
}

// Over the pixels that see the ribbon (any light at all in the reference image
// `mask`): the mean of the red channel; the fraction under a tenth of the median
// (dark speckles); and, for a ribbon along the image's rows, whose shading varies
// only across its width, the fraction under half their row's median: shadow acne
// breaks that smoothness.
struct RibbonStats {
  double mean = 0;
  double dark_fraction = 0;
  double row_dark_fraction = 0;
  int pixels = 0;
};

RibbonStats ribbon_stats(const Image& img, const Image& mask) {
  RibbonStats s;
  std::vector<float> all;
  std::int64_t row_dark = 0;
  for (int y = 0; y < img.height; ++y) {
    std::vector<float> row;
    for (int x = 0; x < img.width; ++x)
      if (mask.at(x, y)[0] > 0) row.push_back(img.at(x, y)[0]);
    if (row.empty()) continue;
    const float m = median(row);
    row_dark += std::count_if(row.begin(), row.end(), [&](float v) { return v < 0.5f * m; });
    all.insert(all.end(), row.begin(), row.end());
  }
  s.pixels = int(all.size());
  if (all.empty()) return s;
  for (float v : all) s.mean += v;
  s.mean /= double(all.size());
  const float m = median(all);
  s.dark_fraction = double(std::count_if(all.begin(), all.end(), [&](float v) { return v < 0.1f * m; })) /
                    double(all.size());
  s.row_dark_fraction = double(row_dark) / double(all.size());
  return s;
}

// Fraction of pixels that differ from the background `bg` (red channel): the
// fibres are in view, so the NaN checks are about something.
double coverage(const Image& img, float bg) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) n += std::abs(img.at(x, y)[0] - bg) > 1e-3f;
  return double(n) / (double(img.width) * img.height);
}

// A wide, straight fibre along X at `centre`: a flat barb ribbon or a round shaft.
Feather straight_fibre(CurveKind kind, const glm::vec3& centre, float radius) {
  Feather f;
  f.curves.push_back(test::straight_curve(kind, centre, 6.0f, radius));
  return f;
}

}  // namespace

TEST(StressRender, CoincidentControlPointsGiveNoNaN) {
  Feather f = test::make_test_feather(20.0f, 1.0f, 0.08f);
  // A barb collapsed to one point, one with a doubled middle point, one that folds back.
  Curve point = test::straight_curve(CurveKind::Barb, {2, 10, 0}, 0.0f, 0.1f);
  Curve doubled = test::straight_curve(CurveKind::Barb, {-2, 8, 0}, 2.0f, 0.1f);
  doubled.points[2].p = doubled.points[1].p;
  Curve folded = test::straight_curve(CurveKind::Barb, {0, 12, 0}, 2.0f, 0.1f);
  folded.points[2].p = folded.points[0].p;
  folded.points[3].p = folded.points[1].p;
  for (Curve* c : {&point, &doubled, &folded}) f.curves.push_back(*c);
  // The shaft with every control point in one place too.
  for (auto& cp : f.curves[0].points) cp.p = {0, 10, 0};
  for (ShadingMode mode : kModes) {
    const Shot shot = shoot(for_mode(f, mode), {0, 10, 0}, 24.0f, 24, 8, 4, true, mode);
    EXPECT_GT(coverage(shot.image, 0.5f), 0.05) << name(mode);
    EXPECT_EQ(shot.nan_pixels, 0) << name(mode);
    EXPECT_EQ(shot.bad_samples, 0) << name(mode);
  }
}

TEST(StressRender, ZeroAndHugeRadiiGiveNoNaN) {
  Feather zero = test::make_test_feather(20.0f, 1.0f, 0.0f);
  for (auto& cp : zero.curves[0].points) cp.radius = 0.0f;
  // Radii far larger than the curves are long: the ribbons cover each other and the view.
  Feather huge = test::make_test_feather(20.0f, 2.0f, 1e3f);
  for (auto& cp : huge.curves[0].points) cp.radius = 1e4f;
  for (ShadingMode mode : kModes) {
    const Shot z = shoot(for_mode(zero, mode), {0, 10, 0}, 24.0f, 16, 4, 4, true, mode);
    EXPECT_EQ(z.nan_pixels, 0) << name(mode);
    EXPECT_EQ(z.bad_samples, 0) << name(mode);
    const Shot h = shoot(for_mode(huge, mode), {0, 10, 0}, 24.0f, 16, 4, 4, true, mode);
    // Not all of the view: Embree drops flat-curve hits within 2 radii of the ray
    // origin (DESIGN §4), and the camera is 50 mm from ribbons 2 m wide.
    EXPECT_GT(coverage(h.image, 0.5f), 0.1) << name(mode) << ": huge fibres must be in view";
    EXPECT_EQ(h.nan_pixels, 0) << name(mode);
    EXPECT_EQ(h.bad_samples, 0) << name(mode);
  }
}

TEST(StressRender, ExtremelyThinRibbonsGiveNoNaN) {
  for (ShadingMode mode : kModes)
    for (float radius : {1e-6f, 1e-20f, kDenorm}) {
      const Feather f = for_mode(test::make_test_feather(20.0f, 0.5f, radius), mode);
      const Shot s = shoot(f, {0, 10, 0}, 24.0f, 16, 4, 4, true, mode);
      EXPECT_GT(coverage(s.image, 0.5f), 0.01) << name(mode) << ": the shaft at least is in view";
      EXPECT_EQ(s.nan_pixels, 0) << name(mode) << " " << radius;
      EXPECT_EQ(s.bad_samples, 0) << name(mode) << " " << radius;
    }
}

TEST(StressRender, LitFibreFarFromTheOriginHasNoAcne) {
  // The same lit fibre at the origin and 10^5 mm away: the far copy must look the
  // same (self-shadowing from too small a ray offset shows as dark speckles). Round
  // curves matter most: Embree's near-origin culling hides flat ribbons from
  // themselves anyway.
  const float radius = 1.0f;
  for (CurveKind kind : {CurveKind::Shaft, CurveKind::Barb}) {
    const char* name = kind == CurveKind::Shaft ? "round shaft" : "flat barb";
    const Shot near = shoot(straight_fibre(kind, {0, 0, 0}, radius), {0, 0, 0}, 2.4f * radius, 32, 16);
    const RibbonStats ref = ribbon_stats(near.image, near.image);
    ASSERT_GT(ref.pixels, 200) << name << ": the fibre must fill much of the view";
    EXPECT_LT(ref.row_dark_fraction, 0.01) << name << ": the reference itself must be smooth along the fibre";
    for (const glm::vec3 where : {glm::vec3(1e5f, 0, 0), glm::vec3(-1e5f, 1e5f, 1e5f)}) {
      const Shot far = shoot(straight_fibre(kind, where, radius), where, 2.4f * radius, 32, 16);
      EXPECT_EQ(far.nan_pixels, 0) << name;
      EXPECT_EQ(far.bad_samples, 0) << name;
      const RibbonStats s = ribbon_stats(far.image, near.image);
      EXPECT_LT(s.row_dark_fraction, ref.row_dark_fraction + 0.01) << name << " at " << where.x << " " << where.y;
      EXPECT_NEAR(s.mean, ref.mean, 0.05 * ref.mean) << name << " at " << where.x << " " << where.y;
    }
  }
}

TEST(StressRender, FeatherFarFromTheOriginLooksTheSame) {
  // Multiple bounces among neighbouring barbs, 10^5 mm out.
  const Feather f = test::make_test_feather(20.0f, 0.5f, 0.08f);
  const glm::vec3 c(0, 10, 0);
  for (ShadingMode mode : kModes) {
    // Explicit barbules are round curves 10 um thick stored in float: 10^5 mm out a
    // float step is 7.8 um and they cannot be drawn (measured: 14 % brighter); at
    // 10^3 mm it is 0.06 um. docs/rendering.md states the limit.
    const glm::vec3 off = mode == ShadingMode::Explicit ? glm::vec3(1e3f, -1e3f, 0) : glm::vec3(1e5f, -1e5f, 0);
    const Feather g = for_mode(f, mode);
    const Shot near = shoot(g, c, 22.0f, 32, 16, 4, false, mode);
    const Shot far = shoot(moved(g, off), c + off, 22.0f, 32, 16, 4, false, mode);
    EXPECT_EQ(far.nan_pixels, 0) << name(mode);
    EXPECT_EQ(far.bad_samples, 0) << name(mode);
    const RibbonStats a = ribbon_stats(near.image, near.image), b = ribbon_stats(far.image, near.image);
    ASSERT_GT(a.pixels, 50) << name(mode);
    EXPECT_NEAR(b.mean, a.mean, 0.1 * a.mean) << name(mode);
    EXPECT_LT(b.dark_fraction, a.dark_fraction + 0.05) << name(mode);
  }
}
