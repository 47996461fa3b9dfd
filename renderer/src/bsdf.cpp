#include "plumage/renderer/bsdf.h"

#include "plumage/common/image.h"

namespace plumage {

void Bsdf::estimate_weights(const LightProxies& lp, float* w) const {
  float pdf;
  for (std::size_t i = 0; i < lp.size(); ++i) w[i] = luminance(lp.strength(i) * f_cos(lp.wi(i), &pdf));
}

}  // namespace plumage
