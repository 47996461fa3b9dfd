// Non-local-means filtering by the render's own variance (denoise.h).
//
// For every offset o of the window, each pixel's distance to its neighbour at o is
// the patch mean of the per-pixel term d_c (a box filter over the patch), so the
// cost is (window) x (pixels) x (a few operations) whatever the patch size. Rows
// are filtered in bands in parallel; a band reads the patch rows around it.
#include "plumage/renderer/denoise.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "plumage/common/error.h"
#include "plumage/common/finite.h"

namespace plumage {

void validate(const DenoiseSettings& s) {
  if (s.radius < 0 || s.radius > 16) throw Error("denoise radius " + std::to_string(s.radius) + " is not within 0-16");
  if (s.patch < 0 || s.patch > 16) throw Error("denoise patch " + std::to_string(s.patch) + " is not within 0-16");
  if (!(s.k > 0) || !std::isfinite(s.k)) throw Error("denoise k must be a positive number");
  if (!(s.alpha >= 0) || !std::isfinite(s.alpha)) throw Error("denoise alpha must be 0 or more");
  if (s.threads < 0) throw Error("denoise threads must be 0 (all cores) or more");
}

Image denoise(const Image& colour, const Image& variance, const DenoiseSettings& s) {
  validate(s);
  if (colour.channels < 3) throw Error("denoise needs an RGB image");
  if (variance.width != colour.width || variance.height != colour.height || variance.channels < 3)
    throw Error("denoise: the variance image is " + std::to_string(variance.width) + "x" +
                std::to_string(variance.height) + " with " + std::to_string(variance.channels) +
                " channels, the colour " + std::to_string(colour.width) + "x" + std::to_string(colour.height));
  const int W = colour.width, H = colour.height, R = s.radius, F = s.patch;
  Image out = colour;
  if (W == 0 || H == 0 || R == 0) return out;
  // A pixel is usable when its colour and variance are finite and the variance >= 0.
  std::vector<unsigned char> ok(std::size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float* c = colour.at(x, y);
      const float* v = variance.at(x, y);
      ok[std::size_t(y) * W + x] = all_finite(glm::vec3(c[0], c[1], c[2])) && all_finite(glm::vec3(v[0], v[1], v[2])) &&
                                    v[0] >= 0 && v[1] >= 0 && v[2] >= 0;
    }
  const float k2 = s.k * s.k, alpha = s.alpha;
  constexpr float kEps = 1e-10f;
  constexpr int kBand = 16;
  const int bands = (H + kBand - 1) / kBand;
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, bands), [&](const tbb::blocked_range<int>& r) {
      for (int band = r.begin(); band != r.end(); ++band) {
        const int y0 = band * kBand, y1 = std::min(H, y0 + kBand);
        // Rows of d needed: the band and F rows on each side (clamped to the image).
        const int d0 = std::max(0, y0 - F), d1 = std::min(H, y1 + F);
        const int DH = d1 - d0;
        std::vector<float> d(std::size_t(W) * DH), row_box(std::size_t(W) * DH);
        std::vector<glm::dvec3> sum(std::size_t(W) * (y1 - y0), glm::dvec3(0));
        std::vector<double> wsum(std::size_t(W) * (y1 - y0), 0.0);
        for (int oy = -R; oy <= R; ++oy)
          for (int ox = -R; ox <= R; ++ox) {
            // d per pixel p = (x, y) against q = p + o; +inf where either is unusable
            // or q is outside the image.
            for (int y = d0; y < d1; ++y)
              for (int x = 0; x < W; ++x) {
                const int qx = x + ox, qy = y + oy;
                float& dd = d[std::size_t(y - d0) * W + x];
                if (qx < 0 || qx >= W || qy < 0 || qy >= H || !ok[std::size_t(y) * W + x] ||
                    !ok[std::size_t(qy) * W + qx]) {
                  dd = INFINITY;
                  continue;
                }
                const float* up = colour.at(x, y);
                const float* uq = colour.at(qx, qy);
                const float* vp = variance.at(x, y);
                const float* vq = variance.at(qx, qy);
                float t = 0;
                for (int c = 0; c < 3; ++c) {
                  const float diff = up[c] - uq[c];
                  t += (diff * diff - alpha * (vp[c] + std::min(vp[c], vq[c]))) / (kEps + k2 * (vp[c] + vq[c]));
                }
                dd = std::isnan(t) ? INFINITY : t / 3;  // inf - inf from extreme values: no weight
              }
            // The patch mean of d: a box over x, then over y (pixels outside the
            // image are left out of the patch, not counted as far).
            for (int y = 0; y < DH; ++y) {
              const float* src = &d[std::size_t(y) * W];
              float* dst = &row_box[std::size_t(y) * W];
              for (int x = 0; x < W; ++x) {
                float acc = 0;
                int n = 0;
                for (int j = std::max(0, x - F); j <= std::min(W - 1, x + F); ++j, ++n) acc += src[j];
                dst[x] = acc / float(n);
              }
            }
            for (int y = y0; y < y1; ++y)
              for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y - y0) * W + x;
                if (!ok[std::size_t(y) * W + x]) continue;
                const int qx = x + ox, qy = y + oy;
                if (qx < 0 || qx >= W || qy < 0 || qy >= H || !ok[std::size_t(qy) * W + qx]) continue;
                float acc = 0;
                int n = 0;
                for (int j = std::max(d0, y - F); j <= std::min(d1 - 1, y + F); ++j, ++n)
                  acc += row_box[std::size_t(j - d0) * W + x];
                const float dist = acc / float(n);
                // exp(-max(0, dist)); an infinite distance (an unusable pixel in the
                // patch) weighs 0, and the pixel itself always weighs 1.
                const double w = (ox == 0 && oy == 0) ? 1.0 : (dist <= 0 ? 1.0 : std::exp(-double(dist)));
                if (!(w > 0)) continue;
                const float* uq = colour.at(qx, qy);
                sum[i] += w * glm::dvec3(uq[0], uq[1], uq[2]);
                wsum[i] += w;
              }
          }
        for (int y = y0; y < y1; ++y)
          for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y - y0) * W + x;
            if (!ok[std::size_t(y) * W + x] || !(wsum[i] > 0)) continue;
            const glm::dvec3 c = sum[i] / wsum[i];
            float* o = out.at(x, y);
            o[0] = float(c.x);
            o[1] = float(c.y);
            o[2] = float(c.z);
          }
      }
    });
  });
  return out;
}

}  // namespace plumage
