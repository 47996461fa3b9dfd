#pragma once
// The project's JSON inputs — layout.json, feather parameter files, light rigs —
// read and parsed one way (docs/robustness.md): a file is judged by its first
// 4 KiB before it is read whole, and a syntax error is reported at FILE:LINE:COL
// in the parser's own words without its prefix.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace plumage {

// Reads `path` (read_file's limits) once its first kJudgedBytes are UTF-8 text
// without NUL bytes whose first character other than white space opens a JSON
// object: a large binary file, or one of zeros, named .json is refused at once
// (FILE:LINE:COL, what was found).
std::string read_json_text(const std::filesystem::path& path);

// Parses `text` from `file`. Throws plumage::Error: at FILE:LINE:COL "invalid JSON:
// ..." for a syntax error, at FILE for anything else the parser refuses (a number
// too large for a double).
nlohmann::json parse_json(const std::string& text, const std::string& file);

}  // namespace plumage
