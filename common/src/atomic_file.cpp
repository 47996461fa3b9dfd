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
// ".name.KIND-PID-N.ext": hidden, unique per process and call, same extension.
fs::path sibling_name(const fs::path& path, const char* kind) {
  static std::atomic<unsigned> counter{0};
  fs::path tmp = path;
  std::string name = ".";
  name += path.stem().string();
  name += kind;
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

void remove_quietly(const fs::path& p) {
  std::error_code ignored;  // a clean-up's own outcome must not replace the reason
  fs::remove(p, ignored);
}
}  // namespace

FileBatch::~FileBatch() {
  for (const Staged& s : staged_) remove_quietly(s.tmp);
}

void FileBatch::stage(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  if (path.empty()) throw Error("output path is empty: give a file name");
  const fs::path dir = path.parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw Error(Location{path.string()}, "cannot write: directory '" + dir.string() +
                                             "' does not exist (create it first)");
  for (const Staged& s : staged_)
    if (fs::weakly_canonical(s.target, ec) == fs::weakly_canonical(path, ec) || s.target == path)
      throw Error(Location{path.string()}, "two outputs of this command name the same file; give each its own");
  const fs::path tmp = sibling_name(path, ".tmp-");
  try {
    write(tmp);
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
  staged_.push_back({tmp, path});
}

void FileBatch::stage_text(const fs::path& path, std::string_view contents) {
  stage(path, [&](const fs::path& tmp) {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(Location{path.string()}, "cannot open for writing: " + last_error());
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw Error(Location{path.string()}, "write failed: " + last_error());
  });
}

void FileBatch::commit() {
  // A target that exists is kept under a hard link until every rename has
  // succeeded, so a failed rename can put the earlier ones back.
  struct Done {
    fs::path target, backup;  // backup empty: the target did not exist, or could not be kept
    bool existed = false;
  };
  std::vector<Done> done;
  auto roll_back = [&] {
    for (auto it = done.rbegin(); it != done.rend(); ++it) {
      std::error_code ec;
      if (!it->backup.empty()) fs::rename(it->backup, it->target, ec);
      else if (!it->existed) fs::remove(it->target, ec);
    }
  };
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    const Staged& s = staged_[i];
    fs::path backup;
    std::error_code ec;
    const bool existed = fs::exists(fs::symlink_status(s.target, ec));
    if (staged_.size() > 1 && fs::is_regular_file(s.target, ec)) {
      backup = sibling_name(s.target, ".old-");
      fs::create_hard_link(s.target, backup, ec);
      if (ec) fs::copy_file(s.target, backup, ec);
      if (ec) backup.clear();
    }
    std::error_code rename_error;
    fs::rename(s.tmp, s.target, rename_error);
    if (rename_error) {
      const Error error(Location{s.target.string()},
                        "cannot rename temporary file into place: " + rename_error.message());
      if (!backup.empty()) remove_quietly(backup);
      roll_back();
      for (const Done& d : done)
        if (!d.backup.empty()) remove_quietly(d.backup);
      for (std::size_t j = i; j < staged_.size(); ++j) remove_quietly(staged_[j].tmp);
      staged_.clear();  // `s` is gone from here on
      throw error;
    }
    done.push_back({s.target, backup, existed});
  }
  for (const Done& d : done)
    if (!d.backup.empty()) remove_quietly(d.backup);
  staged_.clear();
}

void write_via_temp(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  FileBatch batch;
  batch.stage(path, write);
  batch.commit();
}

void write_file_atomic(const fs::path& path, std::string_view contents) {
  FileBatch batch;
  batch.stage_text(path, contents);
  batch.commit();
}

std::uintmax_t check_input_file(const fs::path& path, const std::string& what) {
  const Location where{path.string()};
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw Error(where, "no such file");
  if (ec) throw Error(where, "cannot open: " + ec.message());
  if (st.type() == fs::file_type::directory) throw Error(where, "is a directory, expected " + what);
  if (st.type() != fs::file_type::regular)
    throw Error(where, "is not a regular file (a device, FIFO or socket), expected " + what);
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(where, "cannot open: " + ec.message());
  return size;
}

std::string read_file(const fs::path& path) {
  const std::uintmax_t size = check_input_file(path, "a file");
  if (size > kMaxTextFileBytes)
    throw Error(Location{path.string()}, "file is " + std::to_string(size >> 20) + " MiB, above the " +
                                             std::to_string(kMaxTextFileBytes >> 20) + " MiB limit of text inputs");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Location{path.string()}, "cannot open: " + last_error());
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(Location{path.string()}, "read failed: " + last_error());
  return std::move(ss).str();
}

}  // namespace plumage
