#pragma once
// Text that comes from files or file names and goes into files or messages
// (docs/robustness.md, "Text in, text out"): strings read from files must be
// UTF-8, and a message shows a control character or a byte that is not UTF-8
// escaped, so that it stays one line and valid text.
#include <cstddef>
#include <string>
#include <string_view>

#include "plumage/common/error.h"

namespace plumage {

// The offset of the first byte of `s` that does not begin or continue a
// well-formed UTF-8 sequence (RFC 3629: no overlong forms, no surrogates, nothing
// above U+10FFFF), or std::string_view::npos when `s` is UTF-8 throughout.
std::size_t invalid_utf8_at(std::string_view s);

// `s` with each control character (below 0x20, and 0x7F) written as \n, \t, \r
// or \xNN and each byte that is not part of well-formed UTF-8 as \xNN;
// everything else as it is, so that printable(printable(s)) == printable(s).
std::string printable(std::string_view s);

// FILE:LINE:COL of byte `byte` of `text` (1-based line and column; a byte past
// the end is placed at the end): where a parser's byte offset points.
Location location_of_byte(std::string_view text, std::size_t byte, const std::string& file);

// Text read from a file is UTF-8 without NUL bytes (a binary or sparse file is
// not): throws Error at FILE:LINE:COL of the first byte that is not, "byte 0xFF is
// not UTF-8 text: save the file as UTF-8".
void check_text(std::string_view text, const std::string& file);

// check_text for the first bytes of a longer file (read_file_head): a UTF-8
// sequence cut at its end is not an error.
void check_text_head(std::string_view head, const std::string& file);

// A nlohmann::json (or ordered_json) value as JSON text that is valid UTF-8 whatever
// its strings hold (a file name may hold any byte): a byte that is not UTF-8 is
// written as U+FFFD instead of failing. `indent` as json::dump's (-1: one line).
template <class Json>
std::string json_text(const Json& j, int indent = -1) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

}  // namespace plumage
