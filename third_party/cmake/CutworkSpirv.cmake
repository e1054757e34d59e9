# cutwork_add_spirv(TARGET <lib> SHADERS a.comp b.comp)
# Compiles each GLSL compute shader to SPIR-V with glslangValidator at build time and embeds it
# as a uint32_t array in a generated header <name>_spv.h in the build tree (never in the source
# tree). The header declares `static const uint32_t <name>_spv[]`; include it as "<name>_spv.h".
function(cutwork_add_spirv)
  cmake_parse_arguments(ARG "" "TARGET" "SHADERS" ${ARGN})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/spirv)
  file(MAKE_DIRECTORY ${out_dir})
  set(headers)
  foreach(src ${ARG_SHADERS})
    get_filename_component(name ${src} NAME_WE)
    get_filename_component(abs ${src} ABSOLUTE)
    set(hdr ${out_dir}/${name}_spv.h)
    add_custom_command(
      OUTPUT ${hdr}
      COMMAND ${Vulkan_GLSLANG_VALIDATOR_EXECUTABLE} -V --target-env vulkan1.1 --vn ${name}_spv
              --depfile ${hdr}.d -o ${hdr} ${abs}
      DEPENDS ${abs}
      DEPFILE ${hdr}.d
      COMMENT "glslang: ${name}.comp -> SPIR-V"
      VERBATIM)
    list(APPEND headers ${hdr})
  endforeach()
  target_sources(${ARG_TARGET} PRIVATE ${headers})
  target_include_directories(${ARG_TARGET} PRIVATE ${out_dir})
endfunction()
