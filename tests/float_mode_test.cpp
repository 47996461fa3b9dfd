// The SSE flush-to-zero (FTZ) and denormals-are-zero (DAZ) bits around the
// renderer (docs/robustness.md): a scene build and a render run with both on, in
// every thread that does their work, and the caller gets its own mode back, so
// float results elsewhere never depend on whether a scene was built before.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include <tbb/parallel_for.h>

#include "plumage/renderer/feather_render.h"
#include "render_test_feather.h"

#if defined(__SSE__)
#include <xmmintrin.h>

namespace plumage {
namespace {

constexpr unsigned kFtzDaz = 0x8040;  // MXCSR bit 15 (FTZ) and bit 6 (DAZ)

// A denormal input times one: 0 under DAZ, a denormal result is 0 under FTZ.
bool denormal_survives() {
  volatile float tiny = 1e-39f, one = 1.0f;
  const float r = tiny * one;
  return r != 0.0f;
}

// Sets the caller's FTZ/DAZ bits for the test and puts the register back after.
class CallerMode {
 public:
  explicit CallerMode(bool ftz_daz) : saved_(_mm_getcsr()) {
    _mm_setcsr(ftz_daz ? saved_ | kFtzDaz : saved_ & ~kFtzDaz);
  }
  ~CallerMode() { _mm_setcsr(saved_); }
  CallerMode(const CallerMode&) = delete;
  CallerMode& operator=(const CallerMode&) = delete;

 private:
  unsigned saved_;
};

const DomeRig& rig() {
  static const DomeRig r = read_dome_rig(std::filesystem::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  return r;
}

ViewSpec tiny_view() {
  ViewSpec v;
  v.width = v.height = 8;
  v.spp = 2;
  v.max_depth = 2;
  v.threads = 2;
  return v;
}

// Runs `body` in a new thread: a caller that meets TBB for the first time, as a
// program's main thread does, whatever other tests did before in this process.
template <class F>
void in_fresh_thread(F body) {
  std::thread(body).join();
}

// How many of n parallel tasks saw a denormal turned into zero.
int tasks_that_flush(int n) {
  std::atomic<int> flushed{0};
  tbb::parallel_for(0, n, [&](int) {
    if (!denormal_survives()) ++flushed;
  });
  return flushed.load();
}

TEST(FloatMode, SceneBuildAndRenderLeaveTheCallersModeAlone) {
  in_fresh_thread([] {
    const CallerMode off(false);
    ASSERT_TRUE(denormal_survives());
    const Scene scene(test::make_test_feather(10.0f, 1.0f, 0.05f), SceneOptions{});
    EXPECT_EQ(_mm_getcsr() & kFtzDaz, 0u) << "a scene build left FTZ/DAZ on in the caller";
    EXPECT_TRUE(denormal_survives());
    EXPECT_EQ(tasks_that_flush(1000), 0) << "parallel work after a scene build flushed denormals";
    render_view(scene, rig(), tiny_view());
    EXPECT_EQ(_mm_getcsr() & kFtzDaz, 0u) << "a render left FTZ/DAZ on in the caller";
    EXPECT_TRUE(denormal_survives());
    EXPECT_EQ(tasks_that_flush(1000), 0) << "parallel work after a render flushed denormals";
  });
}

TEST(FloatMode, ACallerThatWantsFtzKeepsIt) {
  in_fresh_thread([] {
    const CallerMode on(true);
    const Scene scene(test::make_test_feather(10.0f, 1.0f, 0.05f), SceneOptions{});
    render_view(scene, rig(), tiny_view());
    EXPECT_EQ(_mm_getcsr() & kFtzDaz, kFtzDaz);
    EXPECT_FALSE(denormal_survives());
  });
}

// The render itself always runs with FTZ/DAZ on, so its pixels do not depend on
// the caller's mode (nor on what ran before in the process).
TEST(FloatMode, PixelsDoNotDependOnTheCallersMode) {
  const Feather feather = test::make_test_feather(10.0f, 1.0f, 0.05f);
  auto render_with = [&](bool ftz_daz) {
    Image image;
    in_fresh_thread([&] {
      const CallerMode mode(ftz_daz);
      const Scene scene(feather, SceneOptions{});
      image = render_view(scene, rig(), tiny_view());
    });
    return image;
  };
  const Image a = render_with(false), b = render_with(true);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(a.pixels, b.pixels);
}

}  // namespace
}  // namespace plumage
#endif  // __SSE__
