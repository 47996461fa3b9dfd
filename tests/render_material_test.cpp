// Fibre absorption from the feather's albedo (constant or texture through the rect
// mapping), and the integrator's guard against non-finite samples.
#include <unistd.h>
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>
#include <filesystem>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/common/stats.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/ribbon_layers.h"
#include "plumage/renderer/scene.h"
#include "one_barb.h"
#include "render_test_feather.h"

using namespace plumage;
using test::mean_channel;
namespace fs = std::filesystem;

TEST(RenderMaterial, TextureMapsThroughTheRectTipUp) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_render_material_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // 2x2 texture: top row red | green, bottom row blue | white (linear EXR).
  Image tex(2, 2, 3);
  tex.set_rgb(0, 0, {1, 0, 0});
  tex.set_rgb(1, 0, {0, 1, 0});
  tex.set_rgb(0, 1, {0, 0, 1});
  tex.set_rgb(1, 1, {1, 1, 1});
  write_image(dir / "albedo.exr", tex);
  Albedo a;
  a.texture = "albedo.exr";  // relative to the curve file's folder
  a.rect_min = {-10, 0};
  a.rect_max = {10, 60};
  const AlbedoMap map(a, dir);
  ASSERT_TRUE(map.textured());
  const float eps = 1e-4f;
  EXPECT_LT(glm::length(map.at({-10, 60}) - glm::vec3(1, 0, 0)), eps);  // top-left: x min, y max (tip)
  EXPECT_LT(glm::length(map.at({10, 60}) - glm::vec3(0, 1, 0)), eps);
  EXPECT_LT(glm::length(map.at({-10, 0}) - glm::vec3(0, 0, 1)), eps);
  EXPECT_LT(glm::length(map.at({10, 0}) - glm::vec3(1, 1, 1)), eps);
  EXPECT_LT(glm::length(map.at({-50, 100}) - glm::vec3(1, 0, 0)), eps);  // clamped outside
  EXPECT_LT(glm::length(map.at({0, 30}) - glm::vec3(0.5f, 0.5f, 0.5f)), eps);  // bilinear centre

  // Darker albedo -> more absorption, through the material.
  HairParams hp;
  const FibreMaterial m(hp, map);
  const glm::vec3 s_white = m.at({10, 0, 0}).sigma_a, s_red = m.at({-10, 60, 0}).sigma_a;
  EXPECT_LT(s_white.y, s_red.y);
  EXPECT_NEAR(s_red.x, s_white.x, 1e-4f);

  Albedo missing = a;
  missing.texture = "no_such_albedo.png";
  try {
    AlbedoMap bad(missing, dir);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(e.where().file.find("no_such_albedo.png"), std::string::npos);
  }
  Albedo empty_rect = a;
  empty_rect.rect_max = empty_rect.rect_min;
  EXPECT_THROW(AlbedoMap(empty_rect, dir), Error);
}

TEST(RenderMaterial, NonFiniteSamplesAreCountedAndDropped) {
  SceneOptions so;
  so.backdrop.enabled = true;
  const Scene scene(test::make_test_feather(20.0f, 1.0f, 0.05f), so);
  LightSet lights;
  lights.add(SphereLight{{0, 10, 30}, 2.0f, glm::vec3(std::numeric_limits<float>::infinity())});
  const FibreMaterial material(HairParams{}, AlbedoMap(glm::vec3(0.5f)));
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{});
  const Camera camera(CameraSpec{}, 8, 8, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 2;
  rs.progress = false;
  stats_reset();
  const Image img = render(camera, integrator, rs).developed(0);
  for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(stats_snapshot()["Renderer/NaN or Inf samples dropped"], 0.0);
}

namespace {

// One layer of touching parallel barbs over a white card under a uniform sky (the
// diffuse light an albedo photo is taken in), seen from above: the layer's colour
// over the bare card's, per channel.
glm::vec3 layer_over_card(AlbedoMapping mapping, const glm::vec3& albedo) {
  Feather f;
  const float r = 0.1f;
  for (int k = -20; k <= 20; ++k) f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, 2 * r * k, 0}, 8, r));
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f), 4.0f};
  const Scene scene(f, so);
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  const FibreMaterial material(HairParams{}, AlbedoMap(albedo), mapping);
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{});
  RenderSettings rs;
  rs.spp = 64;
  rs.progress = false;
  glm::vec3 out;
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.ortho_height = 2.0f;
  cs.up = {0, 1, 0};
  cs.position = {0, 0, 5};
  cs.look_at = {0, 0, 0};
  const Image layer = render(Camera(cs, 16, 16, scene.feather_bounds()), integrator, rs).developed(0);
  cs.position = {12, 12, 5};  // bare card beside the layer
  cs.look_at = {12, 12, 0};
  const Image card = render(Camera(cs, 16, 16, scene.feather_bounds()), integrator, rs).developed(0);
  for (int c = 0; c < 3; ++c) out[c] = float(mean_channel(layer, c) / mean_channel(card, c));
  return out;
}

}  // namespace

