#pragma once
// Laying a built feather along a measured shaft. The builder's shaft is a
// circular arc; a photographed rachis may curve one way near the calamus and the
// other near the tip. The analysis measures each vane's width across its own
// shaft (it unrolls the photo along it), so the built vanes, which stand across the
// arc the same way, are carried onto the measured shaft point by point: a point
// at arc-length fraction u along the built shaft and lateral offset d from it
// goes to the measured shaft's point at u, d along its normal there.
#include "plumage/common/bspline.h"
#include "plumage/common/feather.h"

namespace plumage {

// Moves every control point of `feather` (and turns its normal in the plane) from
// the frame of its own shaft curve to that of `shaft_mm` (calamus at t = 0, tip at
// t = 1, feather XY millimetres). Z is kept. Points beyond either end of the shaft
// continue along the end tangents. Throws plumage::Error when the feather has no
// shaft curve or either shaft has no length.
void lay_along_shaft(Feather& feather, const BSpline2& shaft_mm);

}  // namespace plumage
