#pragma once
// The structure AOV (`plumage render --aov structure`): what the first surface
// along each camera ray is, ramus, distal or proximal barbule or a gap in a barb's
// ribbon, as flat colours, so the geometry of G_b can be checked by eye against
// the paper's Fig. 3 and Fig. 6 (Baron et al. 2021).
#include "plumage/common/image.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/scene.h"

namespace plumage {

// Ramus orange, distal barbule blue, proximal barbule green, gap dark grey,
// shaft white, backdrop and background black.
glm::vec3 structure_colour(Structure s);
inline const glm::vec3 kShaftColour{1.0f}, kBackgroundColour{0.0f};

// n x n stratified rays per pixel, their colours averaged (edges antialiased).
// Throws plumage::Error unless the scene is in substructure mode or n < 1.
Image render_structure_aov(const Scene& scene, const Camera& camera, int n = 3);

}  // namespace plumage
