// The exported scene is the one plumage renders: for every preset, in hair and
// substructure mode, the camera rays, the LEDs, the card, the absorption, the
// alpha sign, the barb width and the depth written for pbrt and Mitsuba equal
// the renderer's own (no external renderer needed; scripts/check_exports.sh
// renders the export in pbrt-v3).
#include "plumage/renderer/export_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <string>
#include <vector>

#include "plumage/common/error.h"
#include "plumage/common/exporters.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/hair_bcsdf.h"
#include "plumage/renderer/scene.h"

using namespace plumage;

namespace {

const DomeRig& dome25() {
  static const DomeRig rig = read_dome_rig(std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json");
  return rig;
}

// Numbers after `key` on its line (in its [ ] list if it has one): `Camera "perspective" "float fov" [ 20.25 ]`.
std::vector<float> numbers_after(const std::string& text, const std::string& key, std::size_t from = 0) {
  std::vector<float> out;
  const std::size_t at = text.find(key, from);
  EXPECT_NE(at, std::string::npos) << "no " << key;
  if (at == std::string::npos) return out;
  const char* p = text.c_str() + at + key.size();
  std::size_t stop = std::min(text.size(), text.find('\n', at + key.size()));
  const std::size_t open = text.find('[', at + key.size());
  if (open < stop) stop = text.find(']', open);  // a parameter list: just its values
  const char* end = text.c_str() + stop;
  while (p < end) {
    char* q = nullptr;
    const float v = std::strtof(p, &q);
    if (q == p) {
      ++p;
      continue;
    }
    out.push_back(v);
    p = q;
  }
  return out;
}

glm::vec3 normalize(const glm::vec3& v) { return v / glm::length(v); }

// The ray direction pbrt's perspective camera gives raster point (x, y), from the
// exported LookAt (after `Scale -1 1 1`), fov and resolution, by pbrt's rules:
// LookAt's camera x is cross(up, dir) (left-handed), the mirror flips it; the
// screen window spans [-1,1] on the shorter image side, [-aspect, aspect] on
// the longer; fov is that of the shorter side; raster y runs down.
glm::vec3 pbrt_ray(const std::vector<float>& look, float fov_deg, int w, int h, float x, float y) {
  const glm::vec3 eye(look[0], look[1], look[2]), at(look[3], look[4], look[5]), up(look[6], look[7], look[8]);
  const glm::vec3 dir = normalize(at - eye);
  const glm::vec3 cam_x = normalize(glm::cross(normalize(up), dir));
  const glm::vec3 cam_y = glm::cross(dir, cam_x);
  const glm::vec3 mirrored_x = -cam_x;
  const float aspect = float(w) / float(h);
  const float xmax = aspect > 1 ? aspect : 1, ymax = aspect > 1 ? 1 : 1 / aspect;
  const float sx = -xmax + x / float(w) * 2 * xmax, sy = ymax - y / float(h) * 2 * ymax;
  const float t = std::tan(fov_deg * float(std::numbers::pi) / 360);
  return normalize(dir + sx * t * mirrored_x + sy * t * cam_y);
}

// Mitsuba's perspective sensor with fov_axis y under a look_at to_world: image +x
// is cross(dir, up) (Mitsuba's camera x points left and its film flips it).
glm::vec3 mitsuba_ray(const ExportCamera& c, int w, int h, float x, float y) {
  const glm::vec3 dir = normalize(c.look_at - c.eye);
  const glm::vec3 right = normalize(glm::cross(dir, c.up));
  const glm::vec3 up = glm::cross(right, dir);
  const float t = std::tan(c.fov_deg * float(std::numbers::pi) / 360), aspect = float(w) / float(h);
  return normalize(dir + (2 * x / float(w) - 1) * t * aspect * right + (1 - 2 * y / float(h)) * t * up);
}

class ExportSceneTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ExportSceneTest, IsWhatTheRendererRenders) {
  const Feather feather = build_feather(load_preset(GetParam()), 1, "preset:" + GetParam());
  ASSERT_GT(feather.left.ribbon_width, 0) << "the presets draw barbs at W";

