# What `cmake --install build --prefix P` puts under P (and the .deb under
# /usr, cmake/Packaging.cmake):
#   bin/                        the tools
#   lib/aperture/               the image plugin (found from bin/ by its
#                               relative path, terrain/io/image_plugin.h)
#   lib/libaperture_*.a         the libraries, as aperture:: targets of
#   lib/cmake/aperture/         find_package(aperture 0.2 CONFIG)
#   lib/pkgconfig/aperture.pc   and pkg-config
#   include/aperture/...        their headers, as the sources include them
#   lib/python3/dist-packages/  the Python module (python/CMakeLists.txt)
#   share/doc/aperture/         copyright and changelog
#   share/aperture/qgis/        the QGIS Processing plugin aperture_processing
#                               (QGIS_PLUGINPATH; docs/gis.md, "QGIS")
#   share/man/man1/             a manual page per tool (cmake/ManPages.cmake)
# The shaders are inside the libraries (engine/vk/embedded_shaders.h).
include(CMakePackageConfigHelpers)

set(AAL_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/aperture)
set(AAL_PLUGIN_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/aperture)

set(aal_tools aal-caps aal-info aal-synth aal-bake aal-render aal-view aal-relief)
if(AAL_MPI)
  list(APPEND aal_tools aal-bake-mpi)
endif()
install(TARGETS ${aal_tools} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS aal_oiio_images LIBRARY DESTINATION ${AAL_PLUGIN_INSTALL_DIR})

# The libraries: aperture::terrain (CPU data and math, file formats),
# aperture::preprocess (baking), aperture::engine (the Vulkan renderer),
# aperture::window (GLFW window, swapchain, ImGui overlay) and
# aperture::config (the include root, shared with the shaders).
foreach(library terrain preprocess engine window config)
  set_target_properties(aal_${library} PROPERTIES EXPORT_NAME ${library})
endforeach()
foreach(library terrain preprocess engine window)
  set_target_properties(aal_${library} PROPERTIES OUTPUT_NAME aperture_${library})
endforeach()
install(TARGETS aal_terrain aal_preprocess aal_engine aal_window aal_config
        EXPORT apertureTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(folder terrain preprocess engine)
  install(DIRECTORY ${folder}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/aperture/${folder}
          FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES shaders/config.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/aperture/shaders)

# The QGIS plugin is Python and metadata only; it finds the tools in
# PREFIX/bin from where it is installed (python/qgis/aperture_processing/tools.py).
install(DIRECTORY python/qgis/aperture_processing
        DESTINATION ${CMAKE_INSTALL_DATADIR}/aperture/qgis
        FILES_MATCHING PATTERN "*.py" PATTERN "metadata.txt" PATTERN "__pycache__" EXCLUDE)

install(EXPORT apertureTargets NAMESPACE aperture:: DESTINATION ${AAL_CMAKE_INSTALL_DIR})
configure_package_config_file(cmake/apertureConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/apertureConfig.cmake
                              INSTALL_DESTINATION ${AAL_CMAKE_INSTALL_DIR})
# 0.x: a minor version may change the API, so 0.2 accepts 0.2.* only.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/apertureConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/apertureConfig.cmake
              ${CMAKE_BINARY_DIR}/apertureConfigVersion.cmake
        DESTINATION ${AAL_CMAKE_INSTALL_DIR})

# pkg-config: static libraries, so their dependencies are in Requires and
# Libs, not in the .private fields. GeographicLib, OpenEXR and xxHash are
# private to aperture_terrain but must still be linked.
# The prefix relative to the .pc file, so that any --prefix keeps it right.
file(RELATIVE_PATH AAL_PC_TO_PREFIX ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
configure_file(cmake/aperture.pc.in ${CMAKE_BINARY_DIR}/aperture.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/aperture.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Debian's documentation layout: the copyright in its machine-readable form
# and the changelog, compressed without a timestamp (gzip -n) so that the
# package is reproducible.
configure_file(cmake/debian/changelog.in ${CMAKE_BINARY_DIR}/debian/changelog @ONLY)
add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/debian/changelog.gz
                   COMMAND gzip -9nf -k ${CMAKE_BINARY_DIR}/debian/changelog
                   DEPENDS ${CMAKE_BINARY_DIR}/debian/changelog
                   COMMENT "changelog.gz" VERBATIM)
add_custom_target(aal_changelog ALL DEPENDS ${CMAKE_BINARY_DIR}/debian/changelog.gz)
install(FILES cmake/debian/copyright ${CMAKE_BINARY_DIR}/debian/changelog.gz
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

include(ManPages)
