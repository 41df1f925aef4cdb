# `cmake --install`: the libraries, headers, CMake package, pkg-config file, the CLI and
# its data (default model bundle, shaders, Blender add-on, docs). See README "Install".
include(CMakePackageConfigHelpers)

install(TARGETS nbrdf_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS nbrdf_shared EXPORT nbrdfTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Unspecified
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS nbrdf EXPORT nbrdfStaticTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/nbrdf DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(nbrdf_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/nbrdf)
install(EXPORT nbrdfTargets NAMESPACE nbrdf:: DESTINATION ${nbrdf_cmake_dir})
install(EXPORT nbrdfStaticTargets NAMESPACE nbrdf:: DESTINATION ${nbrdf_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/install/nbrdfConfig.cmake.in
  ${PROJECT_BINARY_DIR}/nbrdfConfig.cmake INSTALL_DESTINATION ${nbrdf_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/nbrdfConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/nbrdfConfig.cmake ${PROJECT_BINARY_DIR}/nbrdfConfigVersion.cmake
  DESTINATION ${nbrdf_cmake_dir})

# pkg-config: the shared library by default; `--static` lists what libnbrdf.a needs.
# The prefix is found from the .pc file's own place, so a moved install still works.
file(RELATIVE_PATH NBRDF_PC_TO_PREFIX /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
configure_file(${PROJECT_SOURCE_DIR}/cmake/install/nbrdf.pc.in ${PROJECT_BINARY_DIR}/nbrdf.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/nbrdf.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# models/medium decodes at half the default's cost; models/v1, the default until 2026-11-26,
# decodes the textures baked with it; models/tails is the default fine-tuned for low-IOR and
# sharp coats (docs/MODEL_CARD_TAILS.md).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/models/default ${PROJECT_SOURCE_DIR}/models/medium
  ${PROJECT_SOURCE_DIR}/models/v1 ${PROJECT_SOURCE_DIR}/models/tails
  DESTINATION ${CMAKE_INSTALL_DATADIR}/nbrdf/models)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shaders/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nbrdf/shaders
  FILES_MATCHING PATTERN "*.glsl" PATTERN "*.comp" PATTERN "README.md")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/blender_addon/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nbrdf/blender_addon
  PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples)

# `cpack -G DEB` in the build folder: one package with all of the above under /usr. Its
# dependencies on the runtime libraries (OpenEXR, OpenImageIO, OpenColorIO, OpenBLAS, cJSON,
# libgomp) are computed by dpkg-shlibdeps from what the library and the CLI link.
set(CPACK_PACKAGE_NAME nbrdf)
set(CPACK_PACKAGE_VENDOR nbrdf)
set(CPACK_PACKAGE_CONTACT "nbrdf maintainers <nbrdf@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "neural layered BRDFs (Fan et al. 2022): bake, verify and render latent textures")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# dpkg-shlibdeps must find libnbrdf.so.0 itself when it scans the CLI and the library.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${PROJECT_BINARY_DIR}/src)
include(CPack)
