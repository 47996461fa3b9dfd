// Renderer throughput: primary rays through the renderer (camera + Scene::intersect
// + hit record) against bare Embree (rtcIntersect1 alone over the same rays and
// scene), path-tracing rays per second, and the sampler study (RMSE against a
// high-spp reference at equal spp, Sobol vs independent). docs/perf/render.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <embree3/rtcore.h>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/render.h"

using namespace plumage;

namespace {

constexpr int kRes = 256;

struct BenchScene {
  Feather feather = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  Scene scene{feather, SceneOptions{ShadingMode::Hair, {true, glm::vec3(0.8f)}}};
  Camera camera{CameraSpec{}, kRes, kRes, scene.feather_bounds()};
  std::vector<Ray> rays;
  BenchScene() {
    for (int y = 0; y < kRes; ++y)
      for (int x = 0; x < kRes; ++x) rays.push_back(camera.generate(x + 0.5f, y + 0.5f));
  }
};
BenchScene& bench_scene() {
  static BenchScene s;
  return s;
}

void BM_PrimaryRays_Renderer(benchmark::State& state) {
  BenchScene& b = bench_scene();
  std::int64_t hits = 0;
  for (auto _ : state) {
    for (int y = 0; y < kRes; ++y)
      for (int x = 0; x < kRes; ++x) {
        const Ray r = b.camera.generate(x + 0.5f, y + 0.5f);
        SurfaceHit hit;
        hits += b.scene.intersect(r, hit);
        benchmark::DoNotOptimize(hit);
      }
  }
  state.SetItemsProcessed(state.iterations() * kRes * kRes);
  state.counters["hit_fraction"] = double(hits) / double(state.iterations() * kRes * kRes);
}
BENCHMARK(BM_PrimaryRays_Renderer)->Unit(benchmark::kMillisecond);

void BM_PrimaryRays_BareEmbree(benchmark::State& state) {
  BenchScene& b = bench_scene();
  auto scene = static_cast<RTCScene>(b.scene.embree_scene());
  std::int64_t hits = 0;
  for (auto _ : state) {
    for (const Ray& r : b.rays) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      RTCRayHit rh{};
      rh.ray.org_x = r.o.x; rh.ray.org_y = r.o.y; rh.ray.org_z = r.o.z;
      rh.ray.dir_x = r.d.x; rh.ray.dir_y = r.d.y; rh.ray.dir_z = r.d.z;
      rh.ray.tnear = 0;
      rh.ray.tfar = INFINITY;
      rh.ray.mask = 0xffffffffu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      benchmark::DoNotOptimize(rh);
    }
  }
  state.SetItemsProcessed(state.iterations() * kRes * kRes);
  state.counters["hit_fraction"] = double(hits) / double(state.iterations() * kRes * kRes);
}
BENCHMARK(BM_PrimaryRays_BareEmbree)->Unit(benchmark::kMillisecond);

// Mean over pixels and channels of the squared difference.
double mean_squared_error(const Image& img, const Image& reference) {
  double s = 0;
  for (std::size_t i = 0; i < img.pixels.size(); ++i) s += std::pow(double(img.pixels[i]) - reference.pixels[i], 2);
  return s / double(img.pixels.size());
}

// RMSE against `reference` of renders with seeds 0, 1, 2, ... (one per iteration).
double rmse_over_seeds(benchmark::State& state, const Camera& camera, const PathIntegrator& integrator,
                       RenderSettings rs, const Image& reference) {
  double se = 0;
  int runs = 0;
  for (auto _ : state) {
    rs.seed = std::uint64_t(runs++);
    se += mean_squared_error(render(camera, integrator, rs).developed(0), reference);
  }
  return std::sqrt(se / runs);
}

