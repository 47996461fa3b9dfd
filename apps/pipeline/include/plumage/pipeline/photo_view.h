#pragma once
// One pose for the photo and its renders: the picked feather cropped from the
// photo with a margin, and an orthographic top view whose pixel grid maps onto
// that crop through the layout's image <-> feather transform, so the photo panel
// and the render panels overlay pixel for pixel (docs/analysis.md, "One pose").
#include <glm/glm.hpp>

#include "plumage/common/image.h"
#include "plumage/layout/layout.h"
#include "plumage/pipeline/fidelity.h"
#include "plumage/renderer/backdrop.h"
#include "plumage/renderer/camera.h"

namespace plumage {

struct PhotoCrop {
  glm::dvec2 origin_px{0};   // photo pixel coordinates of the panels' top-left corner
  double px_per_panel_px = 1;  // photo pixels per panel pixel (both axes)
  int width = 0, height = 0;   // panel size in pixels
  bool operator==(const PhotoCrop&) const = default;  // the same pixel grid
};

// The picked feather's bounding box grown by `margin` (a fraction of its larger
// side, at least 8 photo pixels), kept inside the photo, shown with `size` pixels
// along its longer side. Throws plumage::Error for a size below 16 or a feather
// outside the photo.
PhotoCrop crop_for(const Layout& layout, const FeatherLayout& feather, int size, double margin = 0.06);

// The crop resampled to the panel: each panel pixel the area-weighted mean of the
// photo over its footprint.
Image crop_photo(const Image& photo, const PhotoCrop& crop);

// The pixel grid the renders of `shown` are traced on (docs/analysis.md, "One
// pose"): `shown` itself where a panel pixel is no smaller than a photo pixel;
// otherwise the photo's own pixel grid over the crop (whole photo pixels, its
// origin on the photo's pixel corners), refined by the smallest whole factor that
// gives it at least kMinRenderSide pixels along its longer side, never finer than
// the panel. A feather that spans few photo pixels is then traced at the detail the
// photo holds, and each of its pixels gathers the samples of several panel pixels.
inline constexpr int kMinRenderSide = 160;
PhotoCrop render_grid_for(const PhotoCrop& shown);

// Samples per pixel on `grid`: what `spp` per pixel of `shown` would spend, but at
// most kGridSppFactor times `spp` (the nearest power of two, for the Sobol sampler;
// at least `spp`, at most 4096). A traced pixel is shown over several panel pixels,
// so its noise is theirs: it needs the noise a panel pixel is allowed, not the
// panel's whole budget. With the render denoised (the default) twice the panel's spp
// leaves it σ 0.007-0.010 on the study's sheet feathers, the panel's budget (32-128
// spp there) 0.006 at 1.6-6.5 times the time (docs/perf/p2f.md, "Traced on the
// photo's grid").
inline constexpr int kGridSppFactor = 2;
int render_spp_for(int spp, const PhotoCrop& shown, const PhotoCrop& grid);

// An image traced on `grid` shown on the panel `shown`: each panel pixel the
// area-weighted mean of the render over its footprint (crop_photo's rule); the
// image itself when the grids are the same.
Image show_on_panel(const Image& render, const PhotoCrop& grid, const PhotoCrop& shown);

// The orthographic top view that sees exactly the crop. Throws plumage::Error when
// the layout's transform mirrors the photo (the camera cannot see a mirror image).
CameraSpec crop_camera(const FeatherLayout& feather, const PhotoCrop& crop);

// The photo's background near the picked feather (linear RGB): the per-channel
// median of the photo panel's outermost ring of pixels, counting only those within
// kBackgroundDe (ΔE 2000) of the whole photo's border median, so that neighbouring
// feathers on a sheet do not count; the whole photo's border median when fewer
// than a tenth of the ring (and 8 pixels) qualify. The whole photo's border is the
// analysis's frame (border_frame_px), not its outermost ring, which on a scan is
// often the scanner's bright edge line.
inline constexpr double kBackgroundDe = 15.0;
glm::vec3 background_colour(const Image& photo, const Image& photo_panel);

// The backdrop card of the photo: the background colour as the card's albedo
// (scaled so no channel exceeds 0.9), large enough to fill the crop's whole view.
BackdropSpec photo_backdrop(const glm::vec3& background, const FeatherLayout& feather, const PhotoCrop& crop,
                            const Bounds3f& feather_bounds);

// The compared pixels: inside the feather's analysed outline grown by `grow_px`
// panel pixels, each marked left or right vane by its side of the analysed shaft.
PanelRegions crop_regions(const FeatherLayout& feather, const PhotoCrop& crop, int grow_px = 3);

}  // namespace plumage
