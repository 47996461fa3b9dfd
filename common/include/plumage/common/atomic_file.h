#pragma once
// Atomic file writes: every writer in Plumage writes to a temporary file beside
// the target and renames it into place, so a failure never leaves a damaged file.
// A command with several outputs stages them all in one FileBatch and commits
// them together: all of them are written, or none.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "plumage/common/interrupt.h"

namespace plumage {

// While one of these lives (a command's run holds one), every input opened
// through check_input_file is remembered, and FileBatch refuses an output that
// is one of them (the same file by device and inode, whatever its path):
// `analyze p.png -o p.png` cannot destroy its photo. Outside a run (a library
// reading a file, editing it and saving it back) nothing is limited.
class InputsProtected {
 public:
  InputsProtected();
  ~InputsProtected();
  InputsProtected(const InputsProtected&) = delete;
  InputsProtected& operator=(const InputsProtected&) = delete;
};

// Outputs written all or none. stage() writes one file under a temporary name
// beside its target (if the writer throws, that temporary is removed); commit()
// renames every staged file into place, and if one rename fails it puts back the
// targets it had already replaced. A target is written only where it is absent
// or a regular file (links followed), never over an input of the run
// (InputsProtected), and a file it replaces keeps its permissions. A batch destroyed before commit() removes its
// temporary files, so a failure anywhere leaves every target as it was.
class FileBatch {
 public:
  FileBatch() = default;
  FileBatch(const FileBatch&) = delete;
  FileBatch& operator=(const FileBatch&) = delete;
  ~FileBatch();

  // Calls `write(tmp_path)` to produce `path`'s contents under a temporary name
  // that keeps `path`'s extension (image writers choose the format by it).
  // Throws plumage::Error naming the path when its directory is missing or the
  // same path is staged twice.
  void stage(const std::filesystem::path& path,
             const std::function<void(const std::filesystem::path& tmp_path)>& write);
  void stage_text(const std::filesystem::path& path, std::string_view contents);
  void commit();

 private:
  struct Staged {
    std::filesystem::path tmp, target;
    RemovedOnSignal on_signal;  // the signal handler's last resort removes `tmp` too
  };
  std::vector<Staged> staged_;
};

// Writes `contents` to `path` atomically. Throws plumage::Error naming the path.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// A one-file FileBatch: writes `path` through a temporary file, then renames it.
void write_via_temp(const std::filesystem::path& path,
                    const std::function<void(const std::filesystem::path& tmp_path)>& write);

// What a file read is to the run: an input the user gave (which no output of the
// run may replace, InputsProtected), or state the program keeps and may rewrite
// (a cache).
enum class FileRole { Input, Cache };

// Checks that `path` names a regular file (links followed) and returns its size.
// A directory, FIFO, socket or device is refused with plumage::Error naming the
// path: a reader would hang on a FIFO or /dev/zero. `what` says what was
// expected ("an image", "a curve file").
std::uintmax_t check_input_file(const std::filesystem::path& path, const std::string& what,
                                FileRole role = FileRole::Input);

// The largest text input read_file accepts (curve files, parameters, layouts, rigs).
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t(1) << 30;

// Reads a whole regular file of at most kMaxTextFileBytes; throws
// plumage::Error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path, FileRole role = FileRole::Input);

// How much of a text input is judged (its format, its encoding) before it is read whole.
inline constexpr std::size_t kJudgedBytes = 4096;

// The first `bytes` bytes of `path` (all of it when it is shorter): to judge a
// large file by its start before reading it whole.
std::string read_file_head(const std::filesystem::path& path, std::size_t bytes = kJudgedBytes);

}  // namespace plumage