  ViewSpec view;
  view.width = 200;
  view.height = 300;  // portrait: pbrt's fov is then the horizontal one
  view.spp = 9;
  view.max_depth = 7;
  view.hair.alpha_deg = 3;
  view.hair.beta_m = 0.25f;
  for (const char* lights : {"all", "1,5,12"}) {
    view.lights = lights;
    for (ShadingMode mode : {ShadingMode::Hair, ShadingMode::Substructure}) {
      SCOPED_TRACE(GetParam() + " " + to_string(mode) + " lights " + lights);
      SceneOptions so;
      so.mode = mode;
      so.backdrop = {true, glm::vec3(0.8f)};
      const ExportScene es = export_scene(feather, dome25(), view, so);
      SceneOptions hair = so;
      hair.mode = ShadingMode::Hair;
      const Scene scene(feather, hair);  // the renderer's own, all curves built
      const auto& fb = scene.feather_bounds();

      // Width: barbs at W / 2 (not their own radius) from the root to the last
      // kBarbTipTaper of their length, then narrowing to their own radius at the
      // tip, as the scene draws them.
      float widest = 0;
      for (const Curve& c : feather.curves)
        if (c.kind == CurveKind::Barb) {
          const std::vector<float> r = render_radii(feather, c);
          const float half_w = 0.5f * feather.substructure(c.side).ribbon_width;
          EXPECT_EQ(r.front(), half_w);
          EXPECT_NE(r.front(), c.points.front().radius);
          if (c.points.size() > 4) {
            EXPECT_EQ(r.back(), std::min(c.points.back().radius, half_w));
          } else {
            EXPECT_EQ(r.back(), half_w);
          }
          for (std::size_t i = 1; i < r.size(); ++i) EXPECT_LE(r[i], r[i - 1]);  // never widens toward the tip
          for (float x : r) widest = std::max(widest, x);
        } else if (c.kind == CurveKind::Down) {  // the afterfeather's down barbs: their own radius
          EXPECT_EQ(render_radii(feather, c), [&] {
            std::vector<float> own;
            for (const ControlPoint& p : c.points) own.push_back(p.radius);
            return own;
          }());
          for (const ControlPoint& p : c.points) widest = std::max(widest, p.radius);
        }
      EXPECT_EQ(widest, scene.max_barb_radius());

      const Camera camera(view.camera, view.width, view.height, fb);
      const std::vector<SphereLight> leds = view_lights(fb, dome25(), view).spheres();
      const HairParams material = view_material(feather, view).at(feather.curves.back().points[2].p);
      EXPECT_EQ(material.sigma_a, sigma_a_from_layer_albedo(feather.albedo.color, view.hair.eta))
          << "plumage's own absorption for the preset's albedo";

      for (bool v4 : {false, true}) {
        SCOPED_TRACE(v4 ? "pbrt-v4" : "pbrt-v3");
        const std::string text = v4 ? format_pbrt_v4(feather, es) : format_pbrt_v3(feather, es);
        // Camera: the same ray through every corner and the centre.
        const std::vector<float> look = numbers_after(text, "\nLookAt");
        ASSERT_EQ(look.size(), 9u);
        EXPECT_NE(text.find("\nScale -1 1 1\nLookAt"), std::string::npos);
        const float fov = numbers_after(text, "\"float fov\"").at(0);
        EXPECT_EQ(numbers_after(text, "\"integer xresolution\"").at(0), float(view.width));
        EXPECT_EQ(numbers_after(text, "\"integer yresolution\"").at(0), float(view.height));
        for (const glm::vec2 px : {glm::vec2(0, 0), glm::vec2(200, 0), glm::vec2(0, 300), glm::vec2(200, 300),
                                   glm::vec2(100, 150), glm::vec2(37, 201)}) {
          const Ray r = camera.generate(px.x, px.y);
          const glm::vec3 d = pbrt_ray(look, fov, view.width, view.height, px.x, px.y);
          EXPECT_NEAR(glm::length(d - r.d), 0, 2e-5f) << px.x << "," << px.y;
          EXPECT_NEAR(glm::length(glm::vec3(look[0], look[1], look[2]) - r.o), 0, 1e-4f * glm::length(r.o));
        }
        // LEDs: every selected one, where the renderer puts it, as bright.
        std::vector<SphereLight> written;
        for (std::size_t at = text.find("AreaLightSource"); at != std::string::npos;
             at = text.find("AreaLightSource", at + 1)) {
          const std::vector<float> L = numbers_after(text, "\"rgb L\"", at);
          const std::vector<float> t = numbers_after(text, "Translate", at);
          const std::vector<float> r = numbers_after(text, "\"float radius\"", at);
          ASSERT_EQ(L.size(), 3u);
          ASSERT_EQ(t.size(), 3u);
          written.push_back({{t[0], t[1], t[2]}, r.at(0), {L[0], L[1], L[2]}});
        }
        ASSERT_EQ(written.size(), leds.size());
        EXPECT_EQ(written.size(), std::string(lights) == "all" ? dome25().leds.size() : 3u);
        for (std::size_t i = 0; i < leds.size(); ++i) {
          EXPECT_EQ(written[i].centre, leds[i].centre) << "LED " << i;
          EXPECT_EQ(written[i].radius, leds[i].radius);
          EXPECT_EQ(written[i].radiance, leds[i].radiance);
        }
        // The card: the backdrop's plane, extent x the feather's larger side.
        const std::vector<float> card = numbers_after(text, v4 ? "\"point3 P\"" : "\"point P\"");
        ASSERT_EQ(card.size(), 12u);
        const float half = 0.5f * BackdropSpec{}.extent * std::max(fb.size().x, fb.size().y);
        for (int k = 0; k < 4; ++k) {
          EXPECT_EQ(card[3 * k + 2], scene.backdrop_z());
          EXPECT_NEAR(std::fabs(card[3 * k] - fb.centre().x), half, 1e-5f * half);
          EXPECT_NEAR(std::fabs(card[3 * k + 1] - fb.centre().y), half, 1e-5f * half);
        }
        // Material: plumage's sigma_a and betas, alpha with pbrt's sign, depth.
        const std::vector<float> sigma = numbers_after(text, "\"rgb sigma_a\"");
        ASSERT_EQ(sigma.size(), 3u);
        EXPECT_EQ(glm::vec3(sigma[0], sigma[1], sigma[2]), material.sigma_a);
        EXPECT_EQ(numbers_after(text, "\"float alpha\"").at(0), -3.0f);
        EXPECT_EQ(numbers_after(text, "\"float beta_m\"").at(0), 0.25f);
        EXPECT_EQ(numbers_after(text, "\"float beta_n\"").at(0), material.beta_n);
        EXPECT_EQ(numbers_after(text, "\"float eta\"").at(0), material.eta);
        EXPECT_EQ(numbers_after(text, "\"integer maxdepth\"").at(0), 7.0f);
        // Barbs: ray-facing at W; substructure says it is exported as hair.
        std::size_t at = 0;
        for (const Curve& c : feather.curves) {
          if (c.kind != CurveKind::Barb) continue;
          at = text.find("\"flat\"", at + 1);
          ASSERT_NE(at, std::string::npos);
          EXPECT_EQ(numbers_after(text, "\"float width0\"", at).at(0), feather.substructure(c.side).ribbon_width);
          EXPECT_EQ(numbers_after(text, "\"float width1\"", at).at(0), feather.substructure(c.side).ribbon_width);
        }
        EXPECT_EQ(text.find("\"ribbon\""), std::string::npos);
        EXPECT_EQ(text.find("no counterpart") != std::string::npos, mode == ShadingMode::Substructure);
      }

      // Mitsuba: the same camera rays, LEDs, material and a depth one higher.
      const std::string xml = format_mitsuba_scene(feather, es, "f.txt");
      EXPECT_NE(xml.find("<integer name=\"max_depth\" value=\"8\"/>"), std::string::npos);
      EXPECT_NE(xml.find("<float name=\"scale_tilt\" value=\"-3\"/>"), std::string::npos);
      for (const glm::vec2 px : {glm::vec2(0, 0), glm::vec2(200, 300), glm::vec2(37, 201)}) {
        const Ray r = camera.generate(px.x, px.y);
        EXPECT_NEAR(glm::length(mitsuba_ray(es.camera, es.width, es.height, px.x, px.y) - r.d), 0, 2e-5f);
      }
      std::size_t spheres = 0;
      for (std::size_t at = xml.find("type=\"sphere\""); at != std::string::npos; at = xml.find("type=\"sphere\"", at + 1))
        ++spheres;
      EXPECT_EQ(spheres, leds.size());
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryPreset, ExportSceneTest, ::testing::ValuesIn(list_presets()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

TEST(ExportScene, TwoRadiusWidthWhenTheVaneHasNoRibbonWidth) {
  Feather feather = build_feather(load_preset("rock-dove-wing"), 1);
  feather.left.ribbon_width = feather.right.ribbon_width = 0;  // `--ribbon-width 0`
  SceneOptions so;
  const ExportScene es = export_scene(feather, dome25(), ViewSpec{}, so);
  const Scene scene(feather, so);
  float widest = 0;
  for (const Curve& c : feather.curves)
    if (c.kind != CurveKind::Shaft)  // barbs and down barbs (the rock dove's afterfeather)
      for (std::size_t i = 0; i < c.points.size(); ++i) {
        EXPECT_EQ(render_radii(feather, c)[i], c.points[i].radius);
        widest = std::max(widest, c.points[i].radius);
      }
  EXPECT_EQ(widest, scene.max_barb_radius());
  EXPECT_FALSE(es.card) << "no backdrop asked for";
}

TEST(ExportScene, RejectsWhatItCannotCarry) {
  const Feather feather = build_feather(load_preset("rock-dove-wing"), 1);
  ViewSpec view;
  view.directional.push_back({});
  EXPECT_THROW(export_scene(feather, dome25(), view, {}), Error);
  view = ViewSpec{};
  view.camera.projection = Projection::Orthographic;
  EXPECT_THROW(export_scene(feather, dome25(), view, {}), Error);
  view = ViewSpec{};
  view.lights = "26";
  EXPECT_THROW(export_scene(feather, dome25(), view, {}), Error);
  view = ViewSpec{};
  view.hair.beta_m = 2;
  EXPECT_THROW(export_scene(feather, dome25(), view, {}), Error);
}

}  // namespace
