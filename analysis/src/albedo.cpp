// Albedo texture in feather coordinates: the photo resampled on a grid of
// feather millimetres (tip up), the shaft painted out from the vane around it,
// and on a light backdrop divided by the backdrop colour (white paper = 1).
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>
#include <opencv2/imgproc.hpp>

#include "plumage/common/feather.h"
#include "plumage/common/image.h"
#include "albedo.h"
#include "plumage/layout/layout.h"
#include "segmentation.h"

namespace plumage::analysis {
namespace {
constexpr int kShaftStations = 16;          // the shaft's colour along it (AlbedoTexture::shaft_rgb)
constexpr std::size_t kMinStationTexels = 4;  // fewer: the station takes its nearest neighbour's colour
}  // namespace

AlbedoResult extract_albedo(const cv::Mat& bgr, const Component& f, const glm::dmat3x2& img_from_f,
                            const BSpline2& shaft_mm, double shaft_width_mm, double mm_per_px,
                            bool light_background, const cv::Vec3d& bg) {
  const glm::dmat3x2 f_from_img = [&] {
    const glm::dmat2 L(img_from_f[0], img_from_f[1]);
    const glm::dmat2 Li = glm::inverse(L);
    return glm::dmat3x2(Li[0], Li[1], -(Li * img_from_f[2]));
  }();
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const cv::Point& p : f.contour) {
    const glm::dvec2 q = apply(f_from_img, glm::dvec2(p.x, p.y));
    lo = glm::min(lo, q), hi = glm::max(hi, q);
  }
  double tau = mm_per_px;  // one texel per working pixel
  const double span = std::max(hi.x - lo.x, hi.y - lo.y) + 4 * tau;
  if (span / tau > 4096) tau = span / 4096;
  AlbedoResult out;
  out.mm_per_texel = tau;
  out.origin_mm = {lo.x - 2 * tau, hi.y + 2 * tau};
  const int W = int(std::ceil((hi.x - lo.x) / tau)) + 4,
            H = int(std::ceil((hi.y - lo.y) / tau)) + 4;

  // Texel (i, j) -> feather (x0 + i tau, y1 - j tau) -> image: one affine map
  // (texel centres at +0.5 are matched by warpAffine's pixel-centre convention).
  const glm::dvec2 ox = img_from_f[0] * tau, oy = -img_from_f[1] * tau;
  const glm::dvec2 o0 = apply(img_from_f, out.origin_mm + glm::dvec2(0.5 * tau, -0.5 * tau));
  const cv::Matx23d T(ox.x, oy.x, o0.x, ox.y, oy.y, o0.y);
  const cv::Matx23d Tm(ox.x, oy.x, o0.x - f.bbox.x, ox.y, oy.y, o0.y - f.bbox.y);
  cv::Mat tex, mask;
  cv::warpAffine(bgr, tex, T, cv::Size(W, H), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REPLICATE);
  cv::warpAffine(f.mask, mask, Tm, cv::Size(W, H), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP);

