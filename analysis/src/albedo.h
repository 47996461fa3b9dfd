#pragma once
// The albedo texture in feather coordinates (albedo.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <vector>
#include <glm/glm.hpp>

#include "plumage/common/bspline.h"
#include "segmentation.h"

namespace plumage::analysis {

// Texture in feather coordinates, shaft painted out; linear RGBA.
struct AlbedoResult {
  cv::Mat rgba;  // CV_32FC4 linear, alpha = mask; times `scale` the albedo
  glm::dvec2 origin_mm{0.0};
  double mm_per_texel = 0;
  double scale = 1.0;  // > 1 where the feather is paler than the paper (AlbedoTexture::scale)
  std::vector<glm::dvec3> shaft_rgb;  // the rachis's own colour along it (AlbedoTexture::shaft_rgb)
};
AlbedoResult extract_albedo(const cv::Mat& bgr, const Component& feather,
                            const glm::dmat3x2& image_from_feather_work, const BSpline2& shaft_mm,
                            double shaft_width_mm, double mm_per_work_px, bool light_background,
                            const cv::Vec3d& background_bgr);

}  // namespace plumage::analysis