TEST(RenderMaterial, OneLayerOfFibresOverACardShowsItsAlbedo) {
  // The default mapping is calibrated on exactly this: a light pink vane photographed
  // on white paper must render pink, not as a grey haze. Within 15 % per channel
  // (Fresnel reflection and the fibres' rounded edges are not in the calibration).
  const glm::vec3 pink(0.95f, 0.5f, 0.55f), brown(0.35f, 0.22f, 0.12f);
  for (const glm::vec3& a : {pink, brown}) {
    const glm::vec3 seen = layer_over_card(AlbedoMapping::Layer, a);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(seen[c], a[c], 0.15f * a[c]) << "albedo channel " << c << " = " << a[c];
  }
  // Chiang et al.'s mapping, made for dense hair, leaves a single layer almost clear.
  const glm::vec3 chiang = layer_over_card(AlbedoMapping::Chiang2016, pink);
  EXPECT_GT(chiang.y, 0.8f);
}

namespace {

// A closed vane over a card (white unless given) under a uniform sky or the dome, seen from above: parallel
// straight barbs 0.6 mm wide (W) whose ribbons overlap `overlap` times the gap
// between them (1.3: one ribbon deep in 70 % of the vane, two in 30 %, as a photo
// feather's closed vane; 2: two deep everywhere), barbules enough to cover every
// ribbon (as close_vane makes them), and a uniform albedo *texture* (the photo's
// area mean, which the mapping divides among the layers). The vane's colour over
// the bare card's, per channel.
enum class Correction { None, PhotoCard };  // ViewSpec::photo_card unset or set to the card
enum class Light { Sky, Dome };             // a uniform sky, or the 25-LED dome with every LED on
glm::vec3 closed_vane_over_card(ShadingMode mode, const glm::vec3& albedo, float overlap, float card_albedo = 0.8f,
                                Correction correction = Correction::None, Light light = Light::Sky,
                                float medulla_sigma_s = 0.0f) {
  const float W = 0.6f, gap = W / overlap;
  Feather f;
  for (int k = -40; k <= 40; ++k) f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, gap * k, 0}, 9, 0.03f));
  // r_r 30 um, r_b 6 um, theta_b 45, phi_b 10, hooked 0.3: a photo feather's (docs/analysis.md).
  SubstructureParams s = test::substructure_params(0, 45, 0.03, 0.006, W, 10, 0.3);
  // The barbs are 6 mm long; N closes a 12 mm barb (as a photo feather's barb half
  // its vane's longest). At N closing the 6 mm barb itself, green comes out 6 % light.
  s.barbules_per_side = closing_barbule_count(12.0, s);
  f.left = f.right = s;
  const fs::path tex = fs::temp_directory_path() / ("plumage_vane_albedo_" + std::to_string(::getpid()) + ".png");
  Image t(4, 4, 3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) t.set_rgb(x, y, albedo);
  write_image(tex, t);
  f.albedo.texture = tex.string();
  f.albedo.rect_min = {-20, -20};
  f.albedo.rect_max = {20, 20};
  SceneOptions so;
  so.mode = mode;
  so.backdrop = {true, glm::vec3(card_albedo), 40.0f, BackdropPlacement::Vane};
  const Scene scene(f, so);
  ViewSpec v;
  if (correction == Correction::PhotoCard) v.photo_card = so.backdrop.albedo;
  if (medulla_sigma_s > 0.0f) {  // the photo inversion's fibre (card_response.h)
    v.hair.medulla_ratio = kPhotoMedullaRatio;
    v.hair.medulla_sigma_s = glm::vec3(medulla_sigma_s);
  }
  v.width = v.height = 32;
  v.spp = 64;
  if (light == Light::Sky) {
    v.lights = "none";
    v.environment = EnvironmentLight(glm::vec3(1.0f));
  }
  v.camera.projection = Projection::Orthographic;
  v.camera.ortho_height = 3.0f;
  v.camera.up = {0, 1, 0};
  v.camera.position = {0, 0, 5};
  v.camera.look_at = {0, 0, 0};
  static const DomeRig dome = read_dome_rig(std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json"), none;
  const DomeRig& rig = light == Light::Dome ? dome : none;
  const Image layer = render_view(scene, rig, v);
  v.camera.position = {15, 15, 5};  // bare card beside the vane
  v.camera.look_at = {15, 15, 0};
  const Image card = render_view(scene, rig, v);
  fs::remove(tex);
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) out[c] = float(mean_channel(layer, c) / mean_channel(card, c));
  return out;
}

}  // namespace

