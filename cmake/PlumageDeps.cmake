# Finds every third-party package Plumage builds against (Debian 12 packages;
# scripts/setup.sh installs them) and exposes each as an imported target.

find_package(glm REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
# OpenImageIO only for the image module (formats other than PNG, EXR and JPEG,
# and writing JPEG); PNG and EXR go through libpng and OpenEXR directly.
find_package(OpenImageIO REQUIRED)
find_package(OpenEXR 3 CONFIG REQUIRED)
find_package(PNG REQUIRED)
# Reading JPEG (most photos) goes through libjpeg directly too.
find_package(JPEG REQUIRED)
find_package(TBB REQUIRED)
# Photos are decoded by read_image (common/image.h): no imgcodecs.
find_package(OpenCV REQUIRED COMPONENTS core imgproc)
find_package(GTest REQUIRED)
if(PLUMAGE_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()

# Embree 3 (Debian ships embree-config.cmake defining the `embree` target).
find_package(embree 3 REQUIRED)
if(NOT TARGET plumage::embree)
  add_library(plumage::embree INTERFACE IMPORTED)
  set_target_properties(plumage::embree PROPERTIES INTERFACE_LINK_LIBRARIES embree)
endif()

# OpenSubdiv: Debian 12's OpenSubdivConfig.cmake names static libraries the
# package does not ship and stops CMake, so find the CPU library and the headers
# directly and wrap them in an imported target.
find_library(OSD_CPU_LIBRARY NAMES osdCPU REQUIRED)
find_path(OSD_INCLUDE_DIR opensubdiv/far/topologyRefiner.h REQUIRED)
if(NOT TARGET plumage::opensubdiv)
  add_library(plumage::opensubdiv UNKNOWN IMPORTED)
  set_target_properties(plumage::opensubdiv PROPERTIES
    IMPORTED_LOCATION "${OSD_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OSD_INCLUDE_DIR}")
endif()
