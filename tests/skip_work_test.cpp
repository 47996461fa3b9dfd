// Skipping what the scene does not need (issue 7): view culling keeps the image,
// lights that are off cost nothing, hair mode runs no substructure code, the
// renderer does not use OpenCV, and adaptive sampling stays near the reference.
#include <unistd.h>
#include <gtest/gtest.h>

#include <vector>

#include <cstring>

#include <set>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <filesystem>
#include <memory>
#include <string>

#include "plumage/common/error.h"
#include "plumage/common/stats.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/error_ladder.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/view_cull.h"

namespace plumage {
namespace {

const Feather& rock_dove() {
  static const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  return f;
}

const DomeRig& rig() {
  static const DomeRig r = read_dome_rig(std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json");
  return r;
}

double counter(const std::string& name) {
  const auto snap = stats_snapshot();
  const auto it = snap.find(name);
  return it == snap.end() ? 0.0 : it->second;
}

double mean(const Image& img) {
  double s = 0;
  for (float v : img.pixels) s += v;
  return s / double(img.pixels.size());
}

// A close top view of part of the vane: most barbs are out of the frame.
ViewSpec zoomed_view(const Scene& full) {
  const Bounds3f& fb = full.feather_bounds();
  ViewSpec v;
  v.width = 24;
  v.height = 24;
  v.spp = 4;
  v.seed = 7;
  const glm::vec3 target(fb.centre().x, fb.lo.y + 0.6f * fb.size().y, fb.centre().z);
  v.camera.look_at = target;
  v.camera.position = target + glm::vec3(0, 0, 15);
  return v;
}

TEST(SkipWork, CullingDropsCurvesButNotPixelsInAZoomedView) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  const Scene full(rock_dove(), so);
  ViewSpec view = zoomed_view(full);
  view.lights = "1,7,13";
  so.cull = view_cull_for(view, rig());
  const double before = counter("Scene/Curves culled (outside the view and its shadow reach)");
  const Scene culled(rock_dove(), so);
  // The shadow reach toward low LEDs keeps a wide band; still a good part goes.
  EXPECT_GT(culled.culled_curves(), rock_dove().curves.size() / 4);
  EXPECT_EQ(counter("Scene/Curves culled (outside the view and its shadow reach)") - before,
            double(culled.culled_curves()));
  // The view is framed from the same bounds and backdrop.
  EXPECT_EQ(culled.feather_bounds().lo, full.feather_bounds().lo);
  EXPECT_EQ(culled.backdrop_z(), full.backdrop_z());

  // Direct light only: a culled curve can neither be hit nor cast a shadow here,
  // so every sample takes the same path.
  view.max_depth = 1;
  const Image a = render_view(full, rig(), view), b = render_view(culled, rig(), view);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_GT(mean(a), 0.0);
  // All bounces: only light scattered off culled barbs is lost; within noise.
  view.max_depth = 16;
  view.spp = 16;
  const Image c = render_view(full, rig(), view), d = render_view(culled, rig(), view);
  EXPECT_NEAR(mean(d), mean(c), 0.02 * mean(c));
}

TEST(SkipWork, CullingKeepsEverythingWhenAllIsInViewOrUnbounded) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  ViewSpec view;  // auto-framed: the whole feather is in the frame
  view.width = 32;
  view.height = 48;
  so.cull = view_cull_for(view, rig());
  EXPECT_EQ(Scene(rock_dove(), so).culled_curves(), 0u);

