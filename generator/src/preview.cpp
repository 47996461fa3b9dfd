#include "plumage/generator/preview.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "plumage/common/bspline.h"
#include "plumage/common/error.h"

namespace plumage {

namespace {

constexpr int kSamplesPerSegment = 6;
constexpr float kMinHalfWidthPx = 0.6f;  // thinner lines are drawn fainter instead

// One curve's coverage is accumulated as a per-pixel maximum and composited once,
// so the joints between its line pieces do not darken where they overlap.
class Canvas {
 public:
  explicit Canvas(Image& img) : img_(img), cov_(std::size_t(img.width) * img.height, 0.0f) {}

  // Anti-aliased capsule from a to b (pixels) with half-width hw: coverage falls
  // off linearly over one pixel at the edge.
  void segment(glm::vec2 a, glm::vec2 b, float hw, float opacity) {
    const int x0 = std::max(0, int(std::floor(std::min(a.x, b.x) - hw - 1)));
    const int x1 = std::min(img_.width - 1, int(std::ceil(std::max(a.x, b.x) + hw + 1)));
    const int y0 = std::max(0, int(std::floor(std::min(a.y, b.y) - hw - 1)));
    const int y1 = std::min(img_.height - 1, int(std::ceil(std::max(a.y, b.y) + hw + 1)));
    const glm::vec2 ab = b - a;
    const float len2 = glm::dot(ab, ab);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const glm::vec2 q(x + 0.5f, y + 0.5f);
        const float t = len2 > 0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
        const float d = glm::length(q - (a + t * ab));
        const float c = std::clamp(hw + 0.5f - d, 0.0f, 1.0f) * opacity;
        if (c <= 0) continue;
        float& slot = cov_[std::size_t(y) * img_.width + x];
        if (slot == 0) touched_.push_back(std::size_t(y) * img_.width + x);
        slot = std::max(slot, c);
      }
  }

  void composite(const glm::vec3& colour) {
    for (std::size_t i : touched_) {
      const int x = int(i % img_.width), y = int(i / img_.width);
      img_.set_rgb(x, y, glm::mix(img_.rgb(x, y), colour, cov_[i]));
      cov_[i] = 0;
    }
    touched_.clear();
  }

 private:
  Image& img_;
  std::vector<float> cov_;
  std::vector<std::size_t> touched_;
};

// A stroke font for the scale bar's label: each glyph is polylines on a 3 x 6
// grid, y up, in the order the pen moves.
using Stroke = std::vector<glm::vec2>;
std::vector<Stroke> glyph(char c) {
  switch (c) {
    case '0': return {{{1, 0}, {2, 0}, {3, 1}, {3, 5}, {2, 6}, {1, 6}, {0, 5}, {0, 1}, {1, 0}}};
    case '1': return {{{0.5f, 5}, {1.5f, 6}, {1.5f, 0}}, {{0.5f, 0}, {2.5f, 0}}};
    case 'm': return {{{0, 0}, {0, 4}}, {{0, 3.2f}, {0.7f, 4}, {1.5f, 3.4f}, {1.5f, 0}},
                      {{1.5f, 3.4f}, {2.3f, 4}, {3, 3.2f}, {3, 0}}};
    default: return {};
  }
}

void draw_label(Canvas& canvas, const std::string& text, glm::vec2 baseline_left, float unit) {
  glm::vec2 pen = baseline_left;
  for (char c : text) {
    for (const Stroke& st : glyph(c))
      for (std::size_t i = 1; i < st.size(); ++i)
        canvas.segment(pen + unit * glm::vec2(st[i - 1].x, -st[i - 1].y), pen + unit * glm::vec2(st[i].x, -st[i].y),
                       std::max(0.7f, 0.35f * unit), 1.0f);
    pen.x += (c == ' ' ? 2.5f : 4.5f) * unit;
  }
}

}  // namespace