  // The shaft is modelled as its own curve, so its colour must not stay in the vane texture.
  // It is painted out as wide as the generated rachis is there: the measured width (the
  // bare quill's) at the base, narrowing as the builder narrows it toward the tip
  // (rachis_width_fraction); a stripe of the quill's width all the way up would paint out
  // a narrow vane to its edge.
  cv::Mat shaft_mask = cv::Mat::zeros(H, W, CV_8U);
  constexpr int kSegments = 200;
  const double base_px = shaft_width_mm / tau;
  const auto texel = [&](double u) {
    const glm::dvec2 q = shaft_mm.eval(u);
    return cv::Point(int(std::lround((q.x - out.origin_mm.x) / tau - 0.5)),
                     int(std::lround((out.origin_mm.y - q.y) / tau - 0.5)));
  };
  int th = 1;
  for (int i = 0; i < kSegments; ++i) {
    const int w = std::max(1, int(std::lround(base_px * rachis_width_fraction((i + 0.5) / kSegments)))) + 2;
    th = std::max(th, w);
    cv::line(shaft_mask, texel(double(i) / kSegments), texel(double(i + 1) / kSegments), cv::Scalar(255), w);
  }
  shaft_mask &= mask;
  // The rachis's own colour, before it is painted out, at kShaftStations stations
  // along it (a white quill below a dark rachis, say): per station, the per-channel
  // median of the middle third of the band (its edges blur into the vane) over the
  // station's length of the shaft, texels wholly inside the feather. A station
  // that too few texels show takes the nearest one's colour; with none shown, or
  // fewer than 8 texels in all, the shaft has no colour of its own. Linear, over
  // the paper on a light backdrop.
  {
    // Arc length along the shaft at each segment's end, for the stations.
    std::vector<double> arc(kSegments + 1, 0.0);
    for (int i = 0; i < kSegments; ++i)
      arc[std::size_t(i) + 1] = arc[std::size_t(i)] + glm::length(shaft_mm.eval(double(i + 1) / kSegments) -
                                                                  shaft_mm.eval(double(i) / kSegments));
    cv::Mat station = cv::Mat::zeros(H, W, CV_8U), inside;  // 1 + station index; 0 off the core
    for (int i = 0; i < kSegments; ++i) {
      const double mid = 0.5 * (arc[std::size_t(i)] + arc[std::size_t(i) + 1]) / std::max(arc.back(), 1e-12);
      const int k = std::min(kShaftStations - 1, int(mid * kShaftStations));
      const int w = std::max(1, int(std::lround(base_px * rachis_width_fraction((i + 0.5) / kSegments)) / 3));
      cv::line(station, texel(double(i) / kSegments), texel(double(i + 1) / kSegments), cv::Scalar(k + 1), w);
    }
    cv::erode(mask == 255, inside, cv::Mat());
    std::vector<float> ch[kShaftStations][3];
    std::size_t total = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (const int k = station.at<uchar>(y, x); k > 0 && inside.at<uchar>(y, x)) {
          const cv::Vec3b p = tex.at<cv::Vec3b>(y, x);
          for (int c = 0; c < 3; ++c) ch[k - 1][c].push_back(srgb_to_linear(p[2 - c] / 255.0f));
          ++total;
        }
    std::vector<std::optional<glm::dvec3>> seen(kShaftStations);
    for (int k = 0; k < kShaftStations; ++k) {
      if (ch[k][0].size() < kMinStationTexels) continue;
      glm::dvec3 rgb;
      for (int c = 0; c < 3; ++c) {
        std::vector<float>& v = ch[k][c];
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
        const double paper = light_background ? std::max(double(srgb_to_linear(float(bg[2 - c]) / 255.0f)), 1e-3) : 1.0;
        rgb[c] = std::min(double(v[v.size() / 2]) / paper, kMaxAlbedoScale);
      }
      seen[std::size_t(k)] = rgb;
    }
    if (total >= 8 && std::any_of(seen.begin(), seen.end(), [](const auto& c) { return c.has_value(); })) {
      for (int k = 0; k < kShaftStations; ++k) {
        int best = -1;
        for (int j = 0; j < kShaftStations; ++j)
          if (seen[std::size_t(j)] && (best < 0 || std::abs(j - k) < std::abs(best - k))) best = j;
        out.shaft_rgb.push_back(*seen[std::size_t(best)]);
      }
    }
  }
  // Fill from the vane either side (normalised convolution over valid texels).
  const double sigma = std::max(1.0, 0.75 * th);
  const cv::Rect strip = [&] {
    const int m = int(std::ceil(3 * sigma)) + 1;
    const cv::Rect r = cv::boundingRect(shaft_mask);
    return cv::Rect(r.x - m, r.y - m, r.width + 2 * m, r.height + 2 * m) & cv::Rect(0, 0, W, H);
  }();
  if (strip.area() > 0) {
    const cv::Mat sm = shaft_mask(strip);
    cv::Mat t = tex(strip);
    // Only texels wholly inside the feather fill it: an edge texel is part card.
    cv::Mat inside;
    cv::erode(mask == 255, inside, cv::Mat());
    cv::Mat valid = inside(strip) & ~sm, vf, tf, num, den;
    valid.convertTo(vf, CV_32F, 1.0 / 255.0);
    t.convertTo(tf, CV_32FC3);
    std::vector<cv::Mat> ch;
    cv::split(tf, ch);
    for (auto& c : ch) c = c.mul(vf);
    cv::merge(ch, num);
    cv::GaussianBlur(num, num, cv::Size(), sigma);
    cv::GaussianBlur(vf, den, cv::Size(), sigma);
    for (int y = 0; y < t.rows; ++y)
      for (int x = 0; x < t.cols; ++x)
        if (sm.at<uchar>(y, x) && den.at<float>(y, x) > 1e-3f) {
          const cv::Vec3f v = num.at<cv::Vec3f>(y, x) / den.at<float>(y, x);
          t.at<cv::Vec3b>(y, x) =
              cv::Vec3b(cv::saturate_cast<uchar>(v[0]), cv::saturate_cast<uchar>(v[1]),
                        cv::saturate_cast<uchar>(v[2]));
        }
  }

  float lut[256], inv_bg[3];
  for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(i / 255.0f);
  for (int c = 0; c < 3; ++c)
    inv_bg[c] =
        light_background ? 1.0f / std::max(srgb_to_linear(float(bg[2 - c]) / 255.0f), 1e-3f) : 1.0f;
  // On a light backdrop a feather paler than the paper has texels above 1: the
  // texture holds them divided by `scale`, the 99th percentile of the feather's
  // brightest channel (so a glint on the quill does not set it), at most
  // kMaxAlbedoScale; 1 when the feather is not paler than the paper.
  if (light_background) {
    std::vector<float> tops;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (mask.at<uchar>(y, x) == 255) {
          const cv::Vec3b p = tex.at<cv::Vec3b>(y, x);
          tops.push_back(std::max({lut[p[2]] * inv_bg[0], lut[p[1]] * inv_bg[1], lut[p[0]] * inv_bg[2]}));
        }
    if (!tops.empty()) {
      const std::size_t k = tops.size() * 99 / 100;
      std::nth_element(tops.begin(), tops.begin() + k, tops.end());
      out.scale = std::clamp(double(tops[k]), 1.0, kMaxAlbedoScale);
    }
  }
  const float inv_scale = float(1.0 / out.scale);
  out.rgba.create(H, W, CV_32FC4);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const cv::Vec3b p = tex.at<cv::Vec3b>(y, x);
      cv::Vec4f& q = out.rgba.at<cv::Vec4f>(y, x);
      for (int c = 0; c < 3; ++c) q[c] = std::min(lut[p[2 - c]] * inv_bg[c] * inv_scale, 1.0f);  // BGR -> RGB
      q[3] = mask.at<uchar>(y, x) / 255.0f;
    }
  return out;
}

}  // namespace plumage::analysis
