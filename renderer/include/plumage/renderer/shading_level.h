#pragma once
// `--shading auto`: each feather shaded at the level its pixel footprint needs
// (docs/substructure.md, "Shading level by footprint"). The explicit-reference
// study there says where each mode is accurate: where a pixel is smaller than a
// barbule period it shows a ramus, a barbule or a gap, which substructure shading
// (G_b) tells apart and a far-field table, a mean over many periods, cannot; where
// a pixel covers several periods the far-field table is the closest mode (its
// model error 2-6x below substructure's in the study's full view) and the least
// noisy. So a feather is shaded in substructure mode when the smallest pixel
// footprint over it is below its typical barbule period, in farfield mode otherwise.
#include "plumage/common/bounds.h"
#include "plumage/common/feather.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/shading_mode.h"

namespace plumage {

// The feather's typical barbule period (mm): the median over its barbs of the
// barb's length (its control polygon's) over its vane's barbules per side N, as
// far-field mode's barb classes count it; 0 for a feather without barbules.
float barbule_period(const Feather& feather);

// Substructure when `footprint` (mm per pixel) is below `period` (mm), farfield
// otherwise; substructure for a feather without barbules (period 0: there is no
// pattern for a table to average, and no table to fit).
ShadingMode shading_for_footprint(float footprint, float period);

// The level for `feather` placed in the world by a similarity of scale `scale`,
// its world box `box`, seen by `camera`.
ShadingMode shading_by_footprint(const Feather& feather, float scale, const Bounds3f& box, const Camera& camera);

}  // namespace plumage
