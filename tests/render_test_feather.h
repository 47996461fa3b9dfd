#pragma once
// A small feather built in code for renderer tests and benchmarks (until the
// generator's presets are available): a tapering shaft along +Y and two vanes of
// gently cupped barbs leaving it at 45 degrees toward the tip.
#include <cmath>

#include "plumage/common/bounds.h"
#include "plumage/common/feather.h"
#include "plumage/common/image.h"
#include "plumage/renderer/fibre_material.h"
#include "plumage/renderer/light_set.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/scene.h"

namespace plumage::test {

// Mean of one channel over a rendered image.
inline double mean_channel(const Image& img, int c) {
  double s = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) s += img.at(x, y)[c];
  return s / (double(img.width) * img.height);
}

// A grey sky (0.4) and one lamp above and beside the feather: light from every
// side, with a highlight and shadows.
inline LightSet grey_sky_and_lamp(const Bounds3f& feather_bounds) {
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(0.4f)));
  lights.add(SphereLight{feather_bounds.centre() + glm::vec3(20, 10, 60), 4.0f, glm::vec3(200.0f)});
  return lights;
}

inline Feather make_test_feather(float length = 60.0f, float barb_spacing = 0.5f, float barb_radius = 0.05f) {
  Feather f;
  f.provenance.source = "test:render_test_feather";
  f.albedo.color = {0.55f, 0.45f, 0.35f};
  Curve shaft;
  shaft.kind = CurveKind::Shaft;
  for (int i = 0; i < 8; ++i) {
    const float s = float(i) / 7.0f;
    shaft.points.push_back({{0.0f, s * length, 0.0f}, 0.6f * (1.0f - s) + 0.1f * s, {0, 0, 1}});
  }
  f.curves.push_back(shaft);
  const float pi = 3.14159265f;
  for (float y = 0.1f * length; y < 0.95f * length; y += barb_spacing) {
    const float s = (y - 0.1f * length) / (0.85f * length);
    const float barb_len = 0.25f * length * std::sin(pi * (0.15f + 0.85f * s));
    for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
      const float sx = side == VaneSide::Left ? -1.0f : 1.0f;
      Curve b;
      b.kind = CurveKind::Barb;
      b.side = side;
      b.root = y / length;
      for (int k = 0; k < 5; ++k) {
        const float t = float(k) / 4.0f;
        const float d = t * barb_len;
        // Cupped vane: the barb dips below the shaft plane toward its tip.
        const glm::vec3 p{sx * d * 0.7071f, y + d * 0.7071f, -0.04f * d * d / std::fmax(barb_len, 1e-3f)};
        b.points.push_back({p, barb_radius * (1.0f - 0.5f * t), {0, 0, 1}});
      }
      f.curves.push_back(b);
    }
  }
  return f;
}

// One straight curve of `kind` along +X through `centre`, with constant radius.
inline Curve straight_curve(CurveKind kind, const glm::vec3& centre, float half_length, float radius) {
  Curve c;
  c.kind = kind;
  c.side = kind == CurveKind::Barb ? VaneSide::Right : VaneSide::None;
  for (int i = 0; i < 4; ++i) {
    const float x = -half_length + 2.0f * half_length * float(i) / 3.0f;
    c.points.push_back({centre + glm::vec3(x, 0, 0), radius, {0, 0, 1}});
  }
  return c;
}

// make_test_feather(30, 0.8, 0.06) on a light card (0.8) under grey_sky_and_lamp,
// in hair mode with the default fibre: what a render of the test feather needs.
struct LitTestFeather {
  Scene scene;
  LightSet lights;
  FibreMaterial material{HairParams{}};
  PathIntegrator integrator;
  LitTestFeather()
      : scene(make_test_feather(30.0f, 0.8f, 0.06f), SceneOptions{ShadingMode::Hair, {true, glm::vec3(0.8f)}}),
        lights(grey_sky_and_lamp(scene.feather_bounds())),
        integrator(scene, lights, material, IntegratorSettings{}) {}
};

}  // namespace plumage::test
