// Fuzzes the generator's JSON parameter reader (docs/generator.md): any text
// parses to validated FeatherParams or throws plumage::Error, and what parses
// round-trips through params_to_json.
#include <cstddef>
#include <cstdint>
#include <string>
#include <typeinfo>

#include <nlohmann/json.hpp>

#include "plumage/common/error.h"
#include "plumage/generator/feather_params.h"
#include "fuzz_verdict.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  plumage::fuzz::expect_parse_or_error([&] {
    const plumage::FeatherParams p = plumage::parse_params(text, "fuzz.json");
    plumage::FeatherParams back;
    try {
      back = plumage::parse_params(plumage::params_to_json(p).dump(), "fuzz-roundtrip.json");
    } catch (const plumage::Error& e) {
      std::fprintf(stderr, "re-reading params_to_json's output failed: %s\n", e.what());
      plumage::fuzz::finding("params_to_json wrote parameters the reader rejects");
    }
    plumage::fuzz::check(back == p, "parse(to_json(p)) != p");
  });
  return 0;
}
