# Third-party libraries, found the way that works on Debian bookworm
# (see docs/ARCHITECTURE.md, "Dependencies").
find_package(PkgConfig REQUIRED)

set(BLA_VENDOR OpenBLAS)
find_package(BLAS REQUIRED)
find_path(CBLAS_INCLUDE_DIR cblas.h PATH_SUFFIXES openblas REQUIRED)

find_package(OpenMP REQUIRED COMPONENTS C)
find_package(cJSON CONFIG REQUIRED)
find_package(OpenEXR CONFIG REQUIRED)

# OpenImageIO's exported CMake target drags /usr/include/opencv4 in; pkg-config is clean.
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
# OpenColorIO 2.1's CMake config is broken on Debian.
pkg_check_modules(OCIO REQUIRED IMPORTED_TARGET OpenColorIO)

find_library(MATH_LIBRARY m REQUIRED)

# glTF 2.0 meshes for `nbrdf render --mesh` (src/render/mesh_gltf.cpp): Debian ships TinyGLTF
# as a header plus a shared library holding its implementation (libtinygltf-dev).
find_path(TINYGLTF_INCLUDE_DIR tiny_gltf.h)
find_library(TINYGLTF_LIBRARY tinygltf)
if(NOT TINYGLTF_INCLUDE_DIR OR NOT TINYGLTF_LIBRARY)
  message(FATAL_ERROR "TinyGLTF not found (tiny_gltf.h: ${TINYGLTF_INCLUDE_DIR}, libtinygltf: "
    "${TINYGLTF_LIBRARY}); it reads glTF meshes for 'nbrdf render --mesh'. On Debian: "
    "apt-get install libtinygltf-dev (scripts/setup-debian.sh installs it).")
endif()
