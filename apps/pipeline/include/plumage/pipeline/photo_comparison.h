#pragma once
// The chains several commands, studies and benchmarks share (DESIGN §2,
// apps/pipeline): a layout's feather to its curves (`generate --layout`,
// photo-to-feather), one feather rendered in both shading modes (`compare`,
// photo-to-feather), and the photo beside those renders in one pose with their
// fidelity measured (photo-to-feather, scripts/photo_study.sh, the tests).
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "plumage/common/feather.h"
#include "plumage/common/image.h"
#include "plumage/layout/layout.h"
#include "plumage/pipeline/colour_calibration.h"
#include "plumage/pipeline/fidelity.h"
#include "plumage/pipeline/photo_view.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/panel_layout.h"

namespace plumage {

class FileBatch;

// layout -> feather (turned onto the analysed shaft, the photo's albedo as a
// texture written to `texture_path`) -> validated; the curves written to
// `fcurves_path` and, when `preview_path` is given, a top view of `preview_size`
// pixels, all staged in `outputs`. Warnings (values analysis was unsure of) are
// appended to `warnings`.
Feather generate_from_layout(const FeatherLayout& layout, std::uint64_t seed, const std::filesystem::path& layout_path,
                             const std::filesystem::path& fcurves_path, const std::filesystem::path& preview_path,
                             int preview_size, FileBatch& outputs, std::vector<std::string>* warnings);

// Both scenes (hair, substructure) are built before either renders, so a bad
// substructure parameter fails before any time is spent.
std::vector<Panel> render_both_modes(const Feather& feather, SceneOptions scene, const DomeRig& rig,
                                     const ViewSpec& view);

// One dome LED at a time (the paper's Fig. 5): per shading mode a contact sheet of
// labelled tiles in rows of `columns`, titled "MODE: one LED at a time"; each
// returned panel is a sheet labelled with its mode ("hair", "substructure").
// Throws plumage::Error when view.lights selects no LED.
std::vector<Panel> light_sequence_sheets(const Feather& feather, SceneOptions scene, const DomeRig& rig,
                                         const ViewSpec& view, int columns);

// The photo, cropped around the picked feather, and the feather's renders in the
// same pose (photo_view.h), with their fidelity against the photo.
struct PhotoComparison {
  PhotoCrop crop;         // the panels
  PhotoCrop render_grid;  // what the renders were traced on (render_grid_for), then shown on the panels
  int render_spp = 0;     // samples per pixel of render_grid
  PanelRegions regions;
  std::vector<Panel> panels;  // photo, hair, substructure
  FidelitySettings settings;
  std::vector<MeasuredPanel> measured;  // as panels
  std::vector<RenderFidelity> fidelity;  // hair, substructure
  std::vector<InversionCounts> inversion;  // hair, substructure: how the texture's texels were inverted
  std::vector<ColourCalibration> calibration;  // hair, substructure: their colour calibration
};

// `view` gives the sampling, lights, threads and the folder the feather's texture
// path is relative to; its size, camera and exposure are set here (panels `size`
// pixels along their longer side, the crop's camera, the card developed to the
// photo's background colour). Where the photo holds fewer pixels than the panel,
// the renders are traced on the photo's grid with the panel's samples gathered
// there (render_grid_for, render_spp_for) and then shown at panel size.
PhotoComparison compare_with_photo(const Image& photo, const Layout& layout, const FeatherLayout& picked,
                                   const Feather& feather, const DomeRig& rig, ViewSpec view, int size,
                                   const FidelitySettings& settings = {}, const CalibrationSettings& calibration = {});

// photo | hair | substructure, labelled.
Image comparison_image(const PhotoComparison& c);
// Per render panel: the silhouettes against the photo's and the pixel ΔE 2000.
Image fidelity_image(const PhotoComparison& c);
// {"settings": ..., "hair": ..., "substructure": ...}
nlohmann::json fidelity_json(const PhotoComparison& c);

}  // namespace plumage
