// `plumage merge`: the parts of a split render (`plumage render --tile I/N`) joined
// into the image one run gives, bit for bit (docs/rendering.md, "Split renders").
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/image.h"
#include "plumage/renderer/render.h"

namespace plumage::cli {
namespace {

struct MergeArgs {
  std::vector<std::string> parts;
  std::string output;
};

int run_merge(const MergeArgs& a) {
  if (const std::string bad = image_output_problem(a.output, {".exr", ".png", ".hdr", ".tif", ".jpg"}); !bad.empty())
    throw UsageError(bad);
  for (const std::string& p : a.parts)
    if (std::filesystem::path(p).extension() != ".exr")
      throw UsageError(p + ": a part is the .exr that `plumage render --tile I/N -o PART.exr` writes");
  if (a.parts.size() > std::size_t(kMaxTiles)) throw UsageError("more than " + std::to_string(kMaxTiles) + " parts");
  std::vector<Image> images;
  images.reserve(a.parts.size());
  for (const std::string& p : a.parts) images.push_back(read_image(p));
  write_image(a.output, merge_tiles(images));
  if (!global_options().quiet)
    std::cerr << "wrote " << a.output << " (" << a.parts.size() << " parts, " << images.front().width << "x"
              << images.front().height << ")\n";
  return 0;
}

const Registration kMerge{
    "merge", "Join the parts of a split render (render --tile I/N) into the image one run gives", [](CLI::App& sub) {
      auto a = std::make_shared<MergeArgs>();
      sub.footer(
          "Give the parts in order, I = 1..N: part I holds the rows of band I and 0 elsewhere, and a part with\n"
          "a pixel outside its band is refused. The merged pixels are those of one run of the same command\n"
          "without --tile, bit for bit.\n"
          "Example: for i in 1 2 3 4; do plumage render f.fcurves --tile $i/4 -o part$i.exr; done\n"
          "         plumage merge part1.exr part2.exr part3.exr part4.exr -o image.exr\n"
          "See docs/rendering.md, \"Split renders\" (GNU parallel and Slurm runners).");
      sub.add_option("parts", a->parts, "The parts, PART1.exr ... PARTN.exr, in order")->required();
      sub.add_option("-o,--output", a->output, "Output image: .exr (linear float) or .png (sRGB 8-bit)")->required();
      return [a] { return run_merge(*a); };
    }};

}  // namespace
}  // namespace plumage::cli