  // An environment lights from the horizon: shadows reach arbitrarily far.
  const Scene full(rock_dove(), SceneOptions{});
  const ViewSpec zoom = zoomed_view(full);
  const Camera camera(zoom.camera, zoom.width, zoom.height, full.feather_bounds());
  LightSet env;
  env.set_environment(EnvironmentLight(glm::vec3(1)));
  const Bounds3f far{glm::vec3(1e4f), glm::vec3(1e4f + 1)};
  EXPECT_TRUE(view_cull(camera, env, full.feather_bounds(), full.feather_bounds().lo.z)(far));
  // A light level with the feather's top: no bound on the shadow's run either.
  LightSet low;
  low.add(SphereLight{glm::vec3(0, 0, full.feather_bounds().hi.z), 1.0f, glm::vec3(1)});
  EXPECT_TRUE(view_cull(camera, low, full.feather_bounds(), full.feather_bounds().lo.z)(far));
}

TEST(SkipWork, CullRuleKeepsShadowCastersAboveTheView) {
  // Orthographic top view of x, y in [-5, 5] over a floor at z = 0.
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = glm::vec3(0, 0, 100);
  cs.look_at = glm::vec3(0);
  cs.ortho_height = 10;
  const Bounds3f fb{glm::vec3(-100, -100, 0), glm::vec3(100, 100, 10)};
  const Camera camera(cs, 10, 10, fb);
  LightSet lights;  // one LED straight up, 50 mm over the floor, radius 1
  lights.add(SphereLight{glm::vec3(0, 0, 50), 1.0f, glm::vec3(1)});
  const CurveKeep keep = view_cull(camera, lights, fb, 0.0f, 0.0f);
  auto box = [](float x, float z) { return Bounds3f{glm::vec3(x, -0.1f, z), glm::vec3(x + 0.2f, 0.1f, z + 0.2f)}; };
  EXPECT_TRUE(keep(box(0, 5)));     // in view
  EXPECT_FALSE(keep(box(30, 0)));   // far outside, on the floor: casts nowhere
  // Shadow ray from the view's corner (5, 5, 0) to the LED's far side: run
  // |(5,5)| + 1 = 8.07 over rise 50 - 1 - 10 = 39, so a caster 9.8 mm up reaches
  // 9.8 x 0.207 = 2.0 mm beyond the view.
  EXPECT_TRUE(keep(box(6.9f, 9.6f)));
  EXPECT_FALSE(keep(box(8.0f, 9.6f)));
  // Brute force: any box the rule drops lies off every segment from a seen point
  // of the floor or the slab to any point of the light.
  for (int i = 0; i < 2000; ++i) {
    const float x = 6 + 20 * float(i % 40) / 40, z = 10 * float(i / 40) / 50;
    const Bounds3f b = box(x, z);
    if (keep(b)) continue;
    for (float px : {-5.0f, 0.0f, 5.0f})
      for (float pz : {0.0f, 5.0f, 10.0f})
        for (float lx : {-1.0f, 0.0f, 1.0f}) {
          const glm::vec3 p(px, 0, pz), l(lx, 0, 50 - (lx == 0 ? 1.0f : 0.0f));
          if (pz > b.hi.z) continue;
          // x is monotonic along the segment: its part inside the box's z range
          // runs between the x at the two z bounds.
          auto x_at = [&](float zz) { return p.x + std::clamp((zz - p.z) / (l.z - p.z), 0.0f, 1.0f) * (l.x - p.x); };
          const float x0 = x_at(b.lo.z), x1 = x_at(b.hi.z);
          EXPECT_TRUE(std::max(x0, x1) < b.lo.x || std::min(x0, x1) > b.hi.x)
              << "box at x=" << x << " z=" << z << " shadows (" << px << "," << pz << ")";
        }
  }
}

TEST(SkipWork, LightsThatAreOffCostNothing) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  const Scene scene(rock_dove(), so);
  ViewSpec view;
  view.width = 16;
  view.height = 24;
  view.spp = 2;
  view.lights = "none";
  const double shadow = counter("Renderer/Shadow rays");
  const Image dark = render_view(scene, rig(), view);
  EXPECT_EQ(counter("Renderer/Shadow rays"), shadow);
  EXPECT_EQ(mean(dark), 0.0);
  // LED 5 of 25 renders exactly as a rig that has only LED 5: the 24 that are off
  // take no samples and change nothing.
  view.lights = "5";
  DomeRig one = rig();
  one.leds = {rig().leds[4]};
  ViewSpec only = view;
  only.lights = "all";
  const Image a = render_view(scene, rig(), view), b = render_view(scene, one, only);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_GT(mean(a), 0.0);
  EXPECT_GT(counter("Renderer/Shadow rays"), shadow);
}

TEST(SkipWork, HairModeRunsNoSubstructureCode) {
  ViewSpec view;
  view.width = 16;
  view.height = 24;
  view.spp = 2;
  const double lookups = counter("Substructure/Structure lookups at shading");
  const double gaps = counter("Substructure/Candidate hits rejected in gaps");
  SceneOptions so;
  so.mode = ShadingMode::Hair;
  const Image hair = render_view(Scene(rock_dove(), so), rig(), view);
  EXPECT_GT(mean(hair), 0.0);
  EXPECT_EQ(counter("Substructure/Structure lookups at shading"), lookups);
  EXPECT_EQ(counter("Substructure/Candidate hits rejected in gaps"), gaps);
  // The counters do move when substructure code runs.
  so.mode = ShadingMode::Substructure;
  render_view(Scene(rock_dove(), so), rig(), view);
  EXPECT_GT(counter("Substructure/Structure lookups at shading"), lookups);
  EXPECT_GT(counter("Substructure/Candidate hits rejected in gaps"), gaps);
}

