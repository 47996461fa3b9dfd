#pragma once
// One error type for the whole project: a message plus the place it refers to
// (a file, and where known a line and column), printed as FILE:LINE:COL: message.
#include <stdexcept>
#include <string>

namespace plumage {

struct Location {
  std::string file;  // empty when the error is not about a file
  int line = 0;      // 1-based; 0 when unknown
  int column = 0;    // 1-based; 0 when unknown
};

class Error : public std::runtime_error {
 public:
  explicit Error(std::string message) : Error(Location{}, std::move(message)) {}
  Error(Location where, std::string message);

  const Location& where() const { return where_; }
  // The message without the place.
  const std::string& message() const { return message_; }

 private:
  Location where_;
  std::string message_;
};

// "FILE:LINE:COL: " (parts that are unknown are left out), or "" for no file.
std::string format_location(const Location& where);

}  // namespace plumage
