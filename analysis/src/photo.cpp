// Loading a photo for analysis: decoded by read_image (common/image.h), any bit
// depth and channel layout to 8-bit BGR, with a memory guard before decoding and
// a downscale above a pixel budget.
#include <cmath>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "photo.h"
#include "luma.h"

namespace plumage::analysis {
namespace fs = std::filesystem;

namespace {
std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
         p[3];
}
std::uint32_t be16(const unsigned char* p) { return (std::uint32_t(p[0]) << 8) | p[1]; }

// A transparent photo is put on a backdrop that contrasts with what is opaque,
// so a white feather on transparency is seen on black and vice versa.
cv::Mat composite_alpha(const cv::Mat& bgra) {
  std::vector<cv::Mat> ch;
  cv::split(bgra, ch);
  const cv::Scalar opaque_mean = cv::mean(bgra, ch[3] > 127);
  const double luma = luma_bgr(opaque_mean);
  const double backdrop = luma > 127 ? 0.0 : 255.0;
  cv::Mat a;
  ch[3].convertTo(a, CV_32F, 1.0 / 255.0);
  cv::Mat out;
  std::vector<cv::Mat> rgb(3);
  for (int c = 0; c < 3; ++c) {
    cv::Mat f;
    ch[c].convertTo(f, CV_32F);
    f = f.mul(a) + backdrop * (1.0 - a);
    f.convertTo(rgb[c], CV_8U);
  }
  cv::merge(rgb, out);
  return out;
}
// The decoded image as OpenCV holds a photo: 8 or 16-bit codes (or float as
// stored), colour in BGR order, grey with alpha as BGRA.
cv::Mat to_mat(const Image& img, const ImageSource& source) {
  const int n = img.channels;
  const int out_channels = n == 2 ? 4 : n;
  const int depth = source.is_float ? CV_32F : source.bits > 8 ? CV_16U : CV_8U;
  cv::Mat m = cv::Mat::zeros(img.height, img.width, CV_MAKETYPE(depth, out_channels));
  const float scale = source.bits > 8 ? 65535.0f : 255.0f;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float* p = img.at(x, y);
      float v[4];
      if (n == 2) {
        v[0] = v[1] = v[2] = p[0];
        v[3] = p[1];
      } else if (n >= 3) {
        for (int c = 0; c < std::min(n, 4); ++c) v[c] = p[c];
        std::swap(v[0], v[2]);  // RGB -> BGR
      } else {
        v[0] = p[0];
      }
      for (int c = 0; c < std::min(out_channels, 4); ++c) {
        if (depth == CV_32F)
          m.ptr<float>(y)[x * out_channels + c] = v[c];
        else if (depth == CV_16U)
          m.ptr<std::uint16_t>(y)[x * out_channels + c] = std::uint16_t(std::lround(v[c] * scale));
        else
          m.ptr<std::uint8_t>(y)[x * out_channels + c] = std::uint8_t(std::lround(v[c] * scale));
      }
    }
  return m;
}
}  // namespace

cv::Size peek_image_size(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> b(1 << 20);
  in.read(reinterpret_cast<char*>(b.data()), std::streamsize(b.size()));
  b.resize(std::size_t(in.gcount()));
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 24 && std::equal(png, png + 8, b.begin()))
    return {int(std::min<std::uint32_t>(be32(&b[16]), 1u << 30)),
            int(std::min<std::uint32_t>(be32(&b[20]), 1u << 30))};
  if (b.size() >= 4 && b[0] == 0xFF && b[1] == 0xD8) {
    std::size_t i = 2;
    while (i + 9 < b.size()) {
      if (b[i] != 0xFF) {
        ++i;
        continue;
      }
      const unsigned m = b[i + 1];
      if (m == 0xFF) {
        ++i;
        continue;
      }
      const bool sof = (m >= 0xC0 && m <= 0xCF) && m != 0xC4 && m != 0xC8 && m != 0xCC;
      if (sof) return {int(be16(&b[i + 7])), int(be16(&b[i + 5]))};
      if (m == 0xD8 || (m >= 0xD0 && m <= 0xD7) || m == 0x01) {
        i += 2;
        continue;
      }
      i += 2 + be16(&b[i + 2]);
    }
  }
  return {0, 0};
}