TEST(RenderMaterial, PhotoAlbedoMappingInvertsTheStackOfRibbons) {
  // Each of k layers returns t = A^(1/k); a ribbon a fraction c fibre returns
  // 1 - c (1 - f); one layer fully covered is the identity.
  const glm::vec3 a(0.9f, 0.5f, 0.1f);
  for (int k : {1, 2, 3, 7})
    for (float c : {1.0f, 0.8f, 0.5f}) {
      const glm::vec3 f = photo_albedo_to_fibre(a, c, k);
      const glm::vec3 t = glm::vec3(1.0f) - c * (glm::vec3(1.0f) - f);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(std::pow(t[i], float(k)), a[i], 1e-5f) << k << " " << c;
    }
  EXPECT_EQ(photo_albedo_to_fibre(a, 1.0f, 1), a);
  // Out-of-range input: A clamped to [0, 1], a point no ribbon covers (k <= 0) as one layer.
  EXPECT_EQ(photo_albedo_to_fibre(glm::vec3(2.0f, -1.0f, 0.5f), 1.0f, 1), glm::vec3(1.0f, 0.0f, 0.5f));
  EXPECT_EQ(photo_albedo_to_fibre(a, 1.0f, 0), a);
  // Darker than the gaps alone allow: f <= 0, which sigma_a_from_* clamps.
  EXPECT_LE(photo_albedo_to_fibre(glm::vec3(0.2f), 0.5f, 1).x, 0.0f);
}

TEST(RenderMaterial, ClosedVaneOverACardShowsThePhotoAlbedo) {
  // The area mean over a closed vane one or two ribbons deep is the texture's
  // albedo. Substructure mode: a light (photo-pink) albedo within 5 % per channel
  // (measured at most 2.7 %), a dark one within 0.08 absolute (measured at most
  // 0.071 with BCSDF sampling alone under the constant sky, 0.063 with light
  // sampling as well: the same mean, other noise): without ViewSpec::photo_card the
  // mapping leaves out what the vane sends back without reaching the card (the R
  // lobe, card_response.h: reflect/c + leak ≈ 0.05 over a card of albedo 0.8),
  // which only a dark albedo notices. Hair mode at the photo
  // feathers' overlap 1.3: within 10 % (measured at most 7.1 % darker: its
  // ray-facing ribbons darken a stack; docs/hair-bcsdf.md). Without dividing the albedo among the
  // layers the two-deep vane's pink green comes out at about 0.32 instead of 0.53.
  const glm::vec3 pink(0.98f, 0.53f, 0.556f), brown(0.35f, 0.22f, 0.12f);
  for (float overlap : {1.3f, 2.0f}) {
    const glm::vec3 light = closed_vane_over_card(ShadingMode::Substructure, pink, overlap);
    const glm::vec3 dark = closed_vane_over_card(ShadingMode::Substructure, brown, overlap);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(light[c], pink[c], 0.05f * pink[c]) << "overlap " << overlap << ", channel " << c;
      EXPECT_NEAR(dark[c], brown[c], 0.08f) << "overlap " << overlap << ", channel " << c;
    }
  }
  const glm::vec3 hair = closed_vane_over_card(ShadingMode::Hair, pink, 1.3f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(hair[c], pink[c], 0.10f * pink[c]) << "hair, channel " << c;
}

