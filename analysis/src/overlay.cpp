// The overlay a person checks the analysis with: outline, shaft (calamus dot,
// tip arrow), barb directions per side, labels with lengths, and a scale bar.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "label_placement.h"
#include "plumage/common/constants.h"
#include "plumage/layout/rules.h"
#include "overlay.h"
#include "grid_scale.h"
#include "vane.h"

namespace plumage::analysis {
namespace {

void label(cv::Mat& img, const std::string& text, cv::Point at, double scale,
           const cv::Scalar& colour) {
  const int th = std::max(1, int(std::lround(scale * 1.5)));
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), th + 2,
              cv::LINE_AA);
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, th, cv::LINE_AA);
}

// The overlay is at most this many pixels wide or tall: enough to check by eye.
constexpr int kMaxSide = 2048;

// A label with the box LabelPlacer gave it and the point it names.
struct PlacedLabel {
  std::string text;
  LabelBox box;
  std::vector<cv::Point> anchors;  // points of the feather it may name (tip, calamus, ...)
  cv::Scalar colour;
  int ascent = 0;  // text height above the baseline
};

// Places `text` at the first of `corners` (top-left corners of its box) where it
// covers no label placed before it (LabelPlacer), then at boxes ever farther from
// the first of `anchors` (the points of the feather it names).
PlacedLabel place_label(LabelPlacer& placer, std::string text, std::vector<std::pair<int, int>> corners,
                        std::vector<cv::Point> anchors, double font, int th, const cv::Scalar& colour) {
  const cv::Point anchor = anchors.front();
  int base = 0;
  const cv::Size ts = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, font, th, &base);
  const cv::Size box(ts.width + 4, ts.height + base + 4);
  for (int ring = 1; ring <= 8; ++ring)
    for (int k = 0; k < 8; ++k) {
      const double a = k * kPi / 4;
      const double dx = std::cos(a) * (0.5 * box.width + ring * box.height);
      const double dy = std::sin(a) * (0.5 * box.height + ring * box.height);
      corners.push_back({int(std::lround(anchor.x + dx - 0.5 * box.width)),
                         int(std::lround(anchor.y + dy - 0.5 * box.height))});
    }
  return {std::move(text), placer.place(box.width, box.height, corners), std::move(anchors), colour, ts.height};
}

// Draws the labels over everything else: first a thin line from each label that
// lies more than its height away from every one of its anchors to the nearest,
// then all the texts.
void draw_labels(cv::Mat& img, const std::vector<PlacedLabel>& labels, double font, int th) {
  for (const PlacedLabel& l : labels) {
    const LabelBox& b = l.box;
    cv::Point from, to;
    long least = -1;
    for (const cv::Point& a : l.anchors) {
      const cv::Point near(std::clamp(a.x, b.x, b.x + b.width), std::clamp(a.y, b.y, b.y + b.height));
      const long d2 = long(near.x - a.x) * (near.x - a.x) + long(near.y - a.y) * (near.y - a.y);
      if (least < 0 || d2 < least) least = d2, from = near, to = a;
    }
    if (least <= long(b.height) * b.height) continue;
    cv::line(img, from, to, cv::Scalar(0, 0, 0), th + 2, cv::LINE_AA);
    cv::line(img, from, to, l.colour, std::max(1, th / 2), cv::LINE_AA);
  }
  for (const PlacedLabel& l : labels)
    label(img, l.text, cv::Point(l.box.x + 2, l.box.y + 2 + l.ascent), font, l.colour);
}

// Top-left corners of a w x h box beside `a`: above, below, right of and left of
// it, `gap` pixels away.
void corners_around(std::vector<std::pair<int, int>>& out, cv::Point a, cv::Size box, int gap) {
  out.insert(out.end(), {{a.x - box.width / 2, a.y - box.height - gap},
                         {a.x - box.width / 2, a.y + gap},
                         {a.x + gap, a.y - box.height / 2},
                         {a.x - box.width - gap, a.y - box.height / 2}});
}

}  // namespace

