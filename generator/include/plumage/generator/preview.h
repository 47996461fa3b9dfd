#pragma once
// A quick orthographic top view of a feather's curves (looking down -Z onto the
// dorsal side, tip up), drawn by a small anti-aliased line rasteriser so a person
// sees the result of `plumage generate` at once, without the renderer: paper
// background, dark shaft, left vane blue, right vane orange, and a 10 mm scale bar
// in the lower left corner.
#include "plumage/common/feather.h"
#include "plumage/common/image.h"

namespace plumage {

struct PreviewOptions {
  int size = 1024;         // pixels along the longer side of the feather's bounds
  bool scale_bar = true;
};

// Colours (linear RGB) the preview uses, exposed for tests and docs.
struct PreviewPalette {
  static constexpr glm::vec3 background{0.80f, 0.77f, 0.70f};
  static constexpr glm::vec3 shaft{0.03f, 0.018f, 0.01f};
  static constexpr glm::vec3 left{0.02f, 0.09f, 0.36f};
  static constexpr glm::vec3 right{0.52f, 0.11f, 0.01f};
};

// RGB image; throws plumage::Error when the feather has no curves or size is
// outside [16, 16384].
Image render_preview(const Feather& feather, const PreviewOptions& options = {});

}  // namespace plumage
