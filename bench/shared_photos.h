#pragma once
// The photos in ../shared/photos that some benchmarks time. They are not part of
// the project: where they are absent the benchmark is skipped with a message.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <optional>

namespace plumage::bench {

// ../shared/photos/NAME, or nullopt (and `state` skipped) when it is absent.
inline std::optional<std::filesystem::path> shared_photo(benchmark::State& state, const char* name) {
  const std::filesystem::path photo = (std::filesystem::path(PLUMAGE_SHARED_DIR) / "photos" / name).lexically_normal();
  if (std::filesystem::exists(photo)) return photo;
  state.SkipWithError("shared photos absent");
  return std::nullopt;
}

}  // namespace plumage::bench
