#pragma once
// Flush-to-zero (FTZ) and denormals-are-zero (DAZ), the two SSE MXCSR bits that
// make float arithmetic treat denormals as 0. Embree asks for both while it builds
// and traces (denormals are slow there) and sets them itself inside its build
// tasks. Plumage decides instead (docs/robustness.md): a scene build and every
// render tile run with both on, in whatever thread does the work, and each thread
// gets its own register back afterwards. So a render's pixels do not depend on the
// caller's mode, and float results elsewhere do not depend on whether a scene was
// built or rendered earlier in the process.
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace plumage::detail {

class FtzDazScope {
 public:
#if defined(__SSE__)
  FtzDazScope() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFtzDaz); }
  // Restores the control bits only: exception flags raised meanwhile stay raised.
  ~FtzDazScope() { _mm_setcsr((saved_ & ~kFlags) | (_mm_getcsr() & kFlags)); }
#endif
  FtzDazScope(const FtzDazScope&) = delete;
  FtzDazScope& operator=(const FtzDazScope&) = delete;

#if defined(__SSE__)
 private:
  static constexpr unsigned kFtzDaz = 0x8040;  // bit 15 FTZ, bit 6 DAZ
  static constexpr unsigned kFlags = 0x3f;     // sticky exception flags, bits 0-5
  unsigned saved_;
#endif
};

}  // namespace plumage::detail
