#include "plumage/common/error.h"

#include "plumage/common/text.h"

namespace plumage {

std::string format_location(const Location& where) {
  if (where.file.empty()) return {};
  std::string s = printable(where.file);  // a newline in a file name keeps the message one line
  if (where.line > 0) {
    s += ':';
    s += std::to_string(where.line);
    if (where.column > 0) {
      s += ':';
      s += std::to_string(where.column);
    }
  }
  s += ": ";
  return s;
}

Error::Error(Location where, std::string message)
    : std::runtime_error(format_location(where) + message),
      where_(std::move(where)),
      message_(std::move(message)) {}

}  // namespace plumage
