// OpenEXR through the OpenEXR library (image_codecs.h): float pixels as stored,
// channels in the order OpenImageIO gives them (channel_key), so an EXR reads the
// same as it did through OpenImageIO.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfTileDescription.h>

#include <algorithm>
#include <cstdint>
#include <climits>
#include <cstring>
#include <exception>
#include <fstream>

#include "image_codecs.h"
#include "plumage/common/error.h"

namespace plumage::codec {
namespace fs = std::filesystem;

namespace {
// The order pixels are returned in: channels without a layer first, then each
// layer ("diffuse.R") in the file's order; within one, colour, luminance and
// alpha first (R, G, B, Y, A), anything else after them in the file's
// (alphabetical) order.
struct ChannelKey {
  std::string layer;
  int rank;
};
ChannelKey channel_key(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  const std::string layer = dot == std::string::npos ? std::string() : name.substr(0, dot);
  const std::string last = dot == std::string::npos ? name : name.substr(dot + 1);
  static const char* const kFirst[] = {"R", "G", "B", "Y", "A"};
  int rank = 5;
  for (int k = 0; k < 5; ++k)
    if (last == kFirst[k]) rank = k;
  return {layer, rank};
}
bool comes_before(const std::string& a, const std::string& b) {
  const ChannelKey ka = channel_key(a), kb = channel_key(b);
  if (ka.layer != kb.layer) return ka.layer < kb.layer;
  return ka.rank < kb.rank;
}

std::string channel_name(int c, int channels) {
  if (channels == 1) return "Y";
  static const char* const kRgba[] = {"R", "G", "B", "A"};
  return c < 4 ? kRgba[c] : "channel" + std::to_string(c);
}

// The sizes the file's (first) header gives, read without opening the file for
// its pixels: OpenEXR takes its line or tile buffers while opening, sized by the
// data window, the channels and the compression's block of lines (256 for DWAB),
// so a file above read_image's limits must be refused before that. Tiles count as
// a block: at most kMaxImageSide on a side and 256 x kMaxImageSide pixels.
Header header_alone(const fs::path& path) {
  const Location where{path.string()};
  Imf::StdIFStream in(path.c_str());
  char start[8];
  in.read(start, sizeof start);
  int version = 0;
  for (int k = 3; k >= 0; --k) version = (version << 8) | static_cast<unsigned char>(start[4 + k]);
  Imf::Header exr;
  exr.readFrom(in, version);
  const Imath::Box2i window = exr.dataWindow();
  Header h;
  h.width = int(std::clamp<std::int64_t>(std::int64_t(window.max.x) - window.min.x + 1, 0, INT32_MAX));
  h.height = int(std::clamp<std::int64_t>(std::int64_t(window.max.y) - window.min.y + 1, 0, INT32_MAX));
  for (auto it = exr.channels().begin(); it != exr.channels().end(); ++it) ++h.channels;
  if (exr.hasTileDescription()) {
    const Imf::TileDescription& t = exr.tileDescription();
    if (t.xSize > unsigned(kMaxImageSide) || t.ySize > unsigned(kMaxImageSide) ||
        std::uint64_t(t.xSize) * t.ySize > 256u * std::uint64_t(kMaxImageSide))
      throw Error(where, "its tiles are " + std::to_string(t.xSize) + "x" + std::to_string(t.ySize) +
                             " pixels, above the limit of a block of image inputs; save it as scanlines");
  }
  return h;
}
}  // namespace

Image read_exr(const fs::path& path, const HeaderCheck& check, Header& header) {
  const Location where{path.string()};
  try {
    check(header_alone(path));
    Imf::InputFile in(path.c_str());
    const Imath::Box2i window = in.header().dataWindow();
    std::vector<std::string> names;
    bool all_uint = true;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        throw Error(where, std::string("channel '") + it.name() + "' is subsampled; save the EXR without subsampling");
      names.emplace_back(it.name());
      all_uint = all_uint && it.channel().type == Imf::UINT;
    }
    std::stable_sort(names.begin(), names.end(), comes_before);
    header.width = int(std::int64_t(window.max.x) - window.min.x + 1);
    header.height = int(std::int64_t(window.max.y) - window.min.y + 1);
    header.channels = int(names.size());
    header.alpha = -1;
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == "A") header.alpha = int(c);
    // 32-bit unsigned samples are integer codes, scaled to [0,1] like PNG's.
    header.is_float = !all_uint;
    header.bits = 32;  // float or uint; 16 when a channel is half
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it)
      if (it.channel().type == Imf::HALF) header.bits = 16;
    if (header.width <= 0 || header.height <= 0 || header.channels <= 0) throw Error(where, "image has no pixels");
    check(header);

    Image img(header.width, header.height, header.channels);
    const std::size_t pixel = sizeof(float) * std::size_t(header.channels);
    const std::size_t row = pixel * std::size_t(header.width);
    // The frame buffer is addressed by absolute pixel coordinates: its origin is
    // moved back by the data window's corner.
    // (In unsigned arithmetic: the moved origin may lie outside the buffer.)
    char* origin = reinterpret_cast<char*>(reinterpret_cast<std::uintptr_t>(img.pixels.data()) -
                                           std::uintptr_t(std::intptr_t(window.min.x)) * pixel -
                                           std::uintptr_t(std::intptr_t(window.min.y)) * row);
    Imf::FrameBuffer frame;
    const Imf::PixelType type = all_uint ? Imf::UINT : Imf::FLOAT;  // both 4 bytes
    for (std::size_t c = 0; c < names.size(); ++c)
      frame.insert(names[c], Imf::Slice(type, origin + sizeof(float) * c, pixel, row));
    in.setFrameBuffer(frame);
    in.readPixels(window.min.y, window.max.y);
    if (all_uint)
      for (float& v : img.pixels) {
        std::uint32_t code;
        std::memcpy(&code, &v, sizeof code);
        v = float(code) * (1.0f / 4294967295.0f);
      }
    return img;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(where, std::string("cannot read as an OpenEXR image: ") + e.what());
  }
}

void write_exr(const fs::path& file, const fs::path& target, const Image& img) {
  try {
    Imf::Header header(img.width, img.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const std::size_t pixel = sizeof(float) * std::size_t(img.channels);
    Imf::FrameBuffer frame;
    char* base = const_cast<char*>(reinterpret_cast<const char*>(img.pixels.data()));
    for (int c = 0; c < img.channels; ++c) {
      const std::string name = channel_name(c, img.channels);
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      frame.insert(name, Imf::Slice(Imf::FLOAT, base + sizeof(float) * std::size_t(c), pixel,
                                    pixel * std::size_t(img.width)));
    }
    // Through our own stream: OpenEXR writes the offset table when the file
    // object is destroyed and drops errors there, so the stream's state is
    // what says whether everything reached the disk.
    std::ofstream os(file, std::ios::binary | std::ios::trunc);
    if (!os) throw Error(Location{target.string()}, "cannot open for writing");
    {
      Imf::StdOFStream stream(os, target.c_str());  // OpenEXR's messages name the file the user asked for
      Imf::OutputFile out(stream, header);
      out.setFrameBuffer(frame);
      out.writePixels(img.height);
    }
    os.close();
    if (!os) throw Error(Location{target.string()}, "write failed (disk full?)");
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(Location{target.string()}, std::string("write failed: ") + e.what());
  }
}

}  // namespace plumage::codec
