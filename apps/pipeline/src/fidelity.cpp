// Fidelity of a render against the photo (fidelity.h; docs/analysis.md, "Fidelity").
#include "plumage/pipeline/fidelity.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "plumage/common/error.h"
#include "plumage/common/interrupt.h"

namespace plumage {

glm::vec3 linear_rgb_to_lab(const glm::vec3& rgb) {
  const glm::vec3 c = glm::max(rgb, glm::vec3(0.0f));
  // Linear sRGB (D65) -> XYZ (IEC 61966-2-1), normalised by the D65 white.
  const double X = (0.4124564 * c.x + 0.3575761 * c.y + 0.1804375 * c.z) / 0.95047;
  const double Y = 0.2126729 * c.x + 0.7151522 * c.y + 0.0721750 * c.z;
  const double Z = (0.0193339 * c.x + 0.1191920 * c.y + 0.9503041 * c.z) / 1.08883;
  const auto f = [](double t) {
    constexpr double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(X), fy = f(Y), fz = f(Z);
  return {float(116 * fy - 16), float(500 * (fx - fy)), float(200 * (fy - fz))};
}

// Sharma, Wu & Dalal, "The CIEDE2000 color-difference formula" (2005), eqs. 1-23; kL = kC = kH = 1.
double ciede2000(const glm::vec3& lab1, const glm::vec3& lab2) {
  constexpr double pi = std::numbers::pi;
  const auto deg = [](double r) { return r * 180.0 / pi; };
  const auto rad = [](double d) { return d * pi / 180.0; };
  const double L1 = lab1.x, a1 = lab1.y, b1 = lab1.z, L2 = lab2.x, a2 = lab2.y, b2 = lab2.z;
  const double C1 = std::hypot(a1, b1), C2 = std::hypot(a2, b2);
  const double Cm7 = std::pow(0.5 * (C1 + C2), 7.0);
  const double G = 0.5 * (1 - std::sqrt(Cm7 / (Cm7 + std::pow(25.0, 7.0))));
  const double a1p = (1 + G) * a1, a2p = (1 + G) * a2;
  const double C1p = std::hypot(a1p, b1), C2p = std::hypot(a2p, b2);
  const auto hue = [&](double b, double ap) {
    if (b == 0 && ap == 0) return 0.0;
    const double h = deg(std::atan2(b, ap));
    return h < 0 ? h + 360 : h;
  };
  const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);
  const double dLp = L2 - L1, dCp = C2p - C1p;
  double dhp = 0;
  if (C1p * C2p != 0) {
    dhp = h2p - h1p;
    if (dhp > 180) dhp -= 360;
    else if (dhp < -180) dhp += 360;
  }
  const double dHp = 2 * std::sqrt(C1p * C2p) * std::sin(rad(dhp / 2));
  const double Lmp = 0.5 * (L1 + L2), Cmp = 0.5 * (C1p + C2p);
  double hmp = h1p + h2p;
  if (C1p * C2p != 0) {
    if (std::abs(h1p - h2p) <= 180) hmp = 0.5 * (h1p + h2p);
    else hmp = h1p + h2p < 360 ? 0.5 * (h1p + h2p + 360) : 0.5 * (h1p + h2p - 360);
  }
  const double T = 1 - 0.17 * std::cos(rad(hmp - 30)) + 0.24 * std::cos(rad(2 * hmp)) +
                   0.32 * std::cos(rad(3 * hmp + 6)) - 0.20 * std::cos(rad(4 * hmp - 63));
  const double dtheta = 30 * std::exp(-std::pow((hmp - 275) / 25, 2.0));
  const double Cmp7 = std::pow(Cmp, 7.0);
  const double RC = 2 * std::sqrt(Cmp7 / (Cmp7 + std::pow(25.0, 7.0)));
  const double SL = 1 + 0.015 * (Lmp - 50) * (Lmp - 50) / std::sqrt(20 + (Lmp - 50) * (Lmp - 50));
  const double SC = 1 + 0.045 * Cmp, SH = 1 + 0.015 * Cmp * T;
  const double RT = -std::sin(rad(2 * dtheta)) * RC;
  const double l = dLp / SL, c = dCp / SC, h = dHp / SH;
  return std::sqrt(l * l + c * c + h * h + RT * c * h);
}

double ciede2000_linear_rgb(const glm::vec3& rgb1, const glm::vec3& rgb2) {
  return ciede2000(linear_rgb_to_lab(rgb1), linear_rgb_to_lab(rgb2));
}

glm::vec3 mean_over_mask(const Image& img, const std::vector<char>& mask) {
  glm::dvec3 sum(0.0);
  long n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (mask[std::size_t(y) * img.width + x]) {
        sum += glm::dvec3(img.rgb(x, y));
        ++n;
      }
  return n > 0 ? glm::vec3(sum / double(n)) : glm::vec3(0.0f);
}

Image gaussian_blur(const Image& img, float sigma) {
  if (img.empty()) throw Error("blur: empty image");
  Image src(img.width, img.height, 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) src.set_rgb(x, y, img.rgb(x, y));
  if (!(sigma > 0)) return src;
  const int r = std::max(1, int(std::ceil(3 * sigma)));
  std::vector<float> k(2 * r + 1);
  float sum = 0;
  for (int i = -r; i <= r; ++i) sum += k[i + r] = std::exp(-0.5f * float(i * i) / (sigma * sigma));
  for (float& v : k) v /= sum;
  Image tmp(img.width, img.height, 3), out(img.width, img.height, 3);
  for (int y = 0; y < img.height; ++y) {
    if (y % 64 == 0) check_interrupted();  // a photo-sized blur takes a while: stop here on a signal
    for (int x = 0; x < img.width; ++x) {
      glm::vec3 a(0);
      for (int i = -r; i <= r; ++i) a += k[i + r] * src.rgb(std::clamp(x + i, 0, img.width - 1), y);
      tmp.set_rgb(x, y, a);
    }
  }
  for (int y = 0; y < img.height; ++y) {
    if (y % 64 == 0) check_interrupted();
    for (int x = 0; x < img.width; ++x) {
      glm::vec3 a(0);
      for (int i = -r; i <= r; ++i) a += k[i + r] * tmp.rgb(x, std::clamp(y + i, 0, img.height - 1));
      out.set_rgb(x, y, a);
    }
  }
  return out;
}

std::optional<glm::vec3> ring_median(const Image& img,
                                     const std::function<bool(int x, int y, const glm::vec3& c)>& keep,
                                     std::size_t min_count, int depth) {
  std::vector<float> ring[3];
  const auto take = [&](int x, int y) {
    const glm::vec3 c = img.rgb(x, y);
    if (!keep(x, y, c)) return;
    for (int k = 0; k < 3; ++k) ring[k].push_back(c[k]);
  };
  // Each pixel once, however deep the frame and however small the image.
  const int d = std::clamp(depth, 1, std::max(1, (std::min(img.width, img.height) + 1) / 2));
  for (int y = 0; y < img.height; ++y) {
    const bool row = y < d || y >= img.height - d;
    for (int x = 0; x < img.width; ++x) {
      if (row || x < d || x >= img.width - d) {
        take(x, y);
      } else {
        x = img.width - d - 1;  // on to the row's right-hand frame
      }
    }
  }
  if (ring[0].empty() || ring[0].size() < min_count) return std::nullopt;
  glm::vec3 m;
  for (int k = 0; k < 3; ++k) {
    auto mid = ring[k].begin() + std::ptrdiff_t(ring[k].size() / 2);
    std::nth_element(ring[k].begin(), mid, ring[k].end());
    m[k] = *mid;
  }
  return m;
}

namespace {

void check_size(const Image& img, const PanelRegions& regions) {
  if (img.width != regions.width || img.height != regions.height || regions.side.size() != std::size_t(img.width) * img.height)
    throw Error("fidelity: a panel of " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                " does not match the compared region's " + std::to_string(regions.width) + "x" +
                std::to_string(regions.height));
}

}  // namespace

MeasuredPanel measure_panel(const Image& panel, const PanelRegions& regions, const FidelitySettings& settings,
                            std::optional<glm::vec3> backdrop) {
  check_size(panel, regions);
  MeasuredPanel m;
  m.blurred = gaussian_blur(panel, settings.blur_sigma_px);
  const int w = panel.width, h = panel.height;
  if (backdrop) {
    m.backdrop = *backdrop;
  } else {
    // The ring outside the compared region; all of it when the region covers it.
    const auto outside = ring_median(m.blurred, [&](int x, int y, const glm::vec3&) { return !regions.at(x, y); });
    m.backdrop = outside ? *outside : *ring_median(m.blurred, [](int, int, const glm::vec3&) { return true; });
  }
  const glm::vec3 backdrop_lab = linear_rgb_to_lab(m.backdrop);
  m.feather.assign(std::size_t(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (regions.at(x, y))
        m.feather[std::size_t(y) * w + x] =
            ciede2000(linear_rgb_to_lab(m.blurred.rgb(x, y)), backdrop_lab) > settings.mask_de;
  // A silhouette has no holes: backdrop-coloured pixels that no path of
  // non-feather pixels joins to the panel's edge (a pale bar on a barred vane,
  // say) are feather; gaps open to the edge (splits) stay.
  std::vector<char> outside(m.feather.size(), 0);
  std::vector<std::pair<int, int>> stack;
  const auto push = [&](int x, int y) {
    const std::size_t i = std::size_t(y) * w + x;
    if (x < 0 || y < 0 || x >= w || y >= h || outside[i] || m.feather[i]) return;
    outside[i] = 1;
    stack.emplace_back(x, y);
  };
  for (int x = 0; x < w; ++x) push(x, 0), push(x, h - 1);
  for (int y = 0; y < h; ++y) push(0, y), push(w - 1, y);
  while (!stack.empty()) {
    const auto [x, y] = stack.back();
    stack.pop_back();
    push(x + 1, y), push(x - 1, y), push(x, y + 1), push(x, y - 1);
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * w + x;
      if (regions.at(x, y) && !outside[i]) m.feather[i] = 1;
    }
  return m;
}

long mask_perimeter(const std::vector<char>& mask, const PanelRegions& regions) {
  const auto in = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < regions.width && y < regions.height && regions.at(x, y) &&
           mask[std::size_t(y) * regions.width + x];
  };
  long n = 0;
  for (int y = 0; y < regions.height; ++y)
    for (int x = 0; x < regions.width; ++x)
      if (in(x, y) && !(in(x - 1, y) && in(x + 1, y) && in(x, y - 1) && in(x, y + 1))) ++n;
  return n;
}

RenderFidelity compare_panels(const MeasuredPanel& photo, const MeasuredPanel& render, const PanelRegions& regions) {
  check_size(photo.blurred, regions);
  check_size(render.blurred, regions);
  struct Sums {
    long both = 0, either = 0, p = 0, r = 0;
    glm::dvec3 photo_sum{0}, render_sum{0};
    double de_sum = 0;
    double lp = 0, lr = 0, lpp = 0, lrr = 0, lpr = 0, ln = 0;  // luminance moments inside the photo's mask
  } sums[3];  // whole feather, left, right
  // Inside the photo's mask by kInset pixels: the blurred rim, half card, would
  // otherwise make any two silhouettes of the same shape correlate.
  constexpr int kInset = 3;
  const auto in_photo = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < regions.width && y < regions.height &&
           photo.feather[std::size_t(y) * regions.width + x];
  };
  const auto interior = [&](int x, int y) {
    for (int dy = -kInset; dy <= kInset; dy += kInset)
      for (int dx = -kInset; dx <= kInset; dx += kInset)
        if (!in_photo(x + dx, y + dy)) return false;
    return true;
  };
  for (int y = 0; y < regions.height; ++y)
    for (int x = 0; x < regions.width; ++x) {
      const unsigned char side = regions.at(x, y);
      if (!side) continue;
      const std::size_t i = std::size_t(y) * regions.width + x;
      const bool in_p = photo.feather[i], in_r = render.feather[i];
      if (!in_p && !in_r) continue;
      double de = 0;
      if (in_p) de = ciede2000_linear_rgb(photo.blurred.rgb(x, y), render.blurred.rgb(x, y));
      for (Sums* s : {&sums[0], &sums[side]}) {
        s->both += in_p && in_r;
        s->either += 1;
        s->p += in_p;
        s->r += in_r;
        if (in_p) {
          s->photo_sum += glm::dvec3(photo.blurred.rgb(x, y));
          s->render_sum += glm::dvec3(render.blurred.rgb(x, y));
          s->de_sum += de;
          if (interior(x, y)) {
            const double a = luminance(photo.blurred.rgb(x, y)), b = luminance(render.blurred.rgb(x, y));
            s->lp += a, s->lr += b, s->lpp += a * a, s->lrr += b * b, s->lpr += a * b, s->ln += 1;
          }
        }
      }
    }
  const auto vane = [](const Sums& s) {
    VaneFidelity v;
    v.iou = s.either > 0 ? double(s.both) / double(s.either) : 0.0;
    v.photo_pixels = int(s.p);
    v.render_pixels = int(s.r);
    if (s.p > 0) {
      v.photo_mean = glm::vec3(s.photo_sum / double(s.p));
      v.render_mean = glm::vec3(s.render_sum / double(s.p));
      v.mean_colour_de2000 = ciede2000_linear_rgb(v.photo_mean, v.render_mean);
      v.pixel_de2000 = s.de_sum / double(s.p);
      const double n = s.ln;
      const double cov = s.lpr - s.lp * s.lr / n, vp = s.lpp - s.lp * s.lp / n, vr = s.lrr - s.lr * s.lr / n;
      v.luminance_correlation = n > 1 && vp > 0 && vr > 0 ? cov / std::sqrt(vp * vr) : 0.0;
    }
    return v;
  };
  RenderFidelity f;
  f.feather = vane(sums[0]);
  f.left = vane(sums[1]);
  f.right = vane(sums[2]);
  f.backdrop_de2000 = ciede2000_linear_rgb(photo.backdrop, render.backdrop);
  const long photo_edge = mask_perimeter(photo.feather, regions), render_edge = mask_perimeter(render.feather, regions);
  f.perimeter_ratio = photo_edge > 0 ? double(render_edge) / double(photo_edge) : 0.0;
  return f;
}

Image mask_picture(const MeasuredPanel& photo, const MeasuredPanel& render, const PanelRegions& regions) {
  Image out(regions.width, regions.height, 3);
  for (int y = 0; y < regions.height; ++y)
    for (int x = 0; x < regions.width; ++x) {
      const std::size_t i = std::size_t(y) * regions.width + x;
      const bool p = photo.feather[i], r = render.feather[i];
      glm::vec3 c = !regions.at(x, y) ? glm::vec3(0.01f, 0.01f, 0.03f)
                    : p && r          ? glm::vec3(0.9f)
                    : p               ? glm::vec3(0.9f, 0.05f, 0.02f)
                    : r               ? glm::vec3(0.02f, 0.6f, 0.9f)
                                      : glm::vec3(0.06f);
      out.set_rgb(x, y, c);
    }
  return out;
}

Image difference_picture(const MeasuredPanel& photo, const MeasuredPanel& render, const PanelRegions& regions) {
  Image out(regions.width, regions.height, 3);
  for (int y = 0; y < regions.height; ++y)
    for (int x = 0; x < regions.width; ++x) {
      const double de = ciede2000_linear_rgb(photo.blurred.rgb(x, y), render.blurred.rgb(x, y));
      const float t = float(std::min(de / 20.0, 1.0));
      glm::vec3 c(std::min(1.0f, 3 * t), std::clamp(3 * t - 1, 0.0f, 1.0f), std::clamp(3 * t - 2, 0.0f, 1.0f));
      if (!regions.at(x, y)) c *= 0.35f;
      out.set_rgb(x, y, c);
    }
  return out;
}

namespace {
nlohmann::json rgb_json(const glm::vec3& c) { return nlohmann::json::array({c.x, c.y, c.z}); }
nlohmann::json vane_json(const VaneFidelity& v) {
  return {{"silhouette_iou", v.iou},
          {"photo_pixels", v.photo_pixels},
          {"render_pixels", v.render_pixels},
          {"photo_mean_rgb", rgb_json(v.photo_mean)},
          {"render_mean_rgb", rgb_json(v.render_mean)},
          {"mean_colour_de2000", v.mean_colour_de2000},
          {"pixel_de2000", v.pixel_de2000},
          {"luminance_correlation", v.luminance_correlation}};
}
}  // namespace

nlohmann::json to_json(const RenderFidelity& f) {
  return {{"feather", vane_json(f.feather)},
          {"left", vane_json(f.left)},
          {"right", vane_json(f.right)},
          {"backdrop_de2000", f.backdrop_de2000},
          {"perimeter_ratio", f.perimeter_ratio}};
}

nlohmann::json to_json(const FidelitySettings& s) {
  return {{"blur_sigma_px", s.blur_sigma_px}, {"mask_de2000", s.mask_de}};
}

}  // namespace plumage
