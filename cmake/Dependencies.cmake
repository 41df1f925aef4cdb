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