Photo load_photo(const fs::path& path, double max_megapixels, double refuse_megapixels) {
  const Location where{path.string()};
  if (check_input_file(path, "a photo") == 0)
    throw Error(where, "empty file, not an image; give a PNG or JPEG photo");
  const cv::Size header = peek_image_size(path);
  const double header_mp = double(header.width) * header.height / 1e6;
  if (header_mp > refuse_megapixels) {
    std::ostringstream m;
    m << "image is " << header.width << "x" << header.height << " (" << std::lround(header_mp)
      << " megapixels), above the " << refuse_megapixels
      << " MP memory guard; downscale it first (e.g. to 16 MP)";
    throw Error(where, m.str());
  }
  if (const std::string cut = damage_of(path); !cut.empty())
    throw Error(where, cut + "; copy or export the photo again");
  // Decoded by the project's one image reader (common/image.h), codes unlinearised:
  // 8-bit codes k come back as k/255, 16-bit as k/65535, float as stored.
  ImageSource source;
  Image decoded;
  try {
    decoded = read_image(path, false, refuse_megapixels, &source);
  } catch (const Error& e) {
    if (e.message().find("megapixel") != std::string::npos) throw;
    const std::string unreadable = "cannot read as an image";
    std::string why = e.message();
    if (why.rfind(unreadable, 0) == 0) {
      why = why.substr(why.size() > unreadable.size() + 2 ? unreadable.size() + 2 : why.size());
      why = "not an image (or it is damaged" + (why.empty() ? "" : ": " + why) + ")";
    }
    throw Error(where, why + "; give a PNG, JPEG or TIFF photo");
  }
  const cv::Mat raw = to_mat(decoded, source);
  Photo photo;
  photo.full_width = raw.cols;
  photo.full_height = raw.rows;
  if (raw.cols < 16 || raw.rows < 16)
    throw Error(where, "image is only " + std::to_string(raw.cols) + "x" +
                           std::to_string(raw.rows) + " pixels; a feather needs at least 16x16");

  cv::Mat img8;
  switch (raw.depth()) {
    case CV_8U:
      img8 = raw;
      break;
    case CV_16U:
      raw.convertTo(img8, CV_8U, 1.0 / 257.0);
      photo.notes.push_back("16-bit input reduced to 8 bits");
      break;
    case CV_32F:
    case CV_64F:
      raw.convertTo(img8, CV_8U, 255.0);
      photo.notes.push_back("float input taken as [0,1]");
      break;
    default:
      raw.convertTo(img8, CV_8U);
      break;
  }
  switch (img8.channels()) {
    case 1:
      cv::cvtColor(img8, photo.bgr, cv::COLOR_GRAY2BGR);
      break;
    case 3:
      photo.bgr = img8;
      break;
    case 4:
      photo.bgr = composite_alpha(img8);
      photo.notes.push_back("alpha composited on a contrasting backdrop");
      break;
    default:
      throw Error(where, "unsupported channel count " + std::to_string(img8.channels()));
  }
  const double mp = double(photo.bgr.total()) / 1e6;
  if (mp > max_megapixels) {
    photo.downscale = std::sqrt(max_megapixels / mp);
    cv::Mat small;
    cv::resize(photo.bgr, small, cv::Size(), photo.downscale, photo.downscale, cv::INTER_AREA);
    photo.downscale = double(small.cols) / photo.full_width;
    photo.bgr = small;
    std::ostringstream m;
    m << "analysed at " << small.cols << "x" << small.rows << " (above " << max_megapixels
      << " MP)";
    photo.notes.push_back(m.str());
  }
  return photo;
}

}  // namespace plumage::analysis
