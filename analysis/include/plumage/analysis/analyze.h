#pragma once
// Photo analysis (DESIGN §8): a photograph of one feather, or a sheet of several,
// to a Layout plus the images a person checks it with. OpenCV stays inside
// analysis/src; this interface speaks plumage::Image only.
#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "plumage/common/image.h"
#include "plumage/layout/layout.h"

namespace plumage {

struct AnalyzeOptions {
  std::optional<double> mm_per_px;   // given scale (photo pixels); else grid, else default
  double grid_mm = 10.0;             // physical spacing of a grid's lines (Feather Atlas: 20)
  double default_mm_per_px = 0.1;    // used, with low confidence, when nothing else is known
  std::optional<int> feather;        // 1-based; report only this feather
  bool allow_border = false;         // a feather touching the border: skipped unless set
  double max_megapixels = 16.0;      // larger photos are analysed downscaled to this
  double refuse_megapixels = 400.0;  // memory guard: larger photos are refused unread
  int stations = 24;                 // profile samples along the shaft
};

// How deep the frame along a photo's border is from which its card colour is
// read: a scan's outermost rows and columns are often a bright or dark line (the
// scanner's lid, the sheet's cut edge), which a one-pixel ring would take for the
// card; a frame a hundredth of the shorter side deep is mostly card.
inline int border_frame_px(int width, int height) { return std::max(2, std::min(width, height) / 100); }

struct PhotoAnalysis {
  Layout layout;  // albedo files are "featherK.albedo.png" until write_analysis names them
  std::vector<Image> albedo;          // per reported feather: linear RGBA, feather coordinates
  std::vector<Image> masks;           // per reported feather: 1 channel, working resolution
  Image overlay;                      // linear RGB, working resolution
  std::vector<std::string> warnings;  // also stored per feather in the layout
  std::vector<std::pair<std::string, double>> stage_seconds;  // wall time per stage
};

// Throws plumage::Error naming the photo for unreadable input, no feather found,
// an out-of-range --feather, or when the picked region (or every region) is one
// that is otherwise skipped: touching the border (unless allowed) or several
// feathers not told apart. Skipped regions are in layout.skipped and warnings.
PhotoAnalysis analyze_photo(const std::filesystem::path& photo, const AnalyzeOptions& options);

// Writes layout.json, the albedo PNGs next to it (<stem>.feather<K>.albedo.png)
// and the overlay when `overlay` is non-empty, each atomically. If any write
// fails, the files this call already wrote are removed again.
void write_analysis(PhotoAnalysis& analysis, const std::filesystem::path& layout_path,
                    const std::filesystem::path& overlay_path = {});

}  // namespace plumage
