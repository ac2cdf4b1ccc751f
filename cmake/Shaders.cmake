# Compiles *.comp.glsl to SPIR-V at build time and embeds it in a C++ library; a shader error fails the build.
#
# dentsim_add_shader_library(NAME SOURCES a.comp.glsl ... INCLUDE_DIRS dir ... DEPENDS header ...)
# makes target NAME with a header "NAME_spirv.h" declaring, per shader file "foo.comp.glsl",
#   extern const uint32_t foo_comp_spv[]; extern const size_t foo_comp_spv_words;
function(dentsim_add_shader_library NAME)
  cmake_parse_arguments(ARG "" "" "SOURCES;INCLUDE_DIRS;DEPENDS" ${ARGN})
  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/${NAME})
  file(MAKE_DIRECTORY ${gen_dir})
  set(include_flags)
  foreach(dir IN LISTS ARG_INCLUDE_DIRS)
    list(APPEND include_flags -I${dir})
  endforeach()
  set(header ${gen_dir}/${NAME}_spirv.h)
  set(header_text "// Generated: SPIR-V of dentsim's shaders (${NAME}).\n#pragma once\n#include <cstddef>\n#include <cstdint>\n")
  set(cpp_sources)
  foreach(src IN LISTS ARG_SOURCES)
    get_filename_component(file_name ${src} NAME)
    string(REGEX REPLACE "\\.glsl$" "" stage_name ${file_name})
    # The stage is the name's last part before .glsl: comp, vert or frag.
    string(REGEX MATCH "[a-z]+$" shader_stage ${stage_name})
    string(REPLACE "." "_" symbol ${stage_name})
    set(symbol ${symbol}_spv)
    set(num_file ${gen_dir}/${stage_name}.spv.inc)
    add_custom_command(
      OUTPUT ${num_file}
      COMMAND ${GLSLC} -fshader-stage=${shader_stage} --target-env=vulkan1.2 -O -Werror ${include_flags}
              -mfmt=num -MD -MF ${num_file}.d -o ${num_file} ${CMAKE_CURRENT_SOURCE_DIR}/${src}
      DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${src} ${ARG_DEPENDS}
      DEPFILE ${num_file}.d
      COMMENT "glslc ${src}"
      VERBATIM)
    set(cpp ${gen_dir}/${stage_name}.spv.cpp)
    file(CONFIGURE OUTPUT ${cpp} CONTENT
"// Generated from ${src}.
#include <cstddef>
#include <cstdint>
extern const uint32_t ${symbol}[] = {
#include \"${stage_name}.spv.inc\"
};
extern const size_t ${symbol}_words = sizeof(${symbol}) / sizeof(uint32_t);
")
    set_source_files_properties(${cpp} PROPERTIES OBJECT_DEPENDS ${num_file})
    list(APPEND cpp_sources ${cpp})
    string(APPEND header_text "extern const uint32_t ${symbol}[];\nextern const size_t ${symbol}_words;\n")
  endforeach()
  file(CONFIGURE OUTPUT ${header} CONTENT "${header_text}")
  add_library(${NAME} STATIC ${cpp_sources})
  target_include_directories(${NAME} PUBLIC ${gen_dir})
endfunction()