TEST(RenderMaterial, CardResponseModelsAClosedVane) {
  // The table of card_response.h against renders of the closed vane above under the
  // dome, on grey and dark cards and at albedos between the table's nodes: with the
  // correction (ViewSpec::photo_card) the vane looks its albedo times the card within
  // 0.01 + 3 % (the table's fit is within 0.0015 of its renders; the rest is the
  // interpolation and the noise); without it, a dark brown vane on a mid-grey card
  // comes out far too light (measured: green 0.28 for 0.15 in hair mode), which is
  // what the correction is for. A vane cannot look darker than black fibres over the
  // card (0.10 of a 0.25 card in hair mode, 0.15 in substructure mode), so the
  // albedos are ones the cards allow.
  for (ShadingMode mode : {ShadingMode::Hair, ShadingMode::Substructure})
    for (float card : {0.6f, 0.3f})
      for (float a : {0.17f, 0.45f}) {
        const float seen = closed_vane_over_card(mode, glm::vec3(a), 1.3f, card, Correction::PhotoCard, Light::Dome).y;
        EXPECT_NEAR(seen, a, 0.01f + 0.03f * a) << to_string(mode) << ", card " << card << ", albedo " << a;
      }
  const float uncorrected = closed_vane_over_card(ShadingMode::Hair, glm::vec3(0.15f), 1.3f, 0.25f, Correction::None, Light::Dome).y;
  EXPECT_GT(uncorrected, 0.15f + 0.01f + 0.03f * 0.15f);
  // The inversion itself: what black fibres show maps to 0, a node's own seen / card
  // to its albedo (clear fibres), out-of-range and non-finite input stays in [0, 1],
  // a white card leaves a light albedo nearly as it is; a texel paler than white
  // clear fibres get a medulla, more for a paler one, up to the table's last row.
  for (ShadingMode mode : {ShadingMode::Hair, ShadingMode::Substructure}) {
    const CardResponse& r = card_response(mode);
    EXPECT_EQ(r.rows[0].medulla_sigma_s, 0.0f);
    EXPECT_EQ(r.rows[0].nodes.front().albedo, 0.0f);
    EXPECT_EQ(r.rows[0].nodes.back().albedo, 1.0f);
    for (float c : {1.0f, 0.5f, 0.25f, 0.1f, 0.02f}) {
      const CardCorrection correct(r, glm::vec3(c));
      EXPECT_NEAR(correct(glm::vec3(r.seen(0, 0, c))).albedo.x, 0.0f, 1e-6f) << c;
      const float white = r.seen(0, CardResponse::kNodes - 1, c);
      EXPECT_NEAR(correct(glm::vec3(white)).albedo.x, 1.0f, 1e-4f) << c;
      EXPECT_EQ(correct(glm::vec3(white)).medulla_sigma_s, 0.0f) << c;
      EXPECT_EQ(correct(glm::vec3(white * 1.05f)).medulla_sigma_s, 0.0f) << c;  // within the margin: a clear fibre
      const FibreColour paler = correct(glm::vec3(white * 1.15f)), palest = correct(glm::vec3(white * 100.0f));
      bool medulla_shows_more = false;  // on a white card a substructure vane's medulla may not
      for (int j = 1; j < CardResponse::kRows; ++j) medulla_shows_more |= r.seen(j, CardResponse::kNodes - 1, c) > white;
      if (medulla_shows_more) {
        EXPECT_GT(palest.medulla_sigma_s, 0.0f) << to_string(mode) << ", card " << c;
        EXPECT_GE(palest.medulla_sigma_s, paler.medulla_sigma_s) << to_string(mode) << ", card " << c;
      }
      if (r.seen(CardResponse::kRows - 1, CardResponse::kNodes - 1, c) > 1.15f * white) {
        EXPECT_GT(paler.medulla_sigma_s, 0.0f) << to_string(mode) << ", card " << c;
      }
      EXPECT_TRUE(palest.clamped);
      EXPECT_FALSE(correct(glm::vec3(white * 0.9f)).clamped);
      for (int i = 1; i < CardResponse::kNodes; ++i) {
        // Every node sees more than the one before (the inversion needs it), and the
        // inversion returns a node's albedo from its own seen / card.
        EXPECT_GT(r.seen(0, i, c), r.seen(0, i - 1, c)) << to_string(mode) << " node " << i << ", card " << c;
        EXPECT_NEAR(correct(glm::vec3(r.seen(0, i, c))).albedo.x, r.rows[0].nodes[i].albedo, 1e-4f);
      }
      // On each medulla row, white fibres show more than black ones, so a channel can be inverted.
      for (int j = 1; j < CardResponse::kRows; ++j)
        EXPECT_GT(r.seen(j, CardResponse::kNodes - 1, c), r.seen(j, 0, c)) << to_string(mode) << " row " << j;
    }
    const glm::vec3 odd = albedo_over_card(glm::vec3(std::nanf(""), 50.0f, -1.0f), glm::vec3(0.0f, std::nanf(""), 1.0f), r);
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(odd[i] >= 0.0f && odd[i] <= 1.0f) << i;
    EXPECT_NEAR(albedo_over_card(glm::vec3(0.5f), glm::vec3(0.9f), r).x, 0.5f, 0.1f);
  }
  // The hue stays: a dark brown whose blue alone lies under what black fibres show
  // over a grey card keeps its channel ratios (per channel it would turn yellow).
  const CardResponse& r = card_response(ShadingMode::Hair);
  const glm::vec3 brown(0.30f, 0.2f, 0.1f), out = albedo_over_card(brown, glm::vec3(0.25f), r);
  EXPECT_GT(out.z, 0.0f);
  EXPECT_NEAR(out.x / out.z, brown.x / brown.z, 1e-4f);
  EXPECT_NEAR(out.y / out.z, brown.y / brown.z, 1e-4f);
}

