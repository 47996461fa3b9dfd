#include "plumage/renderer/error_ladder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "plumage/common/cpu_time.h"
#include "plumage/common/error.h"
#include "plumage/renderer/label_font.h"

namespace plumage {
namespace {

void check_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.empty())
    throw Error("comparing images of different sizes (" + std::to_string(a.width) + "x" + std::to_string(a.height) +
                " and " + std::to_string(b.width) + "x" + std::to_string(b.height) + "); render both at one resolution");
}

std::vector<LadderPoint> of_mode(const std::vector<LadderPoint>& points, const std::string& mode) {
  std::vector<LadderPoint> out;
  for (const LadderPoint& p : points)
    if (p.mode == mode) out.push_back(p);
  std::sort(out.begin(), out.end(), [](const LadderPoint& a, const LadderPoint& b) { return a.spp < b.spp; });
  return out;
}

std::vector<std::string> mode_names(const std::vector<LadderPoint>& points) {
  std::vector<std::string> names;
  for (const LadderPoint& p : points)
    if (std::find(names.begin(), names.end(), p.mode) == names.end()) names.push_back(p.mode);
  return names;
}

// The rungs whose slope is judged: the upper half, but never fewer than two.
std::vector<LadderPoint> upper_half(const std::vector<LadderPoint>& rungs) {
  const std::size_t n = rungs.size();
  const std::size_t first = n >= 4 ? n / 2 : 0;
  return {rungs.begin() + std::ptrdiff_t(first), rungs.end()};
}

void draw_line(Image& img, glm::vec2 a, glm::vec2 b, const glm::vec3& colour, int thickness, float dash = 0) {
  const float len = glm::length(b - a);
  const int steps = std::max(1, int(std::ceil(len * 2)));
  for (int i = 0; i <= steps; ++i) {
    const float t = float(i) / float(steps);
    if (dash > 0 && int(t * len / dash) % 2) continue;
    const glm::vec2 p = a + t * (b - a);
    fill_rect(img, int(std::lround(p.x)) - thickness / 2, int(std::lround(p.y)) - thickness / 2, thickness, thickness,
              colour);
  }
}

std::string decade_label(int e) {
  if (e >= 0 && e <= 3) return std::to_string(int(std::lround(std::pow(10.0, e))));
  return "1E" + std::to_string(e);
}

}  // namespace

double rmse(const Image& a, const Image& ref) {
  check_same_size(a, ref);
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = double(a.pixels[i]) - double(ref.pixels[i]);
    sum += d * d;
  }
  return std::sqrt(sum / double(a.pixels.size()));
}

double relative_mse(const Image& a, const Image& ref) {
  check_same_size(a, ref);
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double r = ref.pixels[i], d = double(a.pixels[i]) - r;
    sum += d * d / (r * r + 1e-2);
  }
  return sum / double(a.pixels.size());
}

double loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    ++n;
  }
  const double den = n * sxx - sx * sx;
  if (n < 2 || !(den > 1e-12 * std::max(1.0, n * sxx))) return std::numeric_limits<double>::quiet_NaN();
  return (n * sxy - sx * sy) / den;
}

double upper_half_slope(const std::vector<LadderPoint>& points, const std::string& mode) {
  std::vector<double> t, e;
  for (const LadderPoint& p : upper_half(of_mode(points, mode))) {
    t.push_back(p.seconds);
    e.push_back(p.rmse);
  }
  return loglog_slope(t, e);
}

std::vector<std::string> biased_modes(const std::vector<LadderPoint>& points, double max_slope) {
  std::vector<std::string> bad;
  for (const std::string& mode : mode_names(points)) {
    const std::vector<LadderPoint> top = upper_half(of_mode(points, mode));
    const double s = upper_half_slope(points, mode);
    if (std::isfinite(s) && s <= max_slope) continue;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: slope %.3f over spp %d..%d", mode.c_str(), s, top.front().spp, top.back().spp);
    bad.emplace_back(buf);
  }
  return bad;
}

