#pragma once
// Atomic file writes: every writer in Plumage writes to a temporary file beside
// the target and renames it into place, so a failure never leaves a damaged file.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace plumage {

// Writes `contents` to `path` atomically. Throws plumage::Error naming the path.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// Calls `write(tmp_path)` to produce the file under a temporary name in the
// same directory, then renames it to `path`. If `write` throws, the temporary
// file is removed and the exception propagates; `path` is untouched.
// The temporary name keeps `path`'s extension (image writers choose the format by it).
void write_via_temp(const std::filesystem::path& path,
                    const std::function<void(const std::filesystem::path& tmp_path)>& write);

// Reads a whole file; throws plumage::Error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

}  // namespace plumage