TEST(RenderMaterial, CardResponseFit) {
  // The fit behind card_response.h's table (scripts/fit_card_response.sh): the
  // closed vane over cards 0.9, 0.5, 0.25 and 0.1 (and, for the rows with a medulla,
  // the black card 0.02 where their light matters most) at each of the table's
  // albedos and medulla scatterings, uncorrected, seen / card = through + reflect / c
  // + bounce c by least squares. Run only with PLUMAGE_CARD_RESPONSE_FIT set to the
  // file that gets the table; the fit must reproduce each of its renders within
  // 0.003 of seen / card (clear fibres) or 0.004 + 2 % of seen (a medulla).
  const char* path = std::getenv("PLUMAGE_CARD_RESPONSE_FIT");
  if (!path) GTEST_SKIP() << "set PLUMAGE_CARD_RESPONSE_FIT=FILE to fit the table (scripts/fit_card_response.sh)";
  std::FILE* out = std::fopen(path, "w");
  ASSERT_NE(out, nullptr) << path;
  const std::vector<float> clear_cards = {0.9f, 0.5f, 0.25f, 0.1f}, medulla_cards = {0.9f, 0.5f, 0.25f, 0.1f, 0.02f};
  for (ShadingMode mode : {ShadingMode::Hair, ShadingMode::Substructure}) {
    std::fprintf(out, "// %s\n", to_string(mode));
    for (const CardResponseRow& row : card_response(mode).rows) {
      std::fprintf(out, "    {%.2ff, {{\n", row.medulla_sigma_s);
      const std::vector<float>& cards = row.medulla_sigma_s > 0.0f ? medulla_cards : clear_cards;
      for (const CardResponseNode& node : row.nodes) {
        // Normal equations of the three-term fit.
        double m[3][4] = {};
        std::vector<float> seen(cards.size());
        for (std::size_t k = 0; k < cards.size(); ++k) {
          const double c = cards[k], x[3] = {1.0, 1.0 / c, c};
          seen[k] = closed_vane_over_card(mode, glm::vec3(node.albedo), 1.3f, cards[k], Correction::None, Light::Dome,
                                          row.medulla_sigma_s).y;
          for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) m[i][j] += x[i] * x[j];
            m[i][3] += x[i] * seen[k];
          }
        }
        for (int i = 0; i < 3; ++i)  // Gauss-Jordan (the matrix is positive definite)
          for (int r = 0; r < 3; ++r) {
            if (r == i) continue;
            const double f = m[r][i] / m[i][i];
            for (int j = 0; j < 4; ++j) m[r][j] -= f * m[i][j];
          }
        const CardResponseNode fit{node.albedo, float(m[0][3] / m[0][0]), float(m[1][3] / m[1][1]),
                                   float(m[2][3] / m[2][2])};
        for (std::size_t k = 0; k < cards.size(); ++k) {
          const float c = cards[k], model = fit.through + fit.reflect / c + fit.bounce * c;
          if (row.medulla_sigma_s > 0.0f)
            EXPECT_NEAR(model * c, seen[k] * c, 0.004f + 0.02f * seen[k] * c)
                << to_string(mode) << ", medulla " << row.medulla_sigma_s << ", albedo " << node.albedo << ", card " << c;
          else
            EXPECT_NEAR(model, seen[k], 0.003f) << to_string(mode) << ", albedo " << node.albedo << ", card " << c;
        }
        std::fprintf(out, "        {%.2ff, %.4ff, %.4ff, %.4ff},\n", fit.albedo, fit.through, fit.reflect, fit.bounce);
      }
      std::fprintf(out, "    }}},\n");
    }
  }
  std::fclose(out);
}

