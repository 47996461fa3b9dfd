#include "plumage/renderer/panel_layout.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/error.h"
#include "plumage/renderer/label_font.h"

namespace plumage {
namespace {
const glm::vec3 kBackground{0.02f}, kLabelColour{1.0f};
constexpr int kGap = 6;

int strip_height(int scale) { return text_height(scale) + 2 * scale + 4; }

void blit(Image& dst, const Image& src, int x0, int y0) {
  for (int y = 0; y < src.height; ++y)
    for (int x = 0; x < src.width; ++x)
      if (x0 + x >= 0 && x0 + x < dst.width && y0 + y >= 0 && y0 + y < dst.height)
        dst.set_rgb(x0 + x, y0 + y, src.rgb(x, y));
}
}  // namespace

Image scale_to_height(const Image& img, int height) {
  if (img.empty() || img.width < 1 || img.height < 1) throw Error("cannot scale an empty image");
  if (height < 1) throw Error("cannot scale an image to height " + std::to_string(height));
  const double f = double(img.height) / height;
  const int width = std::max(1, int(std::lround(img.width / f)));
  Image out(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      // Average of the source pixels under this pixel's footprint (at least one).
      const int x0 = std::min(img.width - 1, int(x * f)), x1 = std::max(x0 + 1, std::min(img.width, int((x + 1) * f)));
      const int y0 = std::min(img.height - 1, int(y * f)), y1 = std::max(y0 + 1, std::min(img.height, int((y + 1) * f)));
      glm::vec3 sum(0);
      for (int j = y0; j < y1; ++j)
        for (int i = x0; i < x1; ++i) sum += img.rgb(i, j);
      out.set_rgb(x, y, sum / float((x1 - x0) * (y1 - y0)));
    }
  return out;
}

Image side_by_side(const std::vector<Panel>& panels, int label_scale) {
  if (panels.empty()) throw Error("side by side: no panels");
  int h = 0;
  for (const Panel& p : panels) h = std::max(h, p.image.height);
  std::vector<Image> scaled;
  int w = kGap;
  for (const Panel& p : panels) {
    scaled.push_back(p.image.height == h ? p.image : scale_to_height(p.image, h));
    w += std::max(scaled.back().width, text_width(p.label, label_scale)) + kGap;
  }
  const int strip = strip_height(label_scale);
  Image out(w, strip + h + kGap, 3);
  fill_rect(out, 0, 0, out.width, out.height, kBackground);
  int x = kGap;
  for (std::size_t i = 0; i < panels.size(); ++i) {
    draw_text(out, x, (strip - text_height(label_scale)) / 2, panels[i].label, kLabelColour, label_scale);
    blit(out, scaled[i], x, strip);
    x += std::max(scaled[i].width, text_width(panels[i].label, label_scale)) + kGap;
  }
  return out;
}

Image contact_sheet(const std::vector<Panel>& tiles, int columns, const std::string& title, int label_scale) {
  if (tiles.empty()) throw Error("contact sheet: no tiles");
  if (columns < 1) throw Error("contact sheet: at least one column");
  const int th = tiles.front().image.height;
  std::vector<Image> scaled;
  int tw = 0;
  for (const Panel& t : tiles) {
    scaled.push_back(t.image.height == th ? t.image : scale_to_height(t.image, th));
    tw = std::max({tw, scaled.back().width, text_width(t.label, label_scale)});
  }
  const int strip = strip_height(label_scale), title_strip = strip_height(label_scale + 1);
  const int cols = std::min(columns, int(tiles.size()));
  const int rows = (int(tiles.size()) + cols - 1) / cols;
  Image out(std::max(kGap + cols * (tw + kGap), text_width(title, label_scale + 1) + 2 * kGap),
            title_strip + rows * (strip + th + kGap), 3);
  fill_rect(out, 0, 0, out.width, out.height, kBackground);
  draw_text(out, kGap, (title_strip - text_height(label_scale + 1)) / 2, title, kLabelColour, label_scale + 1);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const int x = kGap + int(i % cols) * (tw + kGap), y = title_strip + int(i / cols) * (strip + th + kGap);
    draw_text(out, x, y + (strip - text_height(label_scale)) / 2, tiles[i].label, kLabelColour, label_scale);
    blit(out, scaled[i], x, y + strip);
  }
  return out;
}

}  // namespace plumage