std::vector<LadderPoint> run_ladder(const Feather& feather, const DomeRig& rig, const ViewSpec& view,
                                    const LadderSpec& spec) {
  if (spec.reference_seed == view.seed)
    throw Error("the reference and the ladder share seed " + std::to_string(view.seed) +
                "; give the ladder another --seed (shared samples would hide the error)");
  if (spec.spp.empty() || spec.modes.empty()) throw Error("the ladder needs at least one sample count and one mode");
  if (spec.repeats < 1) throw Error("--repeats must be at least 1");
  for (int n : spec.spp)
    if (n < 1) throw Error("ladder sample counts must be at least 1 (got " + std::to_string(n) + ")");
  if (spec.reference_spp < 4 * *std::max_element(spec.spp.begin(), spec.spp.end()))
    throw Error("--reference-spp " + std::to_string(spec.reference_spp) +
                " is under 4x the top rung; the reference's own noise would flatten the ladder");

  ViewSpec ref_view = view;
  ref_view.spp = spec.reference_spp;
  ref_view.seed = spec.reference_seed;
  auto scene_options = [&](ShadingMode mode) {
    SceneOptions so;
    so.mode = mode;
    so.backdrop = spec.backdrop;
    return so;
  };
  std::optional<Image> shared_reference;
  if (spec.reference_mode)
    shared_reference = render_view(Scene(feather, scene_options(*spec.reference_mode)), rig, ref_view);

  std::vector<LadderPoint> out;
  for (ShadingMode mode : spec.modes) {
    const Scene scene(feather, scene_options(mode));
    const Image reference = shared_reference ? *shared_reference : render_view(scene, rig, ref_view);
    for (int n : spec.spp) {
      ViewSpec v = view;
      v.spp = n;
      LadderPoint p;
      p.mode = to_string(mode);
      p.spp = n;
      p.seconds = std::numeric_limits<double>::infinity();
      for (int r = 0; r < spec.repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const double cpu0 = process_cpu_seconds();
        const Image img = render_view(scene, rig, v);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (wall < p.seconds) {
          p.seconds = wall;
          p.cpu_seconds = process_cpu_seconds() - cpu0;
        }
        if (r == 0) {
          p.rmse = rmse(img, reference);
          p.rel_mse = relative_mse(img, reference);
        }
      }
      out.push_back(p);
    }
  }
  return out;
}

std::string ladder_csv(const std::vector<LadderPoint>& points) {
  std::ostringstream os;
  os << "mode,spp,seconds,rmse,relative_mse,cpu_seconds\n";
  os.precision(9);
  for (const LadderPoint& p : points)
    os << p.mode << ',' << p.spp << ',' << p.seconds << ',' << p.rmse << ',' << p.rel_mse << ',' << p.cpu_seconds
       << '\n';
  return os.str();
}