TEST(RenderMaterial, RibbonLayersCountTheBarbsOverAPoint) {
  // Three straight barbs along X at y = 0, 0.4, 0.8 drawn 0.6 mm wide (W): around
  // y = 0.2 and 0.6 two ribbons overlap, at y = 0.0 and 0.8 one lies alone, beyond
  // the ribbons and off the map the count is 1 (nothing to divide among).
  Feather f;
  for (float y : {0.0f, 0.4f, 0.8f}) f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, y, 0}, 3, 0.03f));
  f.right.ribbon_width = 0.6f;
  const RibbonLayers layers(f);
  EXPECT_LE(layers.cell_mm(), 0.25f * 0.3f + 1e-6f);
  EXPECT_EQ(layers.at({0, 0.2f}), 2);
  EXPECT_EQ(layers.at({0.5f, 0.6f}), 2);
  EXPECT_EQ(layers.at({0, -0.05f}), 1);
  EXPECT_EQ(layers.at({0, 0.4f}), 1);  // 0.4 from the neighbours: outside their W/2
  EXPECT_EQ(layers.at({0, 1.5f}), 1);
  EXPECT_EQ(layers.at({100, 100}), 1);
  EXPECT_EQ(layers.at({std::nanf(""), 0}), 1);
  // Narrower ribbons no longer overlap.
  f.right.ribbon_width = 0.3f;
  EXPECT_EQ(RibbonLayers(f).at({0, 0.2f}), 1);
  // Only a textured feather gets the map in a scene (a constant albedo is used as it is).
  f.right.ribbon_width = 0.6f;
  SurfaceHit hit;
  hit.kind = HitKind::Barb;
  hit.p = {0, 0.2f, 0};
  EXPECT_EQ(Scene(f, SceneOptions{}).ribbon_layers(hit), 1);
  f.albedo.texture = "unread.png";
  const Scene textured(f, SceneOptions{});
  EXPECT_EQ(textured.ribbon_layers(hit), 2);
  hit.kind = HitKind::Shaft;
  EXPECT_EQ(textured.ribbon_layers(hit), 1);
}

TEST(RenderMaterial, TheShaftsColourFollowsItsStations) {
  // A white quill below a black rachis: two stations, at a quarter and three
  // quarters of the shaft's length, linear in between. The straight shaft's
  // B-spline (control points at x = -6, -2, 2, 6) runs from x = -2 (its root,
  // t = 0) to 2 (t = 1) at constant speed, so t is the fraction of its length.
  const Curve shaft = test::straight_curve(CurveKind::Shaft, {0, 0, 0}, 6, 0.6f);
  Albedo albedo;
  albedo.shaft = {glm::vec3(1.0f), glm::vec3(0.0f)};
  const AlbedoMap map(albedo, ".", &shaft);
  ASSERT_TRUE(map.has_shaft_colour());
  EXPECT_NEAR(map.shaft_colour(0.0f).x, 1.0f, 1e-5f);
  EXPECT_NEAR(map.shaft_colour(0.125f).x, 1.0f, 1e-5f);
  EXPECT_NEAR(map.shaft_colour(0.375f).x, 0.75f, 1e-5f);
  EXPECT_NEAR(map.shaft_colour(0.5f).x, 0.5f, 1e-5f);
  EXPECT_NEAR(map.shaft_colour(0.875f).x, 0.0f, 1e-5f);
  EXPECT_NEAR(map.shaft_colour(-1.0f).x, 1.0f, 1e-5f) << "beyond the root";
  // Without the curve the stations cannot be placed: their mean.
  EXPECT_NEAR(AlbedoMap(albedo, ".").shaft_colour(0.0f).x, 0.5f, 1e-6f);
  // The material's shaft fibre follows: light at the root, dark at the tip.
  const FibreMaterial m(HairParams{}, AlbedoMap(albedo, ".", &shaft));
  EXPECT_LT(m.at_shaft({-1.8f, 0, 0}, 0.05f).sigma_a.x, m.at_shaft({1.8f, 0, 0}, 0.95f).sigma_a.x);
  // A hit on the shaft says where it lies along it: a ray down onto x = -1 and
  // one onto a point beside the axis at x = 0 meet the tube a quarter and half
  // of the way from the root.
  Feather f;
  f.curves.push_back(shaft);
  const Scene scene(f, SceneOptions{});
  for (const auto& [x, y, t] : {std::tuple{-1.0f, 0.0f, 0.25f}, std::tuple{0.0f, 0.3f, 0.5f}}) {
    Ray ray;
    ray.o = {x, y, 5};
    ray.d = {0, 0, -1};
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(ray, hit)) << x;
    EXPECT_NEAR(scene.curve_parameter(hit), t, 1e-3f) << x;
  }
}