// All 25 dome LEDs, placed as every render places them (view_lights).
LightSet dome_all(const Scene& scene) {
  return view_lights(scene.feather_bounds(), read_dome_rig(std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json"),
                     ViewSpec{});
}

// Whole-image path tracing (1 thread so the figure is per core): rays = camera,
// bounce and shadow rays.
void BM_PathTrace(benchmark::State& state) {
  BenchScene& b = bench_scene();
  const LightSet lights = dome_all(b.scene);
  const FibreMaterial material(HairParams{}, AlbedoMap(b.feather.albedo, "."));
  const PathIntegrator integrator(b.scene, lights, material, IntegratorSettings{});
  const Camera camera(CameraSpec{}, 64, 64, b.scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 4;
  rs.threads = int(state.range(0));
  rs.progress = false;
  std::int64_t rays = 0;
  for (auto _ : state) {
    stats_reset();
    benchmark::DoNotOptimize(render(camera, integrator, rs));
    rays += std::int64_t(stats_snapshot()["Renderer/Rays traced"]);
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PathTrace)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// What down barbs cost (docs/curve-format.md, "Down"): the rock dove built with a
// closed vane (arg 0) and as a plume of down barbs base to tip (arg 1, the
// afterfeather's defaults), hair mode under the dome, one thread; rays per second
// and rays per camera sample.
void BM_PathTraceDown(benchmark::State& state) {
  FeatherParams p = load_preset("rock-dove-wing");
  p.afterfeather.enabled = state.range(0) == 1;
  p.afterfeather.fraction = 1.0;
  p.afterfeather.radius = FeatherParams{}.afterfeather.radius;
  p.afterfeather.cover = FeatherParams{}.afterfeather.cover;
  const Feather feather = build_feather(p, 1, "preset:rock-dove-wing");
  const Scene scene(feather, SceneOptions{ShadingMode::Hair, {true, glm::vec3(0.8f)}});
  const LightSet lights = dome_all(scene);
  const FibreMaterial material(HairParams{}, AlbedoMap(feather.albedo, "."));
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{});
  const Camera camera(CameraSpec{}, 64, 64, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 4;
  rs.threads = 1;
  rs.progress = false;
  std::int64_t rays = 0, samples = 0;
  for (auto _ : state) {
    stats_reset();
    benchmark::DoNotOptimize(render(camera, integrator, rs));
    auto snap = stats_snapshot();
    rays += std::int64_t(snap["Renderer/Rays traced"]);
    samples += std::int64_t(snap["Renderer/Camera samples"]);
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["rays_per_sample"] = double(rays) / double(std::max<std::int64_t>(samples, 1));
}
BENCHMARK(BM_PathTraceDown)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// RMSE of a 48x48 render of the feather under the dome against a 1024-spp
// Sobol reference, at equal spp for each sampler (arg 0: spp, arg 1: 0 = Sobol, 1 = independent).
void BM_SamplerRMSE(benchmark::State& state) {
  BenchScene& b = bench_scene();
  static const LightSet lights = dome_all(b.scene);
  static const FibreMaterial material(HairParams{}, AlbedoMap(b.feather.albedo, "."));
  static const PathIntegrator integrator(b.scene, lights, material, IntegratorSettings{});
  static const Camera camera(CameraSpec{}, 48, 48, b.scene.feather_bounds());
  static const Image reference = [] {
    RenderSettings rs;
    rs.spp = 1024;
    rs.seed = 999;
    rs.progress = false;
    return render(camera, integrator, rs).developed(0);
  }();
  RenderSettings rs;
  rs.spp = int(state.range(0));
  rs.sampler = state.range(1) == 0 ? SamplerKind::Sobol : SamplerKind::Independent;
  rs.progress = false;
  state.counters["rmse"] = rmse_over_seeds(state, camera, integrator, rs, reference);
  state.SetLabel(rs.sampler == SamplerKind::Sobol ? "sobol" : "independent");
}
BENCHMARK(BM_SamplerRMSE)
    ->ArgsProduct({{4, 16, 64}, {0, 1}})
    ->Iterations(4)
    ->Unit(benchmark::kMillisecond);

// Next-event estimation's light choice (arg 0: spp, arg 1: LightPick uniform /
// estimate / all): RMSE of a 48x48 render of the osprey preset (hair shading,
// white card) under all 25 LEDs against one 512-spp reference drawn with every
// light per vertex, and the CPU time per image (1 thread). Efficiency is
// 1 / (rmse^2 x time). docs/perf/render.md, "Light selection".
void BM_LightPickRMSE(benchmark::State& state) {
  static const Feather feather = build_feather(load_preset("osprey-wing-covert"), 1, "preset:osprey-wing-covert");
  static const Scene scene(feather, SceneOptions{ShadingMode::Hair, {true, glm::vec3(0.8f)}});
  static const LightSet lights = dome_all(scene);
  static const FibreMaterial material(HairParams{}, AlbedoMap(feather.albedo, "."));
  static const Camera camera(CameraSpec{}, 48, 48, scene.feather_bounds());
  const auto integrator = [](LightPick pick) {
    IntegratorSettings is;
    is.light_pick = pick;
    return PathIntegrator(scene, lights, material, is);
  };
  static const Image reference = [&] {
    RenderSettings rs;
    rs.spp = 512;
    rs.seed = 999;
    rs.threads = 1;
    rs.progress = false;
    return render(camera, integrator(LightPick::All), rs).developed(0);
  }();
  const LightPick pick = LightPick(state.range(1));
  const PathIntegrator pi = integrator(pick);
  RenderSettings rs;
  rs.spp = int(state.range(0));
  rs.threads = 1;
  rs.progress = false;
  state.counters["rmse"] = rmse_over_seeds(state, camera, pi, rs, reference);
  state.SetLabel(to_string(pick));
}
BENCHMARK(BM_LightPickRMSE)
    ->ArgsProduct({{16, 32}, {0, 1, 2}})
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond);

}  // namespace

namespace {

// Cost of four sample dimensions (arg: 0 = Sobol, 1 = independent).
void BM_SamplerNext4(benchmark::State& state) {
  PixelSampler s(state.range(0) == 0 ? SamplerKind::Sobol : SamplerKind::Independent, 7);
  std::uint32_t i = 0;
  for (auto _ : state) {
    s.start(int(i & 63), int(i >> 6 & 63), i);
    benchmark::DoNotOptimize(s.next4());
    ++i;
  }
  state.SetLabel(state.range(0) == 0 ? "sobol" : "independent");
}
BENCHMARK(BM_SamplerNext4)->Arg(0)->Arg(1);

}  // namespace
