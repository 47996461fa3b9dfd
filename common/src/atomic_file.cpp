#include "plumage/common/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>
#include <sys/stat.h>
#include <system_error>
#include <unistd.h>

#include "plumage/common/error.h"

namespace plumage {
namespace fs = std::filesystem;

namespace {
// The longest file name (bytes) the temporary names are kept to: POSIX's NAME_MAX,
// which the common Linux file systems share.
constexpr std::size_t kMaxNameBytes = NAME_MAX;

// ".name.KIND-PID-N.ext": hidden, unique per process and call, same extension. A
// long name's stem is cut so that the whole fits in a file name.
fs::path sibling_name(const fs::path& path, const char* kind) {
  static std::atomic<unsigned> counter{0};
  const std::string unique = kind + std::to_string(::getpid()) + '-' + std::to_string(counter++);
  std::string ext = path.extension().string(), stem = path.stem().string();
  ext.resize(std::min(ext.size(), kMaxNameBytes / 2));
  const std::size_t room = kMaxNameBytes - 1 - unique.size() - ext.size();
  if (stem.size() > room) stem.resize(room);
  fs::path tmp = path;
  tmp.replace_filename("." + stem + unique + ext);
  return tmp;
}

// The files this process has opened as inputs (check_input_file), by device and
// inode, so that no output replaces one of them.
struct InputFile {
  dev_t dev;
  ino_t ino;
  std::string path;
};
std::mutex g_inputs_mutex;
std::vector<InputFile> g_inputs;
std::atomic<int> g_protecting{0};  // InputsProtected objects alive

// The remembered input that `st` is (same device and inode), if any. Needs the lock.
const InputFile* find_input(const struct stat& st) {
  for (const InputFile& f : g_inputs)
    if (f.dev == st.st_dev && f.ino == st.st_ino) return &f;
  return nullptr;
}

void note_input(const fs::path& path) {
  struct stat st {};
  if (g_protecting == 0 || ::stat(path.c_str(), &st) != 0) return;
  const std::lock_guard<std::mutex> lock(g_inputs_mutex);
  if (!find_input(st)) g_inputs.push_back({st.st_dev, st.st_ino, path.string()});
}

// The input `path` is (the same file, by device and inode), if it is one.
const InputFile* input_at(const fs::path& path) {
  struct stat st {};
  if (g_protecting == 0 || ::stat(path.c_str(), &st) != 0) return nullptr;
  const std::lock_guard<std::mutex> lock(g_inputs_mutex);
  return find_input(st);
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

InputsProtected::InputsProtected() {
  const std::lock_guard<std::mutex> lock(g_inputs_mutex);
  ++g_protecting;
}

InputsProtected::~InputsProtected() {
  const std::lock_guard<std::mutex> lock(g_inputs_mutex);
  if (--g_protecting == 0) g_inputs.clear();
}

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
  // Only a regular file is replaced (links followed): a device, FIFO or socket
  // that an output names is left as it is, and so is every input of this run.
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::directory)
    throw Error(Location{path.string()}, "is a directory: give a file name for the output");
  if (fs::exists(st) && st.type() != fs::file_type::regular)
    throw Error(Location{path.string()},
                "is a device, FIFO or socket, not a regular file; an output replaces only files: give a file name");
  if (const InputFile* in = input_at(path))
    throw Error(Location{path.string()}, "is an input of this command ('" + in->path +
                                             "'): give the output another name");
  for (const Staged& s : staged_)
    if (fs::weakly_canonical(s.target, ec) == fs::weakly_canonical(path, ec) || s.target == path)
      throw Error(Location{path.string()}, "two outputs of this command name the same file; give each its own");
  const fs::path tmp = sibling_name(path, ".tmp-");
  RemovedOnSignal on_signal(tmp);
  try {
    write(tmp);
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
  staged_.push_back({tmp, path, std::move(on_signal)});
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
  check_interrupted();  // stopped before any rename: every target stays as it was
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
    // The file it replaces keeps its permissions (a private file stays private).
    if (const fs::file_status old = fs::status(s.target, ec); !ec && old.type() == fs::file_type::regular)
      fs::permissions(s.tmp, old.permissions(), fs::perm_options::replace, ec);
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

std::uintmax_t check_input_file(const fs::path& path, const std::string& what, FileRole role) {
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
  if (role == FileRole::Input) note_input(path);
  return size;
}

std::string read_file(const fs::path& path, FileRole role) {
  const std::uintmax_t size = check_input_file(path, "a file", role);
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

std::string read_file_head(const fs::path& path, std::size_t bytes) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Location{path.string()}, "cannot open: " + last_error());
  std::string head(bytes, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(std::size_t(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

}  // namespace plumage
