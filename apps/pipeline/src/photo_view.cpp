// The photo's crop and the camera that sees exactly it (photo_view.h).
#include "plumage/pipeline/photo_view.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/error.h"
#include "plumage/analysis/analyze.h"

namespace plumage {

namespace {

glm::dvec2 linear(const glm::dmat3x2& A, const glm::dvec2& v) { return glm::dmat2(A[0], A[1]) * v; }

// Weights of the source pixels under each of `n` output pixels of width `step`
// starting at `origin` (source pixels outside [0, size) clamped to the edge).
struct Footprint {
  std::vector<int> first, count;
  std::vector<int> index;
  std::vector<float> weight;
};
Footprint footprints(double origin, double step, int n, int size) {
  Footprint f;
  for (int i = 0; i < n; ++i) {
    const double a = origin + i * step, b = a + step;
    f.first.push_back(int(f.index.size()));
    double total = 0;
    const std::size_t start = f.weight.size();
    for (int p = int(std::floor(a)); p < int(std::ceil(b)); ++p) {
      const double w = std::min(b, p + 1.0) - std::max(a, double(p));
      if (w <= 0) continue;
      f.index.push_back(std::clamp(p, 0, size - 1));
      f.weight.push_back(float(w));
      total += w;
    }
    for (std::size_t k = start; k < f.weight.size(); ++k) f.weight[k] = float(f.weight[k] / total);
    f.count.push_back(int(f.weight.size() - start));
  }
  return f;
}

}  // namespace

PhotoCrop crop_for(const Layout& layout, const FeatherLayout& feather, int size, double margin) {
  if (size < 16) throw Error("the panels must be at least 16 pixels on their longer side");
  const auto& b = feather.bbox_px;
  const double m = std::max(8.0, margin * std::max(b[2], b[3]));
  const double x0 = std::max(0.0, b[0] - m), y0 = std::max(0.0, b[1] - m);
  const double x1 = std::min(double(layout.image_width), b[0] + b[2] + m);
  const double y1 = std::min(double(layout.image_height), b[1] + b[3] + m);
  if (!(x1 - x0 >= 1 && y1 - y0 >= 1))
    throw Error("feather " + std::to_string(feather.id) + ": its bounding box lies outside the " +
                std::to_string(layout.image_width) + "x" + std::to_string(layout.image_height) + " photo");
  PhotoCrop c;
  c.px_per_panel_px = std::max(x1 - x0, y1 - y0) / size;
  c.width = std::max(8, int(std::lround((x1 - x0) / c.px_per_panel_px)));
  c.height = std::max(8, int(std::lround((y1 - y0) / c.px_per_panel_px)));
  // Centred on the box: the panel's sides are whole numbers of pixels.
  c.origin_px = 0.5 * glm::dvec2(x0 + x1, y0 + y1) - 0.5 * c.px_per_panel_px * glm::dvec2(c.width, c.height);
  return c;
}

Image crop_photo(const Image& photo, const PhotoCrop& crop) {
  if (photo.empty()) throw Error("crop: empty photo");
  const Footprint fx = footprints(crop.origin_px.x, crop.px_per_panel_px, crop.width, photo.width);
  const Footprint fy = footprints(crop.origin_px.y, crop.px_per_panel_px, crop.height, photo.height);
  // Rows first (only the source rows the crop needs), then columns.
  const int row0 = fy.index.empty() ? 0 : *std::min_element(fy.index.begin(), fy.index.end());
  const int row1 = fy.index.empty() ? 0 : *std::max_element(fy.index.begin(), fy.index.end());
  Image rows(crop.width, row1 - row0 + 1, 3);
  for (int y = row0; y <= row1; ++y)
    for (int i = 0; i < crop.width; ++i) {
      glm::vec3 a(0);
      for (int k = fx.first[i]; k < fx.first[i] + fx.count[i]; ++k) a += fx.weight[k] * photo.rgb(fx.index[k], y);
      rows.set_rgb(i, y - row0, a);
    }
  Image out(crop.width, crop.height, 3);
  for (int j = 0; j < crop.height; ++j)
    for (int i = 0; i < crop.width; ++i) {
      glm::vec3 a(0);
      for (int k = fy.first[j]; k < fy.first[j] + fy.count[j]; ++k) a += fy.weight[k] * rows.rgb(i, fy.index[k] - row0);
      out.set_rgb(i, j, a);
    }
  return out;
}

PhotoCrop render_grid_for(const PhotoCrop& shown) {
  const double s = shown.px_per_panel_px;
  if (s >= 1) return shown;
  const glm::dvec2 end = shown.origin_px + s * glm::dvec2(shown.width, shown.height);
  const double longer = s * std::max(shown.width, shown.height);  // in photo pixels
  const int finest = std::max(1, int(std::floor(1.0 / s)));
  const int factor = std::clamp(int(std::ceil(kMinRenderSide / std::max(longer, 1e-9))), 1, finest);
  PhotoCrop g;
  g.px_per_panel_px = 1.0 / factor;
  const glm::dvec2 first = glm::floor(shown.origin_px * double(factor));
  const glm::dvec2 last = glm::ceil(end * double(factor));
  g.origin_px = first / double(factor);
  g.width = std::max(1, int(last.x - first.x));
  g.height = std::max(1, int(last.y - first.y));
  return g;
}

int render_spp_for(int spp, const PhotoCrop& shown, const PhotoCrop& grid) {
  const double ratio = double(shown.width) * shown.height / (double(grid.width) * grid.height);
  if (!(ratio > 1)) return spp;
  const double want = std::min({4096.0, spp * ratio, double(spp) * kGridSppFactor});
  const int rounded = 1 << int(std::lround(std::log2(want)));
  return std::clamp(rounded, spp, std::max(spp, 4096));
}

Image show_on_panel(const Image& render, const PhotoCrop& grid, const PhotoCrop& shown) {
  if (grid == shown) return render;
  // In the grid's own pixels: its origin at 0, its pixels of side 1.
  PhotoCrop on_grid = shown;
  on_grid.origin_px = (shown.origin_px - grid.origin_px) / grid.px_per_panel_px;
  on_grid.px_per_panel_px = shown.px_per_panel_px / grid.px_per_panel_px;
  return crop_photo(render, on_grid);
}

CameraSpec crop_camera(const FeatherLayout& f, const PhotoCrop& crop) {
  const glm::dmat3x2& A = f.feather_from_image;
  const double s = crop.px_per_panel_px;
  const glm::dvec2 centre = apply(A, crop.origin_px + 0.5 * s * glm::dvec2(crop.width, crop.height));
  const glm::dvec2 up_mm = linear(A, {0.0, -1.0}), right_mm = linear(A, {1.0, 0.0});
  const double mm_per_px = glm::length(up_mm);
  if (!(mm_per_px > 0) || !std::isfinite(mm_per_px))
    throw Error("feather " + std::to_string(f.id) + ": the layout's image-to-feather transform is degenerate");
  const glm::dvec2 up = up_mm / mm_per_px;
  // A camera looking down -Z with this up has its right along (up.y, -up.x).
  if (glm::dot(right_mm, glm::dvec2(up.y, -up.x)) <= 0)
    throw Error("feather " + std::to_string(f.id) +
                ": the layout's image-to-feather transform mirrors the photo; a top view cannot show it");
  // Low enough to stay under the dome rig's LEDs (300 mm), high above a cupped vane.
  const double above = std::min(0.3 * f.length_mm + 10.0, 250.0);
  CameraSpec c;
  c.projection = Projection::Orthographic;
  c.position = glm::vec3(float(centre.x), float(centre.y), float(above));
  c.look_at = glm::vec3(float(centre.x), float(centre.y), 0.0f);
  c.up = glm::vec3(float(up.x), float(up.y), 0.0f);
  c.ortho_height = float(crop.height * s * mm_per_px);
  return c;
}

glm::vec3 background_colour(const Image& photo, const Image& photo_panel) {
  const glm::vec3 whole = *ring_median(photo, [](int, int, const glm::vec3&) { return true; }, 1,
                                       border_frame_px(photo.width, photo.height));
  const glm::vec3 whole_lab = linear_rgb_to_lab(whole);
  const std::size_t ring = 2 * std::size_t(photo_panel.width) + 2 * std::size_t(std::max(0, photo_panel.height - 2));
  const auto local = ring_median(
      photo_panel,
      [&](int, int, const glm::vec3& c) { return ciede2000(linear_rgb_to_lab(c), whole_lab) < kBackgroundDe; },
      std::max<std::size_t>(8, ring / 10));
  return glm::max(local ? *local : whole, glm::vec3(1e-3f));
}

BackdropSpec photo_backdrop(const glm::vec3& colour, const FeatherLayout& f, const PhotoCrop& crop,
                            const Bounds3f& feather_bounds) {
  const float top = std::max({colour.x, colour.y, colour.z});
  BackdropSpec b;
  b.enabled = true;
  b.placement = BackdropPlacement::Vane;  // the photographed vane lies on its card
  b.albedo = top > 0.9f ? colour * (0.9f / top) : colour;
  // The card is a square centred under the feather: make it reach every corner of the view.
  const glm::vec2 c(feather_bounds.centre().x, feather_bounds.centre().y);
  const double s = crop.px_per_panel_px;
  float need = 0;
  for (double u : {0.0, 1.0})
    for (double v : {0.0, 1.0}) {
      const glm::dvec2 corner = apply(f.feather_from_image, crop.origin_px + s * glm::dvec2(u * crop.width, v * crop.height));
      need = std::max({need, std::abs(float(corner.x) - c.x), std::abs(float(corner.y) - c.y)});
    }
  const glm::vec3 size = feather_bounds.size();
  const float side = std::max({size.x, size.y, 1e-3f});
  b.extent = std::max(b.extent, 2.2f * need / side);
  return b;
}

PanelRegions crop_regions(const FeatherLayout& f, const PhotoCrop& crop, int grow_px) {
  PanelRegions r;
  r.width = crop.width, r.height = crop.height;
  const std::size_t n = std::size_t(r.width) * r.height;
  std::vector<unsigned char> inside(n, f.outline_px.size() < 3 ? 1 : 0);
  const double s = crop.px_per_panel_px;
  if (f.outline_px.size() >= 3) {
    std::vector<glm::dvec2> poly;
    for (const glm::dvec2& p : f.outline_px) poly.push_back((p - crop.origin_px) / s);
    std::vector<double> xs;
    for (int y = 0; y < r.height; ++y) {
      const double yc = y + 0.5;
      xs.clear();
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        if ((a.y <= yc) != (b.y <= yc)) xs.push_back(a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x));
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
        for (int x = std::max(0, int(std::ceil(xs[k] - 0.5))); x < r.width && x + 0.5 <= xs[k + 1]; ++x)
          inside[std::size_t(y) * r.width + x] = 1;
    }
    // Grown by a square of side 2 grow_px + 1: rows, then columns.
    std::vector<unsigned char> tmp(n, 0);
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x)
        if (inside[std::size_t(y) * r.width + x])
          for (int d = std::max(0, x - grow_px); d <= std::min(r.width - 1, x + grow_px); ++d) tmp[std::size_t(y) * r.width + d] = 1;
    std::fill(inside.begin(), inside.end(), 0);
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x)
        if (tmp[std::size_t(y) * r.width + x])
          for (int d = std::max(0, y - grow_px); d <= std::min(r.height - 1, y + grow_px); ++d) inside[std::size_t(d) * r.width + x] = 1;
  }
  // Left or right of the shaft (seen dorsally, tip up, the left vane is on the left).
  std::vector<glm::dvec2> shaft;
  if (f.shaft_mm.valid())
    for (int i = 0; i <= 128; ++i) shaft.push_back(f.shaft_mm.eval(i / 128.0));
  r.side.assign(n, 0);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      const std::size_t i = std::size_t(y) * r.width + x;
      if (!inside[i]) continue;
      const glm::dvec2 p = apply(f.feather_from_image, crop.origin_px + s * glm::dvec2(x + 0.5, y + 0.5));
      double best = 1e300, cross = 0;
      for (std::size_t k = 0; k + 1 < shaft.size(); ++k) {
        const glm::dvec2 a = shaft[k], d = shaft[k + 1] - a;
        const double t = std::clamp(glm::dot(p - a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
        const glm::dvec2 q = p - (a + t * d);
        const double dist = glm::dot(q, q);
        if (dist < best) best = dist, cross = d.x * q.y - d.y * q.x;
      }
      r.side[i] = cross > 0 ? 1 : 2;
    }
  return r;
}

}  // namespace plumage
