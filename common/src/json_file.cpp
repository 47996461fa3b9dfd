// JSON inputs read and parsed one way (json_file.h).
#include "plumage/common/json_file.h"

#include <cstdio>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/text.h"

namespace plumage {

std::string read_json_text(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (check_input_file(path, "a JSON file") > kJudgedBytes) {
    const std::string head = read_file_head(path);
    check_text_head(head, file);
    std::size_t first = head.starts_with("\xEF\xBB\xBF") ? 3 : 0;
    first = head.find_first_not_of(" \t\r\n", first);
    if (first != std::string::npos && head[first] != '{') {
      char shown[16];
      std::snprintf(shown, sizeof shown, head[first] >= 0x21 && head[first] < 0x7F ? "'%c'" : "byte 0x%02X",
                    static_cast<unsigned char>(head[first]));
      throw Error(location_of_byte(head, first, file),
                  std::string("invalid JSON: expected '{' to open the file's object, found ") + shown);
    }
  }
  return read_file(path);
}

nlohmann::json parse_json(const std::string& text, const std::string& file) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..." -> "syntax error ..."
    std::string what = e.what();
    if (const auto k = what.find("parse error"); k != std::string::npos)
      if (const auto colon = what.find(": ", k); colon != std::string::npos) what = what.substr(colon + 2);
    throw Error(location_of_byte(text, e.byte > 0 ? e.byte - 1 : 0, file), "invalid JSON: " + what);
  } catch (const nlohmann::json::exception& e) {  // not syntax: e.g. a number too large for a double
    std::string what = e.what();
    if (const auto k = what.find("] "); k != std::string::npos) what = what.substr(k + 2);
    throw Error(Location{file}, "invalid JSON: " + what);
  }
}

}  // namespace plumage
