#pragma once
// The closed-loop accuracy study of photo analysis (issue #6): feathers drawn at
// random from a fixed seed are built by the generator, rendered top-down with the
// path tracer on a white and on a black card, degraded (blur, noise, JPEG) and
// analysed; the layout is compared with the truth taken from the generated
// geometry, projected through the same orthographic camera. Shared by
// tests/closed_loop_test.cpp (which asserts the bounds) and the report it writes
// for docs/analysis.md when PLUMAGE_CLOSED_LOOP_REPORT is set
// (scripts/closed_loop.sh).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "plumage/common/image.h"
#include "plumage/generator/feather_params.h"

namespace plumage::closed_loop {

// The five bounds.
struct Bounds {
  double shaft = 0.01;      // centreline distance, fraction of the shaft length (everywhere)
  double angle_deg = 3.0;   // median barb-angle error over the compared stations
  double spacing = 0.05;    // median relative barb-spacing error
  double width = 0.03;      // vane half-width error, fraction of the length (every station)
  double iou = 0.97;        // outline mask intersection over union (at least)
};

struct Degradation {
  double blur_sigma_px = 0.8;  // Gaussian blur (lens), before the noise
  double noise_sigma = 0.02;   // Gaussian noise on sRGB values in 0..1 (sensor)
  int jpeg_quality = 90;       // JPEG compression (4:2:0, as cameras write)
};

struct StudyOptions {
  int feathers = 20;
  std::uint64_t seed = 2026;
  int long_side_px = 1100;     // image height; the feather runs up the image
  int spp = 4;
  int max_depth = 1;
  Degradation degrade;
  std::filesystem::path work_dir;  // photos and layouts go here (must exist)
  // Test hooks that must make the study fail: scale every truth barb angle by
  // this factor / shift the truth centreline by this many pixels along +x.
  double perturb_truth_angle = 1.0;
  double perturb_truth_shaft_px = 0.0;
  // Debugging aids: only feather K; the overlays also written next to the photos.
  std::optional<int> only;
  bool keep_overlays = false;
};

// Confidence an analysed station needs to be compared (as the layout's users
// are told to require, docs/analysis.md).
struct Thresholds {
  double width = 0.9, angle = 0.5, spacing = 0.3;
};

struct CaseResult {
  int feather = 0;  // 1-based
  bool dark = false;
  std::string summary;  // the drawn parameters in a few words
  double length_mm = 0, mm_per_px = 0;
  // The five errors (see Bounds for their definitions).
  double shaft = 0, angle_deg = 0, spacing = 0, width = 0, iou = 0;
  double angle_max_deg = 0, spacing_max = 0;  // worst compared station, for the report
  // Station-sides compared and left out per measure: no confidence, or no truth
  // (no vane there in the generated feather).
  int angle_used = 0, angle_low_conf = 0, angle_no_truth = 0;
  int spacing_used = 0, spacing_low_conf = 0, spacing_no_truth = 0;
  int width_used = 0, width_low_conf = 0;
  std::filesystem::path photo;  // the degraded render that was analysed
  Image overlay;                // the analysis overlay with the truth drawn on it
  bool passes(const Bounds& b) const;
};

// `count` plausible feathers from `seed` (splits and afterfeather off) whose barbs
// are at least ~4.5 px apart at `long_side_px`.
std::vector<FeatherParams> draw_params(int count, std::uint64_t seed, int long_side_px);

// Builds, renders, degrades, analyses and scores one feather on one background.
CaseResult run_case(const FeatherParams& params, int index, bool dark, const StudyOptions& options);

// Every drawn feather on white and on black.
std::vector<CaseResult> run_study(const StudyOptions& options);

// The markdown table of the results, with the bounds, and the worst and median of
// each error over all cases.
std::string report_markdown(const std::vector<CaseResult>& results, const StudyOptions& options,
                            const Bounds& bounds);

}  // namespace plumage::closed_loop
