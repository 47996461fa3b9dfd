#include "plumage/common/atomic_file.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>
#include <unistd.h>

#include "plumage/common/error.h"

namespace plumage {
namespace fs = std::filesystem;

namespace {
fs::path temp_name_for(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  fs::path tmp = path;
  // ".name.tmp-PID-N.ext": hidden, unique per process and call, same extension.
  std::string name = ".";
  name += path.stem().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += path.extension().string();
  tmp.replace_filename(name);
  return tmp;
}

// The reason the stream call just made failed, read at once so nothing in
// between (a clean-up, a string being built) can replace errno. Streams do not
// promise to set errno; when the failed call did not, say so plainly.
std::string last_error() {
  const int err = errno;
  return err ? std::strerror(err) : "unknown reason (no error code from the system)";
}
}  // namespace

void write_via_temp(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  if (path.empty()) throw Error("output path is empty: give a file name");
  fs::path dir = path.parent_path();
  if (!dir.empty() && !fs::is_directory(dir))
    throw Error(Location{path.string()}, "cannot write: directory '" + dir.string() +
                                             "' does not exist (create it first)");
  const fs::path tmp = temp_name_for(path);
  try {
    write(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code rename_error;
  fs::rename(tmp, path, rename_error);
  if (rename_error) {
    std::error_code ignored;  // the clean-up's own outcome must not replace the reason
    fs::remove(tmp, ignored);
    throw Error(Location{path.string()}, "cannot rename temporary file into place: " + rename_error.message());
  }
}

void write_file_atomic(const fs::path& path, std::string_view contents) {
  write_via_temp(path, [&](const fs::path& tmp) {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(Location{path.string()}, "cannot open for writing: " + last_error());
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw Error(Location{path.string()}, "write failed: " + last_error());
  });
}

std::string read_file(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(Location{path.string()}, "is a directory, expected a file");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Location{path.string()}, "cannot open: " + last_error());
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(Location{path.string()}, "read failed: " + last_error());
  return std::move(ss).str();
}

}  // namespace plumage
