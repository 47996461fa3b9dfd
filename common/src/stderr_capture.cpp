#include "plumage/common/stderr_capture.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace plumage {

StderrCapture::StderrCapture() {
  const char* keep = std::getenv("PLUMAGE_KEEP_STDERR");
  if (keep != nullptr && keep[0] != '\0' && keep[0] != '0') return;  // nothing captured
  std::fflush(stderr);
  char name[] = "/tmp/plumage-stderr-XXXXXX";
  file_ = ::mkstemp(name);
  if (file_ < 0) return;  // nothing captured: the messages stay on stderr
  ::unlink(name);
  saved_ = ::dup(STDERR_FILENO);
  if (saved_ < 0 || ::dup2(file_, STDERR_FILENO) < 0) {
    if (saved_ >= 0) ::close(saved_);
    ::close(file_);
    saved_ = file_ = -1;
  }
}

std::string StderrCapture::text() {
  if (saved_ < 0) return {};
  std::fflush(stderr);
  ::dup2(saved_, STDERR_FILENO);
  ::close(saved_);
  saved_ = -1;
  std::string out;
  char buf[4096];
  ::lseek(file_, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(file_, buf, sizeof buf)) > 0 && out.size() < 65536;) out.append(buf, std::size_t(n));
  ::close(file_);
  file_ = -1;
  std::string joined;
  std::size_t start = 0;
  while (start < out.size()) {
    std::size_t end = out.find('\n', start);
    if (end == std::string::npos) end = out.size();
    if (end > start) joined += (joined.empty() ? "" : "; ") + out.substr(start, end - start);
    start = end + 1;
  }
  return joined;
}

StderrCapture::~StderrCapture() {
  if (saved_ >= 0) text();
  if (file_ >= 0) ::close(file_);
}

}  // namespace plumage
