#pragma once
// The plain-text curve format `.fcurves` (docs/curve-format.md): a whole Feather
// (curves, substructure parameters per vane, albedo, provenance) in a versioned,
// human-editable file. The reader is strict and reports FILE:LINE:COL; the
// writer round-trips exactly (write -> read -> write gives identical bytes).
#include <filesystem>
#include <string>
#include <string_view>

#include "plumage/common/feather.h"

namespace plumage {

class FileBatch;

inline constexpr int kFcurvesVersion = 1;

// Throws plumage::Error when the feather breaks a rule of the format (units not
// mm, fewer than 4 control points, NaN, negative radius, non-unit normal, a barb
// without a side, ...; docs/curve-format.md): what the reader would reject.
void validate_feather(const Feather& feather);

// Serialises a feather (floats in shortest round-trip form).
std::string format_fcurves(const Feather& feather);
// Writes atomically.
void write_fcurves(const std::filesystem::path& path, const Feather& feather);
// The same, staged in `batch` (atomic_file.h) with a command's other outputs.
void write_fcurves(FileBatch& batch, const std::filesystem::path& path, const Feather& feather);

// Parses text; `filename` is used in error messages. Throws plumage::Error.
Feather parse_fcurves(std::string_view text, const std::string& filename = "<memory>");
Feather read_fcurves(const std::filesystem::path& path);

}  // namespace plumage