TEST(ShaftColour, StationsAreCentredOnEqualStretches) {
  const std::vector<glm::vec3> three = {glm::vec3(0.0f), glm::vec3(3.0f), glm::vec3(6.0f)};
  EXPECT_EQ(shaft_colour_at(three, 0.0f).x, 0.0f);
  EXPECT_EQ(shaft_colour_at(three, 1.0f / 6.0f).x, 0.0f);
  EXPECT_NEAR(shaft_colour_at(three, 0.5f).x, 3.0f, 1e-5f);
  EXPECT_NEAR(shaft_colour_at(three, 2.0f / 3.0f).x, 4.5f, 1e-5f);
  EXPECT_EQ(shaft_colour_at(three, 1.0f).x, 6.0f);
  EXPECT_EQ(shaft_colour_at({glm::vec3(2.0f)}, 0.7f).x, 2.0f);
  // Extreme fractions stay at the ends and finite.
  for (float f : {-INFINITY, -1e30f, std::nanf(""), 1e30f, INFINITY}) {
    const float v = shaft_colour_at(three, f).x;
    EXPECT_TRUE(v == 0.0f || v == 6.0f) << f << " gave " << v;
  }
}

TEST(RenderMaterial, TheShaftTakesItsOwnColour) {
  // A thick shaft alone over a grey card, its feather textured mid-grey: with
  // Albedo::shaft white it renders light, black dark, and without one as the texture
  // (at_shaft falls back to at). The material says the same fibre by fibre.
  const auto render_shaft = [](std::vector<glm::vec3> shaft) {
    Feather f;
    f.curves.push_back(test::straight_curve(CurveKind::Shaft, {0, 0, 0}, 6, 0.6f));
    const fs::path tex = fs::temp_directory_path() / ("plumage_shaft_albedo_" + std::to_string(::getpid()) + ".png");
    Image t(2, 2, 3);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) t.set_rgb(x, y, glm::vec3(0.3f));
    write_image(tex, t);
    f.albedo.texture = tex.string();
    f.albedo.rect_min = {-20, -20};
    f.albedo.rect_max = {20, 20};
    f.albedo.shaft = shaft;
    const FibreMaterial m(HairParams{}, AlbedoMap(f.albedo, "."));
    if (!shaft.empty()) {
      EXPECT_EQ(m.at_shaft({0, 0, 0}, 0.5f).sigma_a, sigma_a_from_layer_albedo(shaft[0], HairParams{}.eta));
    } else {
      EXPECT_EQ(m.at_shaft({0, 0, 0}, 0.5f).sigma_a, m.at({0, 0, 0}).sigma_a);
    }
    SceneOptions so;
    so.backdrop = {true, glm::vec3(0.5f), 4.0f};
    const Scene scene(f, so);
    ViewSpec v;
    v.width = v.height = 16;
    v.spp = 16;
    v.lights = "none";
    v.environment = EnvironmentLight(glm::vec3(1.0f));
    v.camera.projection = Projection::Orthographic;
    v.camera.ortho_height = 0.8f;  // inside the shaft's 1.2 mm width
    v.camera.up = {1, 0, 0};
    v.camera.position = {0, 0, 5};
    v.camera.look_at = {0, 0, 0};
    const Image img = render_view(scene, DomeRig{}, v);
    fs::remove(tex);
    return mean_channel(img, 1);
  };
  const double white = render_shaft({glm::vec3(1.0f)}), black = render_shaft({glm::vec3(0.0f)}), none = render_shaft({});
  EXPECT_GT(white, 1.5 * none);
  EXPECT_LT(black, 0.8 * none);
}
