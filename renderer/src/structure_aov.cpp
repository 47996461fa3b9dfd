#include "plumage/renderer/structure_aov.h"

#include <tbb/parallel_for.h>

#include "plumage/common/error.h"

namespace plumage {

glm::vec3 structure_colour(Structure s) {
  switch (s) {
    case Structure::Ramus: return {1.0f, 0.45f, 0.05f};
    case Structure::Distal: return {0.1f, 0.3f, 1.0f};
    case Structure::Proximal: return {0.1f, 0.85f, 0.2f};
    case Structure::Empty: break;
  }
  return glm::vec3(0.12f);
}

Image render_structure_aov(const Scene& scene, const Camera& camera, int n) {
  if (scene.options().mode == ShadingMode::Hair)
    throw Error("--aov structure shows rami and barbules: use it with --shading substructure or explicit");
  if (n < 1) throw Error("structure AOV: at least one ray per pixel");
  Image img(camera.width(), camera.height(), 3);
  tbb::parallel_for(0, camera.height(), [&](int y) {
    for (int x = 0; x < camera.width(); ++x) {
      glm::vec3 sum(0);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Ray ray = camera.generate(float(x) + (float(i) + 0.5f) / float(n), float(y) + (float(j) + 0.5f) / float(n));
          SurfaceHit hit;
          // Gaps kept: the AOV shows where the ribbon is empty, not what lies behind it.
          if (!scene.intersect(ray, hit, true) || hit.kind == HitKind::Backdrop) sum += kBackgroundColour;
          else if (hit.kind == HitKind::Shaft) sum += kShaftColour;
          else if (scene.options().mode == ShadingMode::Explicit)
            sum += structure_colour(scene.explicit_fibre(hit).structure);
          else sum += structure_colour(scene.structure_at(hit).hit.structure);
        }
      img.set_rgb(x, y, sum / float(n * n));
    }
  });
  return img;
}

}  // namespace plumage
