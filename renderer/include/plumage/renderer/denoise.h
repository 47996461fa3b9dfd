#pragma once
// Non-local-means filtering of a render by its own per-pixel variance (Rousselle,
// Knaus and Zwicker 2012, "Adaptive rendering with non-local means filtering",
// ACM TOG 31(6) 195, §4): each pixel becomes a weighted mean of the pixels in a
// window around it, a neighbour weighing exp(-max(0, d)) with d the mean over a
// small patch and the channels of
//
//   d_c(p, q) = [(u_p - u_q)^2 - alpha (V_p + min(V_p, V_q))] / [eps + k^2 (V_p + V_q)]
//
// u the noisy colours and V the variances of their means: the difference two
// pixels' noise alone would make is taken out, so a neighbour counts in proportion
// to how far its true colour can be from the pixel's, in units of the noise.
// Where the noise is 0 only equal patches mix, so a converged render is returned
// as it is. Biased (it trades noise for a blur of what differs by less than the
// noise): off in `render` and `compare`, on in `photo-to-feather`; measured in
// docs/rendering.md, "Denoising".
#include "plumage/common/image.h"

namespace plumage {

struct DenoiseSettings {
  int radius = 5;        // window: (2 radius + 1)^2 neighbours
  int patch = 1;         // patch: (2 patch + 1)^2 pixels
  float k = 0.7f;        // the weights' width in units of the noise (docs/rendering.md, "Denoising")
  float alpha = 1.0f;    // how much of the noise difference is taken out
  int threads = 0;       // 0 = all cores
};

// Throws plumage::Error unless radius and patch are 0..16, k > 0, alpha >= 0 (finite).
void validate(const DenoiseSettings& s);

// `colour` RGB (3 channels or more; the first three are filtered, others copied),
// `variance` the same size with each channel's variance of the pixel's mean (a
// render's, Film::developed_variance). Non-finite values in either count as
// unknown: such a pixel keeps its own colour and lends none. Throws plumage::Error
// for mismatched sizes or fewer than 3 channels.
Image denoise(const Image& colour, const Image& variance, const DenoiseSettings& s = {});

}  // namespace plumage
