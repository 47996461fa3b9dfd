// Fuzzes the .fscene reader (docs/scene-format.md): any text parses or throws
// plumage::Error, and what parses round-trips: formatting it gives text that
// parses to the same placements and formats to the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "plumage/common/error.h"
#include "plumage/common/scene_format.h"
#include "fuzz_verdict.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  plumage::fuzz::expect_parse_or_error([&] {
    const plumage::FeatherScene first = plumage::parse_fscene(text, "fuzz.fscene");
    const std::string written = plumage::format_fscene(first);
    plumage::FeatherScene second;
    try {
      second = plumage::parse_fscene(written, "fuzz-roundtrip.fscene");
    } catch (const plumage::Error& e) {
      std::fprintf(stderr, "re-reading the writer's output failed: %s\n", e.what());
      plumage::fuzz::finding("format_fscene wrote a file parse_fscene rejects");
    }
    plumage::fuzz::check(second.placements.size() == first.placements.size(), "placements lost in the round trip");
    for (std::size_t i = 0; i < first.placements.size(); ++i)
      plumage::fuzz::check(second.placements[i].to_world == first.placements[i].to_world &&
                               second.placements[i].feather == first.placements[i].feather,
                           "a placement changed in the round trip");
    plumage::fuzz::check(plumage::format_fscene(second) == written, "format is not stable");
  });
  return 0;
}