Image render_preview(const Feather& feather, const PreviewOptions& options) {
  if (options.size < 16 || options.size > 16384)
    throw Error("preview size " + std::to_string(options.size) + " is out of range; allowed [16, 16384] pixels");
  glm::vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const Curve& c : feather.curves)
    for (const ControlPoint& p : c.points) {
      if (!std::isfinite(p.p.x) || !std::isfinite(p.p.y) || !std::isfinite(p.radius))
        throw Error("cannot draw a preview: a control point is not finite (NaN or infinity)");
      lo = glm::min(lo, glm::vec2(p.p));
      hi = glm::max(hi, glm::vec2(p.p));
    }
  if (feather.curves.empty() || !(hi.x >= lo.x) || !std::isfinite(hi.x - lo.x) || !std::isfinite(hi.y - lo.y))
    throw Error("cannot draw a preview: the feather has no (finite) curves");

  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f});
  const float margin = 0.06f * options.size;
  const float scale = (options.size - 2 * margin) / extent;  // pixels per mm
  const int w = std::max(16, int(std::ceil((hi.x - lo.x) * scale + 2 * margin)));
  const int h = std::max(16, int(std::ceil((hi.y - lo.y) * scale + 2 * margin)));
  Image img(w, h, 3);
  // A faint vertical gradient keeps the page from looking flat.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.set_rgb(x, y, PreviewPalette::background * (0.92f + 0.08f * float(y) / h));

  // Feather +Y (tip) points up the image.
  auto to_px = [&](const glm::dvec3& p) {
    return glm::vec2(margin + (float(p.x) - lo.x) * scale, h - margin - (float(p.y) - lo.y) * scale);
  };
  Canvas canvas(img);
  auto draw = [&](const Curve& c, const glm::vec3& colour, float opacity) {
    if (c.points.size() < 4) return;
    std::vector<glm::dvec3> cp;
    std::vector<double> radius;
    for (const auto& p : c.points) cp.push_back(glm::dvec3(p.p)), radius.push_back(p.radius);
    const BSpline3 curve(cp);
    const BSpline1 r(radius);
    const int n = int(curve.num_segments()) * kSamplesPerSegment;
    glm::vec2 prev = to_px(curve.eval(0));
    for (int i = 1; i <= n; ++i) {
      const double t = double(i) / n;
      const glm::vec2 cur = to_px(curve.eval(t));
      const float hw = float(r.eval(t)) * scale;
      canvas.segment(prev, cur, std::max(hw, kMinHalfWidthPx), opacity * std::min(1.0f, hw / kMinHalfWidthPx + 0.35f));
      prev = cur;
    }
    canvas.composite(colour);
  };
  // Down barbs (tubes their fibres fill to down_cover) as faint as they are full.
  for (const Curve& c : feather.curves)
    if (c.kind != CurveKind::Shaft)
      draw(c, c.side == VaneSide::Right ? PreviewPalette::right : PreviewPalette::left,
           c.kind == CurveKind::Down ? 0.9f * feather.down_cover : 0.9f);
  for (const Curve& c : feather.curves)
    if (c.kind == CurveKind::Shaft) draw(c, PreviewPalette::shaft, 1.0f);

  if (options.scale_bar && 10 * scale < w - 2 * margin) {
    const float y = h - 0.45f * margin, x0 = margin;
    const glm::vec3 ink(0.02f);
    canvas.segment({x0, y}, {x0 + 10 * scale, y}, 1.5f, 1.0f);
    for (int mm = 0; mm <= 10; ++mm) {
      const float tick = mm % 5 == 0 ? 6.0f : 3.0f;
      canvas.segment({x0 + mm * scale, y}, {x0 + mm * scale, y - tick}, 0.6f, 1.0f);
    }
    const float unit = std::max(1.2f, 0.03f * margin);  // glyphs are 6 units tall
    draw_label(canvas, "10 mm", {x0 + 10 * scale + 3 * unit, y + 3 * unit}, unit);
    canvas.composite(ink);
  }
  return img;
}

}  // namespace plumage