cv::Mat draw_overlay(const cv::Mat& bgr, const std::vector<OverlayFeather>& feathers,
                     const std::vector<OverlaySkipped>& skipped, double mm_per_px,
                     const LayoutScale& scale, const GridScale& grid, const cv::Mat& busy) {
  cv::Mat img;
  const double g_k = std::min(1.0, double(kMaxSide) / std::max(bgr.cols, bgr.rows));
  const auto px = [g_k](const glm::dvec2& p) {  // working pixels to overlay pixels
    return cv::Point(int(std::lround(g_k * p.x)), int(std::lround(g_k * p.y)));
  };
  if (g_k < 1.0)
    cv::resize(bgr, img, cv::Size(), g_k, g_k, cv::INTER_AREA);
  else
    img = bgr.clone();
  mm_per_px /= g_k;
  const double dim = std::max(img.cols, img.rows);
  const int th = std::max(1, int(std::lround(dim / 900)));
  const double font = std::max(0.4, dim / 2000);
  const cv::Scalar green(60, 220, 60), red(40, 40, 255), yellow(0, 230, 255), cyan(255, 230, 0),
      blue(255, 120, 0), white(255, 255, 255), grey(150, 150, 150), magenta(255, 60, 255);
  // Scale bar: a round number of millimetres near a tenth of the width.
  const double target_mm = 0.12 * img.cols * mm_per_px;
  double bar_mm = 1;
  for (double c : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0})
    if (c <= target_mm) bar_mm = c;
  const int bar_px = int(std::lround(bar_mm / mm_per_px));
  // Put the bar in the emptiest corner.
  const cv::Size box(std::min(img.cols, std::max(bar_px, 30 * th) + 20 * th),
                     std::min(img.rows, 24 * th + 20));
  cv::Point p0;
  double least = 1e300;
  for (int cy : {0, 1})
    for (int cx : {0, 1}) {
      const cv::Rect r(cx ? img.cols - box.width : 0, cy ? img.rows - box.height : 0, box.width,
                       box.height);
      const cv::Rect rb(int(r.x / g_k), int(r.y / g_k), int(r.width / g_k), int(r.height / g_k));
      const double m =
          busy.empty() ? 0.0 : cv::mean(busy(rb & cv::Rect(0, 0, busy.cols, busy.rows)))[0];
      if (m < least - 1e-9) least = m, p0 = cv::Point(r.x + 10 * th, r.y + r.height - 6 * th);
    }
  std::ostringstream bar_text;
  bar_text << bar_mm << " mm (" << to_string(scale.source);
  if (grid.found)
    bar_text << ", " << std::fixed << std::setprecision(1) << grid.period_px << " px = "
             << scale.grid_mm << " mm";
  if (scale.source == ScaleSource::Default) bar_text << ", unknown scale";
  bar_text << ")";
  const cv::Point bar_text_at = p0 + cv::Point(0, -6 * th - 6);
  int bar_base = 0;
  const cv::Size bar_ts =
      cv::getTextSize(bar_text.str(), cv::FONT_HERSHEY_SIMPLEX, font, th, &bar_base);
  // Labels go where no other label is; the scale bar and its text are kept clear.
  LabelPlacer placer(img.cols, img.rows);
  std::vector<PlacedLabel> labels;
  const int bar_top = bar_text_at.y - bar_ts.height - 4;
  placer.reserve(LabelBox{p0.x - 4, bar_top, std::max(bar_px, bar_ts.width) + 8, p0.y + 4 - bar_top});
  for (const OverlayFeather& f : feathers) {
    std::vector<cv::Point> outline;
    for (const cv::Point& p : f.contour) outline.push_back(px(glm::dvec2(p.x, p.y)));
    cv::polylines(img, outline, true, f.touches_border ? red : green, th, cv::LINE_AA);
    std::vector<cv::Point> sh;
    for (int i = 0; i <= 100; ++i) sh.push_back(px(f.shaft_px.eval(i / 100.0)));
    cv::polylines(img, sh, false, red, th + 1, cv::LINE_AA);
    cv::circle(img, sh.front(), 3 * th + 2, blue, cv::FILLED, cv::LINE_AA);
    const glm::dvec2 tip = f.shaft_px.eval(1.0), dir = glm::normalize(f.shaft_px.deriv(1.0));
    cv::arrowedLine(img, px(tip - dir * (12.0 * th / g_k)), px(tip + dir * (4.0 * th / g_k)), red,
                    th + 1, cv::LINE_AA, 0, 0.5);
    // Barb directions at the middle of each side's vane: trusted readings
    // (confidence >= kLayoutMinConfidence) long and in the side's colour, the
    // rest short and grey (layout -> params takes those from their neighbours).
    for (std::size_t k = 0; k < f.vanes.t.size(); ++k) {
      const double t = f.vanes.t[k];
      const glm::dvec2 C = f.shaft_px.eval(t), T = glm::normalize(f.shaft_px.deriv(t));
      const glm::dvec2 N(-T.y, T.x);
      for (int side : {-1, +1}) {
        const SideMeasure& S = side < 0 ? f.vanes.left : f.vanes.right;
        const double w = S.width_px[k];
        if (w < 4) continue;
        const double a = S.angle_deg[k] * kPi / 180.0;
        const glm::dvec2 b = T * std::cos(a) + N * (side * std::sin(a));
        const glm::dvec2 m = C + N * (side * 0.5 * w);
        if (k < S.downy.size() && S.downy[k]) {  // the downy base: a dot, no barb direction
          cv::circle(img, px(m), 2 * th, magenta, cv::FILLED, cv::LINE_AA);
          continue;
        }
        const bool trusted = S.angle_conf[k] >= kLayoutMinConfidence;
        const double len = (trusted ? 0.4 : 0.15) * w;
        cv::line(img, px(m - b * (0.5 * len)), px(m + b * (0.5 * len)),
                 trusted ? (side < 0 ? yellow : cyan) : grey, th, cv::LINE_AA);
      }
    }
    // Where each side's downy base ends: a line across that side's vane.
    for (int side : {-1, +1}) {
      const SideMeasure& S = side < 0 ? f.vanes.left : f.vanes.right;
      if (!(S.afterfeather_to_t > 0)) continue;
      const double t = S.afterfeather_to_t;
      const auto near = std::lower_bound(f.vanes.t.begin(), f.vanes.t.end(), t);
      const double w = S.width_px[std::min<std::size_t>(near - f.vanes.t.begin(), f.vanes.t.size() - 1)];
      const glm::dvec2 C = f.shaft_px.eval(t), T = glm::normalize(f.shaft_px.deriv(t));
      const glm::dvec2 N(-T.y, T.x);
      cv::line(img, px(C), px(C + N * (side * w)), magenta, th, cv::LINE_AA);
    }
    std::ostringstream s;
    s << "F" << f.id << " " << std::lround(f.length_mm) << "mm";
    int base = 0;
    const cv::Size ts = cv::getTextSize(s.str(), cv::FONT_HERSHEY_SIMPLEX, font, th, &base);
    const cv::Size lb(ts.width + 4, ts.height + base + 4);
    // First where a sparse sheet has it (just past the tip), then around the
    // tip, the calamus and the middle of the shaft.
    const cv::Point ahead = px(tip + dir * (10.0 * th / g_k));
    std::vector<std::pair<int, int>> corners{{ahead.x - 20 * th - 2, ahead.y - 4 * th - ts.height - 2}};
    const glm::dvec2 base_dir = glm::normalize(f.shaft_px.deriv(0.0));
    const cv::Point behind = px(f.shaft_px.eval(0.0) - base_dir * (10.0 * th / g_k)),
                    middle = px(f.shaft_px.eval(0.5));
    corners_around(corners, ahead, lb, 2 * th);
    corners_around(corners, behind, lb, 2 * th);
    corners_around(corners, middle, lb, 4 * th);
    labels.push_back(place_label(placer, s.str(), corners, {ahead, behind, middle}, font, th, white));
  }
  // Skipped regions: red when on the border, orange when feathers touch or
  // overlap; the label says which.
  const cv::Scalar orange(0, 140, 255);
  for (const OverlaySkipped& s : skipped) {
    std::vector<cv::Point> outline;
    for (const cv::Point& p : s.contour) outline.push_back(px(glm::dvec2(p.x, p.y)));
    cv::polylines(img, outline, true, s.touches_border ? red : orange, th + 1, cv::LINE_AA);
    const cv::Rect rbox = cv::boundingRect(outline);
    std::string text = "F";  // appended piecewise: "F" + std::to_string trips GCC 12's -Wrestrict
    text += std::to_string(s.id);
    text += s.touches_border ? " skipped: border" : " skipped: touching";
    int base = 0;
    const cv::Size ts = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, font, th, &base);
    const cv::Size lb(ts.width + 4, ts.height + base + 4);
    const cv::Point centre(rbox.x + rbox.width / 2, rbox.y + rbox.height / 2);
    std::vector<std::pair<int, int>> corners{{centre.x - lb.width / 2, centre.y - lb.height / 2}};
    corners_around(corners, centre, lb, lb.height);
    corners_around(corners, cv::Point(centre.x, rbox.y), lb, 2 * th);
    corners_around(corners, cv::Point(centre.x, rbox.y + rbox.height), lb, 2 * th);
    labels.push_back(place_label(placer, text, corners, {centre}, font, th, s.touches_border ? red : orange));
  }
  cv::rectangle(img, p0 + cv::Point(-4, -4 * th - 4), p0 + cv::Point(bar_px + 4, 4),
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::rectangle(img, p0 + cv::Point(0, -4 * th), p0 + cv::Point(bar_px, 0), white, cv::FILLED);
  label(img, bar_text.str(), bar_text_at, font, white);
  draw_labels(img, labels, font, th);
  return img;
}

}  // namespace plumage::analysis
