// Fuzzes the .fcurves reader (docs/curve-format.md): any text parses or throws
// plumage::Error, and what parses round-trips: format -> parse gives the same
// feather and formatting it again gives the same bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <typeinfo>

#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "fuzz_verdict.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  plumage::fuzz::expect_parse_or_error([&] {
    const plumage::Feather first = plumage::parse_fcurves(text, "fuzz.fcurves");
    const std::string written = plumage::format_fcurves(first);
    plumage::Feather second;
    try {
      second = plumage::parse_fcurves(written, "fuzz-roundtrip.fcurves");
    } catch (const plumage::Error& e) {
      std::fprintf(stderr, "re-reading the writer's output failed: %s\n", e.what());
      plumage::fuzz::finding("format_fcurves wrote a file parse_fcurves rejects");
    }
    plumage::fuzz::check(second == first, "parse(format(f)) != f");
    plumage::fuzz::check(plumage::format_fcurves(second) == written, "format is not stable");
  });
  return 0;
}