Image plot_ladder(const std::vector<LadderPoint>& points, int width, int height) {
  if (width < 200 || height < 150) throw Error("the ladder plot needs at least 200x150 pixels");
  Image img(width, height, 3, 1.0f);
  const glm::vec3 black(0), grey(0.6f);
  const int left = 70, right = 20, top = 40, bottom = 50;
  const int pw = width - left - right, ph = height - top - bottom;

  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const LadderPoint& p : points)
    if (p.seconds > 0 && p.rmse > 0 && std::isfinite(p.seconds) && std::isfinite(p.rmse)) {
      x0 = std::min(x0, std::log10(p.seconds)), x1 = std::max(x1, std::log10(p.seconds));
      y0 = std::min(y0, std::log10(p.rmse)), y1 = std::max(y1, std::log10(p.rmse));
    }
  if (!(x1 >= x0)) x0 = -1, x1 = 0, y0 = -1, y1 = 0;
  // Whole decades around the data, so every axis has at least two labelled ticks.
  x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1);
  y0 = std::floor(y0), y1 = std::max(std::ceil(y1), y0 + 1);
  auto to_px = [&](double lx, double ly) {
    return glm::vec2(float(left + (lx - x0) / (x1 - x0) * pw), float(top + (y1 - ly) / (y1 - y0) * ph));
  };

  draw_line(img, {left, top}, {left, top + ph}, black, 2);
  draw_line(img, {left, top + ph}, {left + pw, top + ph}, black, 2);
  for (int e = int(x0); e <= int(x1); ++e) {
    const glm::vec2 p = to_px(e, y0);
    draw_line(img, p, p + glm::vec2(0, 6), black, 2);
    const std::string s = decade_label(e);
    draw_text(img, int(p.x) - text_width(s, 2) / 2, int(p.y) + 10, s, black, 2);
    for (int k = 2; k <= 9 && e < int(x1); ++k) {
      const glm::vec2 q = to_px(e + std::log10(double(k)), y0);
      draw_line(img, q, q + glm::vec2(0, 3), black, 1);
    }
  }
  for (int e = int(y0); e <= int(y1); ++e) {
    const glm::vec2 p = to_px(x0, e);
    draw_line(img, p, p - glm::vec2(6, 0), black, 2);
    const std::string s = decade_label(e);
    draw_text(img, int(p.x) - 10 - text_width(s, 2), int(p.y) - text_height(2) / 2, s, black, 2);
    for (int k = 2; k <= 9 && e < int(y1); ++k) {
      const glm::vec2 q = to_px(x0, e + std::log10(double(k)));
      draw_line(img, q, q - glm::vec2(3, 0), black, 1);
    }
  }
  draw_text(img, left + pw / 2 - text_width("SECONDS", 2) / 2, height - 18, "SECONDS", black, 2);
  draw_text(img, 4, 8, "RMSE", black, 2);

  const glm::vec3 colours[] = {{0.85f, 0.3f, 0.1f}, {0.1f, 0.4f, 0.85f}, {0.2f, 0.6f, 0.2f}, {0.6f, 0.2f, 0.6f}};
  const std::vector<std::string> names = mode_names(points);
  int legend_x = left + 10;
  glm::vec2 anchor(-1);
  for (std::size_t m = 0; m < names.size(); ++m) {
    const glm::vec3 c = colours[m % 4];
    const std::vector<LadderPoint> rungs = of_mode(points, names[m]);
    for (std::size_t i = 0; i < rungs.size(); ++i) {
      if (!(rungs[i].seconds > 0 && rungs[i].rmse > 0)) continue;
      const glm::vec2 p = to_px(std::log10(rungs[i].seconds), std::log10(rungs[i].rmse));
      if (anchor.x < 0) anchor = p;
      fill_rect(img, int(p.x) - 3, int(p.y) - 3, 7, 7, c);
      if (i > 0 && rungs[i - 1].seconds > 0 && rungs[i - 1].rmse > 0)
        draw_line(img, to_px(std::log10(rungs[i - 1].seconds), std::log10(rungs[i - 1].rmse)), p, c, 2);
    }
    draw_text(img, legend_x, 12, names[m], c, 2);
    legend_x += text_width(names[m], 2) + 20;
  }
  // Slope -0.5 through the first point: one decade right, half a decade down.
  if (anchor.x >= 0) {
    const float dx = float(pw) / float(x1 - x0), dy = float(ph) / float(y1 - y0);
    const glm::vec2 dir = glm::normalize(glm::vec2(dx, 0.5f * dy));
    const float t = std::min((left + pw - anchor.x) / dir.x, (top + ph - anchor.y) / std::max(dir.y, 1e-6f));
    draw_line(img, anchor, anchor + t * dir, grey, 2, 8);
    const std::string s = "SLOPE -0.5";
    draw_text(img, legend_x, 12, s, grey, 2);
  }
  return img;
}

}  // namespace plumage
