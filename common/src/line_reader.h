#pragma once
// The line reader the plain-text formats share (.fcurves, curve_format.h; .fscene,
// scene_format.h): one line at a time, split into tokens that are views into the
// text (words, or strings in double quotes with \" and \\ escapes; '#' starts a
// comment), numbers through std::from_chars, and every error thrown as
// plumage::Error at FILE:LINE:COL of the token that broke the rule.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "plumage/common/error.h"

namespace plumage::detail {

struct Token {
  std::string_view text;  // quoted strings keep their quotes
  int column;             // 1-based
};

class LineReader {
 public:
  LineReader(std::string_view text, const std::string& filename) : text_(text), file_(filename) {}

 protected:
  // Splits the next line into tokens; returns false at end of text.
  bool next_line();
  [[noreturn]] void fail(int column, const std::string& message) const {
    throw Error(Location{file_, line_no_, column}, message);
  }
  [[noreturn]] void fail(const Token& t, const std::string& message) const { fail(t.column, message); }
  int end_column() const { return static_cast<int>(line_.size()) + 1; }

  // The first line, 'MAGIC VERSION' with 1 <= VERSION <= `newest`; rejects a
  // byte-order mark and text that is not UTF-8 (check_text). `what` names the
  // format in the message for a file without the header ("a .fcurves file").
  std::uint64_t read_header(const char* magic, int newest, const char* what);

  float to_float(const Token& t, const char* what) const;
  float finite_float(const Token& t, const char* what) const;
  float nonneg_float(const Token& t, const char* what) const;
  float ranged_float(const Token& t, const char* what, float lo, float hi, const char* range) const;
  std::uint64_t unsigned_int(const Token& t, const char* what) const;
  std::string quoted(const Token& t, const char* what) const;
  // The line holds exactly n tokens; `form` is the record's syntax for the message.
  void expect_count(std::size_t n, const std::string& form) const;

  std::string_view text_;
  std::string file_;
  std::size_t pos_ = 0;
  int line_no_ = 0;
  std::string_view line_;
  std::vector<Token> tok_;
};

}  // namespace plumage::detail
