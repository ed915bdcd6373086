# Compiles GLSL to SPIR-V 1.5 (--target-env vulkan1.2: glslang emits LocalSizeId
# for SPIR-V 1.6, which would need maintenance4) at build time into
# ${AAL_SHADER_DIR}; shaders may #include headers from shaders/ (config.h is
# shared with C++).
set(AAL_SHADER_DIR ${CMAKE_BINARY_DIR}/shaders CACHE INTERNAL "SPIR-V output folder")

# aal_add_shaders(TARGET name SOURCES a.comp b.frag ... DEPENDS headers...)
function(aal_add_shaders)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES;DEPENDS" ${ARGN})
  set(outputs)
  foreach(src ${ARG_SOURCES})
    get_filename_component(name ${src} NAME)
    set(out ${AAL_SHADER_DIR}/${name}.spv)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${AAL_SHADER_DIR}
      COMMAND ${AAL_GLSLANG_VALIDATOR} --quiet --target-env vulkan1.2
              -I${CMAKE_SOURCE_DIR}/shaders -o ${out} ${CMAKE_CURRENT_SOURCE_DIR}/${src}
      DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${src} ${ARG_DEPENDS}
      COMMENT "GLSL ${name} -> SPIR-V"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  add_custom_target(${ARG_TARGET} ALL DEPENDS ${outputs})
endfunction()
