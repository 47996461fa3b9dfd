// The shared line reader of the plain-text formats (line_reader.h).
#include "line_reader.h"

#include <charconv>
#include <cmath>
#include <system_error>

#include "plumage/common/text.h"

namespace plumage::detail {

bool LineReader::next_line() {
  if (pos_ >= text_.size()) return false;
  std::size_t nl = text_.find('\n', pos_);
  if (nl == std::string_view::npos) nl = text_.size();
  line_ = text_.substr(pos_, nl - pos_);
  if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);  // tolerate CRLF files
  pos_ = nl + 1;
  ++line_no_;

  tok_.clear();
  const char* s = line_.data();
  const std::size_t n = line_.size();
  std::size_t i = 0;
  while (i < n) {
    const char c = s[i];
    if (c == ' ' || c == '\t') {
      ++i;
      continue;
    }
    if (c == '#') break;
    const std::size_t start = i;
    if (c == '"') {
      ++i;
      for (;;) {
        if (i >= n) fail(static_cast<int>(start) + 1, "unterminated string: add the closing '\"'");
        if (s[i] == '\\') {
          if (i + 1 >= n || (s[i + 1] != '"' && s[i + 1] != '\\'))
            fail(static_cast<int>(i) + 1, "unknown escape in string: only \\\" and \\\\ are allowed");
          i += 2;
          continue;
        }
        if (s[i] == '"') {
          ++i;
          break;
        }
        if (static_cast<unsigned char>(s[i]) < 0x20 || s[i] == 0x7f)
          fail(static_cast<int>(i) + 1,
               "control character in a string: strings are one line of printable text");
        ++i;
      }
      if (i < n && s[i] != ' ' && s[i] != '\t' && s[i] != '#')
        fail(static_cast<int>(i) + 1, "expected a space after the closing '\"'");
    } else {
      while (i < n && s[i] != ' ' && s[i] != '\t' && s[i] != '#') {
        if (s[i] == '"') fail(static_cast<int>(i) + 1, "stray '\"' inside a word: quote the whole string");
        if (static_cast<unsigned char>(s[i]) < 0x20 || s[i] == 0x7f)
          fail(static_cast<int>(i) + 1, "control character in the text: the file must be plain text");
        ++i;
      }
    }
    tok_.push_back({line_.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return true;
}

float LineReader::to_float(const Token& t, const char* what) const {
  float v = 0;
  const char* b = t.text.data();
  const char* e = b + t.text.size();
  // from_chars does not take a leading '+'; numbers in the format never have one.
  auto [ptr, ec] = std::from_chars(b, e, v, std::chars_format::general);
  if (ec == std::errc::result_out_of_range)
    fail(t, std::string(what) + ": '" + std::string(t.text) + "' is out of range for a 32-bit float");
  if (ec != std::errc() || ptr != e)
    fail(t, std::string(what) + ": expected a number, found '" + std::string(t.text) + "'");
  return v;
}

float LineReader::finite_float(const Token& t, const char* what) const {
  const float v = to_float(t, what);
  if (!std::isfinite(v)) fail(t, std::string(what) + ": must be finite, found '" + std::string(t.text) + "'");
  return v;
}

float LineReader::nonneg_float(const Token& t, const char* what) const {
  const float v = finite_float(t, what);
  if (v < 0) fail(t, std::string(what) + ": must not be negative, found '" + std::string(t.text) + "'");
  return v;
}

float LineReader::ranged_float(const Token& t, const char* what, float lo, float hi, const char* range) const {
  const float v = finite_float(t, what);
  if (v < lo || v > hi)
    fail(t, std::string(what) + ": must be in " + range + ", found '" + std::string(t.text) + "'");
  return v;
}

std::uint64_t LineReader::unsigned_int(const Token& t, const char* what) const {
  std::uint64_t v = 0;
  const char* b = t.text.data();
  const char* e = b + t.text.size();
  auto [ptr, ec] = std::from_chars(b, e, v);
  if (ec == std::errc::result_out_of_range)
    fail(t, std::string(what) + ": '" + std::string(t.text) + "' is too large");
  if (ec != std::errc() || ptr != e)
    fail(t, std::string(what) + ": expected a whole number >= 0, found '" + std::string(t.text) + "'");
  return v;
}

std::string LineReader::quoted(const Token& t, const char* what) const {
  if (t.text.size() < 2 || t.text.front() != '"')
    fail(t, std::string(what) + ": expected a string in double quotes, found '" + std::string(t.text) + "'");
  std::string s;
  s.reserve(t.text.size() - 2);
  for (std::size_t i = 1; i + 1 < t.text.size(); ++i) {
    if (t.text[i] == '\\') ++i;  // the tokenizer has checked the escape
    s += t.text[i];
  }
  return s;
}

void LineReader::expect_count(std::size_t n, const std::string& form) const {
  if (tok_.size() < n)
    fail(end_column(), "'" + std::string(tok_[0].text) + "' record is incomplete: expected '" + form + "'");
  if (tok_.size() > n) fail(tok_[n], "unexpected '" + std::string(tok_[n].text) + "' after '" + form + "'");
}

std::uint64_t LineReader::read_header(const char* magic, int newest, const char* what) {
  if (text_.starts_with("\xEF\xBB\xBF"))
    throw Error(Location{file_, 1, 1}, "the file starts with a UTF-8 byte-order mark: save it without one");
  check_text(text_, file_);
  if (!next_line()) line_no_ = 1;  // an empty file: point at its first line
  const std::string m(magic);
  if (line_no_ != 1 || tok_.empty() || tok_[0].text != m)
    fail(1, "missing header: the first line must be '" + m + " " + std::to_string(newest) + "' (is this " + what +
                "?)");
  if (tok_.size() < 2) fail(end_column(), "header: expected a version number after '" + m + "'");
  const std::uint64_t version = unsigned_int(tok_[1], "format version");
  if (version > static_cast<std::uint64_t>(newest))
    fail(tok_[1], "format version " + std::string(tok_[1].text) + " is newer than this reader (" +
                      std::to_string(newest) + "): upgrade Plumage to read it");
  if (version < 1) fail(tok_[1], "format version must be 1 or more, found " + std::string(tok_[1].text));
  expect_count(2, m + " VERSION");
  return version;
}

}  // namespace plumage::detail
