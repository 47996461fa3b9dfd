#pragma once
// Leaves out of the BVH the curves that can neither be seen by the camera nor
// shadow anything it sees (docs/skip-work.md states the rule). Off by default:
// light a culled curve would have bounced into the view is lost, so it is an
// approximation for scenes lit mostly directly.
#include <span>
#include <vector>

#include "plumage/renderer/camera.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/light_set.h"
#include "plumage/renderer/scene.h"

namespace plumage {

// The camera's view of the slab floor_z <= z <= feather top, as an XY rectangle
// grown by `margin` (fraction of its size); a curve is kept when its box reaches
// that rectangle grown further by its shadow reach: (height above floor) x the
// largest horizontal-per-vertical run of a shadow ray toward any light that is on.
// Keeps everything when the bound does not exist (an environment, a light at or
// below the feather's top, a camera inside or below the slab).
CurveKeep view_cull(const Camera& camera, const LightSet& lights, const Bounds3f& feather_bounds, float floor_z,
                    float margin = 0.1f);

// Applies a SceneOptions::cull (empty: keep everything) to the curves' boxes: per
// curve, 1 when it goes into the BVH.
std::vector<char> keep_curves(const SceneCull& cull, std::span<const Bounds3f> curve_boxes,
                              const Bounds3f& feather_bounds, float floor_z);

// SceneOptions::cull for the view render_view() will draw: the same camera and
// lights (view_lights(); an environment or a directional light keeps every curve).
SceneCull view_cull_for(const ViewSpec& view, const DomeRig& rig, float margin = 0.1f);

}  // namespace plumage
