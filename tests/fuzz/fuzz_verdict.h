#pragma once
// The contract every fuzz target checks: an input parses or throws plumage::Error.
// Anything else (another exception type, a crash, a sanitizer report, a broken
// round trip) is a finding, so it aborts and libFuzzer saves the input.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <typeinfo>

#include "plumage/common/error.h"

namespace plumage::fuzz {

[[noreturn]] inline void finding(const char* what) {
  std::fprintf(stderr, "FUZZ FINDING: %s\n", what);
  std::abort();
}

inline void check(bool ok, const char* what) {
  if (!ok) finding(what);
}

// Runs `body`; plumage::Error is the accepted way to reject input.
template <class Body>
void expect_parse_or_error(Body&& body) {
  try {
    body();
  } catch (const plumage::Error&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FUZZ FINDING: %s escaped instead of plumage::Error: %s\n",
                 typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    finding("a non-std exception escaped instead of plumage::Error");
  }
}

}  // namespace plumage::fuzz
