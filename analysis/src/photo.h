#pragma once
// Reading the photo at working resolution (photo.cpp).
// One stage of photo analysis, private to analysis/src: OpenCV types, pixel
// figures in working pixels (the photo after any downscale).
#include <opencv2/core.hpp>
#include <filesystem>
#include <string>
#include <vector>

namespace plumage::analysis {

struct Photo {
  cv::Mat bgr;  // 8-bit BGR, working resolution
  int full_width = 0, full_height = 0;
  double downscale = 1.0;  // working pixels per photo pixel
  std::vector<std::string> notes;
};
// Reads PNG/JPEG/TIFF/PNM..., 8 or 16 bit, grey, grey+alpha, RGB, RGBA.
Photo load_photo(const std::filesystem::path& path, double max_megapixels,
                 double refuse_megapixels);
// Width and height from a PNG or JPEG header without decoding; {0,0} if unknown.
cv::Size peek_image_size(const std::filesystem::path& path);

}  // namespace plumage::analysis
