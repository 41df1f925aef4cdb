# The GPU backend's kernels (src/gpu/kernels/*.comp) -> SPIR-V as C arrays (glslangValidator
# --vn), embedded in libnbrdf: no shader files at run time. The backend needs the Vulkan
# headers only (the loader is dlopen()ed at run time, src/gpu/gpu_vk.h); without glslang or
# the headers, or with -DNBRDF_BUILD_SHADERS=OFF, src/gpu compiles to its stub (gpu_stub.c:
# "built without GPU support").
# Sets NBRDF_GPU_SPIRV_HEADERS (generated headers, to list among the library's sources) and
# NBRDF_HAVE_GPU (0/1).
set(NBRDF_HAVE_GPU 0)
set(NBRDF_GPU_SPIRV_HEADERS)
if(NBRDF_BUILD_SHADERS)
  find_program(NBRDF_GPU_GLSLANG glslangValidator)
  find_path(NBRDF_VULKAN_INCLUDE_DIR vulkan/vulkan.h)
  if(NBRDF_GPU_GLSLANG AND NBRDF_VULKAN_INCLUDE_DIR)
    set(NBRDF_HAVE_GPU 1)
  else()
    message(STATUS "nbrdf: no glslangValidator or Vulkan headers: the GPU backend is a stub")
  endif()
endif()
if(NBRDF_HAVE_GPU)
  set(gen ${CMAKE_CURRENT_BINARY_DIR}/generated)
  file(GLOB gpu_kernels CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/gpu/kernels/*.comp)
  foreach(src IN LISTS gpu_kernels)
    get_filename_component(name ${src} NAME_WE)
    set(out ${gen}/gpu_spv_${name}.h)
    add_custom_command(OUTPUT ${out}
      COMMAND ${NBRDF_GPU_GLSLANG} -V --target-env vulkan1.1 --vn gpu_spv_${name} -o ${out} ${src}
      DEPENDS ${src}
      COMMENT "GLSL -> SPIR-V (embedded) gpu_spv_${name}.h" VERBATIM)
    list(APPEND NBRDF_GPU_SPIRV_HEADERS ${out})
  endforeach()
endif()
