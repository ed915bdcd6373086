# `cpack -G DEB` in the build folder: aperture_<version>_<arch>.deb, which
# installs with `apt-get install ./aperture_*.deb` on Debian 12 (its Depends
# come from dpkg-shlibdeps) and which lintian passes without errors.
set(CPACK_PACKAGE_NAME aperture)
set(CPACK_PACKAGE_VENDOR "The aperture authors")
set(CPACK_PACKAGE_CONTACT "The aperture authors <maintainers@aperture.example>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "ambient aperture lighting for terrain (DEMs)")
set(CPACK_PACKAGE_DESCRIPTION
    "aperture lights digital elevation models by the sun and the sky in real time.
It bakes, for every texel of a heightfield, the visible part of the sky as a
spherical cap (bent normal and arc length), and renders the terrain with soft
sun shadows, sky light and local inter-reflection, on any Vulkan device or on
the CPU (lavapipe). Tools: aal-bake (aperture maps, sky-view factor),
aal-render (headless images and movies), aal-view (interactive viewer),
aal-relief (shaded-relief GeoTIFFs), aal-info, aal-caps and aal-synth.
Also the static libraries with their headers, CMake package config and
pkg-config file, and the Python module aperture.")
set(CPACK_RESOURCE_FILE_LICENSE ${CMAKE_SOURCE_DIR}/LICENSE)
set(CPACK_RESOURCE_FILE_README ${CMAKE_SOURCE_DIR}/README.md)
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The CPU Vulkan driver is loaded at run time, not linked; the Python
# module imports numpy (and aperture.rio rasterio).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "mesa-vulkan-drivers, python3, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-rasterio, vulkan-validationlayers, ffmpeg")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
include(CPack)
