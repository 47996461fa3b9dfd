#pragma once
// Third-party decoders (libpng, libjpeg, libtiff, through OpenImageIO and
// OpenCV) print their own warnings and errors on stderr, which would break the
// promise of one error line. While a StderrCapture lives, what is written to
// file descriptor 2 goes to a temporary file instead; text() hands it back, so
// a caller can fold it into its one plumage::Error line or drop it.
// The redirection is process-wide: use it around single-threaded decoding only.
// PLUMAGE_KEEP_STDERR=1 in the environment turns capturing off, so that a crash
// or sanitizer report inside a decoder reaches the terminal (scripts/fuzz.sh
// sets it; a captured report would vanish with the unlinked temporary file).
#include <string>

namespace plumage {

class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();  // restores stderr
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Restores stderr and returns what was printed meanwhile, its lines joined by "; ".
  std::string text();

 private:
  int saved_ = -1;
  int file_ = -1;
};

}  // namespace plumage
