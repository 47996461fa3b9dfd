#pragma once
// Text that comes from files or file names and goes into files or messages
// (docs/robustness.md, "Text in, text out"): strings read from files must be
// UTF-8, and a message shows a control character or a byte that is not UTF-8
// escaped, so that it stays one line and valid text.
#include <cstddef>
#include <string>
#include <string_view>

namespace plumage {

// The offset of the first byte of `s` that does not begin or continue a
// well-formed UTF-8 sequence (RFC 3629: no overlong forms, no surrogates, nothing
// above U+10FFFF), or std::string_view::npos when `s` is UTF-8 throughout.
std::size_t invalid_utf8_at(std::string_view s);

// `s` with each control character (below 0x20, and 0x7F) written as \n, \t, \r
// or \xNN and each byte that is not part of well-formed UTF-8 as \xNN;
// everything else as it is, so that printable(printable(s)) == printable(s).
std::string printable(std::string_view s);

// A nlohmann::json (or ordered_json) value as JSON text that is valid UTF-8 whatever
// its strings hold (a file name may hold any byte): a byte that is not UTF-8 is
// written as U+FFFD instead of failing. `indent` as json::dump's (-1: one line).
template <class Json>
std::string json_text(const Json& j, int indent = -1) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

}  // namespace plumage