// A static library's symbols (demangled names), `undefined` or defined ones (code
// and data, weak ones included).
std::set<std::string> archive_symbols(const std::filesystem::path& archive, bool undefined) {
  const std::string cmd = "nm -C " + std::string(undefined ? "--undefined-only" : "--defined-only") + " '" +
                          archive.string() + "' 2>/dev/null";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  std::set<std::string> names;
  if (!pipe) return names;
  char line[8192];
  while (std::fgets(line, sizeof line, pipe.get())) {
    std::string s(line);
    if (!s.empty() && s.back() == '\n') s.pop_back();
    // "ADDRESS T name" or "                 U name" (a member's "file.o:" header has no type).
    const std::size_t type_at = s.empty() ? std::string::npos
                                : s[0] == ' '  ? s.find_first_not_of(' ')
                                               : s.find_first_not_of(' ', s.find(' '));
    if (type_at == std::string::npos || type_at + 2 > s.size() || s[type_at + 1] != ' ') continue;
    const char type = s[type_at];
    if (!undefined && !std::strchr("TWVDBR", type)) continue;
    names.insert(s.substr(type_at + 2));
  }
  return names;
}

// Undefined symbols of a static library that name OpenCV's namespace.
int opencv_references(const std::filesystem::path& archive) {
  const std::set<std::string> used = archive_symbols(archive, true);
  return int(std::count_if(used.begin(), used.end(), [](const std::string& s) { return s.find("cv::") != std::string::npos; }));
}

// OpenCV stays in photo analysis: neither the renderer nor the generator (which
// builds feathers from params or a layout file) links it (DESIGN section 2).
TEST(SkipWork, RendererAndGeneratorDoNotUseOpenCV) {
  const std::filesystem::path build = std::filesystem::path(PLUMAGE_CLI).parent_path();
  const auto renderer = build / "libplumage_renderer.a", generator = build / "libplumage_generator.a",
             analysis = build / "libplumage_analysis.a";
  if (!std::filesystem::exists(renderer) || !std::filesystem::exists(generator) ||
      !std::filesystem::exists(analysis) || std::system("nm --version >/dev/null 2>&1"))
    GTEST_SKIP() << "needs nm and the static libraries in " << build;
  // The check can see OpenCV: photo analysis uses it.
  EXPECT_GT(opencv_references(analysis), 0);
  EXPECT_EQ(opencv_references(renderer), 0);
  EXPECT_EQ(opencv_references(generator), 0);
}

// The arrows between the libraries run one way (docs/analysis.md, "Where the code
// is"): photo analysis and the generator are peers that both use the layout
// library (layout.json's types, reader, writer and rules), and neither uses a
// symbol the other defines; the layout library uses neither.
TEST(SkipWork, AnalysisAndGeneratorArePeersOverTheLayoutLibrary) {
  const std::filesystem::path build = std::filesystem::path(PLUMAGE_CLI).parent_path();
  const auto generator = build / "libplumage_generator.a", analysis = build / "libplumage_analysis.a",
             layout = build / "libplumage_layout.a";
  if (!std::filesystem::exists(generator) || !std::filesystem::exists(analysis) || !std::filesystem::exists(layout) ||
      std::system("nm --version >/dev/null 2>&1"))
    GTEST_SKIP() << "needs nm and the static libraries in " << build;
  const auto uses = [](const std::set<std::string>& undefined, const std::set<std::string>& defined) {
    std::vector<std::string> both;
    for (const std::string& s : undefined)
      if (defined.count(s)) both.push_back(s);
    return both;
  };
  const auto gen_defs = archive_symbols(generator, false), ana_defs = archive_symbols(analysis, false),
             lay_defs = archive_symbols(layout, false);
  const auto gen_uses = archive_symbols(generator, true), ana_uses = archive_symbols(analysis, true),
             lay_uses = archive_symbols(layout, true);
  // The check can see a use: both read and write through the layout library.
  EXPECT_FALSE(uses(ana_uses, lay_defs).empty());
  EXPECT_FALSE(uses(gen_uses, lay_defs).empty());
  const auto first = [](const std::vector<std::string>& v) { return v.empty() ? std::string() : v.front(); };
  EXPECT_EQ(uses(ana_uses, gen_defs).size(), 0u) << "analysis uses the generator's " << first(uses(ana_uses, gen_defs));
  EXPECT_EQ(uses(gen_uses, ana_defs).size(), 0u) << "the generator uses analysis's " << first(uses(gen_uses, ana_defs));
  EXPECT_EQ(uses(lay_uses, gen_defs).size() + uses(lay_uses, ana_defs).size(), 0u)
      << "the layout library uses " << first(uses(lay_uses, gen_defs)) << first(uses(lay_uses, ana_defs));
}

