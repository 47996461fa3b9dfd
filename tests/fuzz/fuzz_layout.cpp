// Fuzzes the analysis layout reader (docs/layout-format.md): any text parses to a
// validated Layout or throws plumage::Error, and what parses round-trips: writing
// it and reading it back writes the same JSON again.
#include <cstddef>
#include <cstdint>
#include <string>
#include <typeinfo>

#include "plumage/common/error.h"
#include "plumage/layout/layout.h"
#include "fuzz_verdict.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  plumage::fuzz::expect_parse_or_error([&] {
    const plumage::Layout layout = plumage::parse_layout(text, "fuzz-layout.json");
    const std::string written = plumage::layout_to_json(layout);
    std::string again;
    try {
      again = plumage::layout_to_json(plumage::parse_layout(written, "fuzz-roundtrip.json"));
    } catch (const plumage::Error& e) {
      std::fprintf(stderr, "re-reading layout_to_json's output failed: %s\n", e.what());
      plumage::fuzz::finding("layout_to_json wrote a layout parse_layout rejects");
    }
    plumage::fuzz::check(again == written, "to_json(parse(to_json(l))) != to_json(l)");
  });
  return 0;
}