Image render_adaptive(const Scene& scene, int spp, std::uint64_t seed, bool adaptive, int threads) {
  ViewSpec view;
  view.width = 16;
  view.height = 24;
  view.spp = spp;
  view.seed = seed;
  view.threads = threads;
  view.adaptive = adaptive;
  view.target_error = 0.05f;
  view.min_spp = 16;
  return render_view(scene, rig(), view);
}

TEST(SkipWork, AdaptiveSamplingSavesSamplesAndStaysNearTheReference) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  const Scene scene(rock_dove(), so);
  const Image reference = render_adaptive(scene, 512, 99, false, 0);
  const Image fixed = render_adaptive(scene, 256, 1, false, 0);
  const double saved = counter("Renderer/Camera samples saved by adaptive sampling");
  const Image adaptive = render_adaptive(scene, 256, 1, true, 0);
  const double saved_now = counter("Renderer/Camera samples saved by adaptive sampling") - saved;
  EXPECT_GT(saved_now, 0.25 * 16 * 24 * 256);
  // A 5 % relative standard error per pixel, against 256 samples' own noise.
  EXPECT_LT(rmse(adaptive, reference), 2.0 * rmse(fixed, reference) + 0.05 * mean(reference));
  EXPECT_NEAR(mean(adaptive), mean(reference), 0.03 * mean(reference));
  // Deterministic for a seed and independent of the thread count.
  EXPECT_EQ(render_adaptive(scene, 256, 1, true, 1).pixels, adaptive.pixels);
  EXPECT_EQ(render_adaptive(scene, 256, 1, true, 2).pixels, adaptive.pixels);
  // Off by default: the non-adaptive image is unchanged by the adaptive settings.
  ViewSpec v;
  EXPECT_FALSE(v.adaptive);
}

TEST(SkipWork, AdaptiveSettingsAreChecked) {
  const Scene scene(rock_dove(), SceneOptions{});
  ViewSpec view;
  view.width = 4;
  view.height = 4;
  view.adaptive = true;
  view.target_error = 0;
  EXPECT_THROW(render_view(scene, rig(), view), Error);
  view.target_error = NAN;
  EXPECT_THROW(render_view(scene, rig(), view), Error);
  view.target_error = 0.1f;
  view.min_spp = 1;
  EXPECT_THROW(render_view(scene, rig(), view), Error);
}

TEST(SkipWork, CliCullAndAdaptiveShowInStats) {
  const auto dir = std::filesystem::temp_directory_path() / ("plumage_skipwork_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cli = PLUMAGE_CLI, log = (dir / "log.txt").string();
  ASSERT_EQ(std::system((cli + " -q generate --preset rock-dove-wing --seed 1 -o " + (dir / "rd.fcurves").string() +
                         " 2>/dev/null").c_str()), 0);
  const std::string render = cli + " -q --stats render " + (dir / "rd.fcurves").string() + " -o " +
                             (dir / "o.png").string() + " --resolution 16x16 --spp 32 ";
  auto output = [&] {
    std::stringstream ss;
    ss << std::ifstream(log).rdbuf();
    return ss.str();
  };
  // --stats lists every counter, zeros included, so read the numbers, not just the names.
  auto count = [&](const std::string& name) {
    const std::string text = output();
    const auto at = text.find(name);
    if (at == std::string::npos) return -1.0;
    const auto end = text.find('\n', at);
    const std::string rest = text.substr(at + name.size(), end == std::string::npos ? std::string::npos : end - at - name.size());
    const auto close = rest.find(')');  // skip a parenthesised part of the name
    return std::stod(close == std::string::npos ? rest : rest.substr(close + 1));
  };
  ASSERT_EQ(std::system((render + "--camera-pos 10,60,15 --look-at 10,60,0 --cull 2>" + log).c_str()), 0);
  EXPECT_GT(count("Curves culled"), 0) << output();
  EXPECT_EQ(count("saved by adaptive sampling"), 0) << output();
  ASSERT_EQ(std::system((render + "--adaptive --target-error 0.2 2>" + log).c_str()), 0);
  EXPECT_GT(count("saved by adaptive sampling"), 0) << output();
  EXPECT_EQ(count("Curves culled"), 0) << output();
  EXPECT_NE(std::system((render + "--adaptive --target-error 0 2>" + log).c_str()), 0);
  EXPECT_NE(output().find("--target-error"), std::string::npos) << output();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace plumage
