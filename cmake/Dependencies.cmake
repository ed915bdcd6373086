# Finds every dependency; a missing one stops configuration with the Debian
# package that provides it (scripts/install-deps.sh installs them all).

function(aal_missing what apt_package)
  message(FATAL_ERROR
    "aperture: ${what} not found. Install it with\n"
    "    sudo apt-get install ${apt_package}\n"
    "or run scripts/install-deps.sh to install every dependency.")
endfunction()

macro(aal_find_package name apt_package)
  find_package(${name} ${ARGN} QUIET)
  if(NOT ${name}_FOUND)
    aal_missing(${name} ${apt_package})
  endif()
endmacro()

aal_find_package(Vulkan libvulkan-dev)
aal_find_package(glslang glslang-dev CONFIG)
find_program(AAL_GLSLANG_VALIDATOR glslangValidator)
if(NOT AAL_GLSLANG_VALIDATOR)
  aal_missing(glslangValidator glslang-tools)
endif()
aal_find_package(glfw3 libglfw3-dev CONFIG)
aal_find_package(glm libglm-dev CONFIG)
# Aperture maps are EXR files, read and written with OpenEXR's own library.
aal_find_package(Imath libimath-dev CONFIG)
aal_find_package(OpenEXR libopenexr-dev CONFIG)
aal_find_package(OpenImageIO libopenimageio-dev CONFIG)
# Debian's OpenImageIO config lists /usr/include/opencv4 although OpenCV's
# headers are optional; drop include folders that do not exist.
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
set(_oiio_existing)
foreach(dir IN LISTS _oiio_includes)
  if(EXISTS "${dir}")
    list(APPEND _oiio_existing "${dir}")
  endif()
endforeach()
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${_oiio_existing}")
# Debian installs GeographicLib's find module outside CMake's default path.
list(APPEND CMAKE_MODULE_PATH /usr/share/cmake/geographiclib)
aal_find_package(GeographicLib libgeographiclib-dev)
if(NOT TARGET GeographicLib::GeographicLib)
  add_library(GeographicLib::GeographicLib INTERFACE IMPORTED)
  set_target_properties(GeographicLib::GeographicLib PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${GeographicLib_INCLUDE_DIRS}"
    INTERFACE_LINK_LIBRARIES "${GeographicLib_LIBRARIES}")
endif()
aal_find_package(GDAL libgdal-dev)
aal_find_package(TBB libtbb-dev CONFIG)
aal_find_package(CLI11 libcli11-dev CONFIG)
find_package(PkgConfig QUIET)
if(NOT PKG_CONFIG_FOUND)
  aal_missing(pkg-config pkg-config)
endif()
pkg_check_modules(IMGUI QUIET IMPORTED_TARGET imgui)
if(NOT IMGUI_FOUND)
  aal_missing("Dear ImGui (pkg-config imgui)" "libimgui-dev libstb-dev")
endif()
# XXH64 for the aperture maps' pixel checksum (terrain/io/pixel_checksum.h).
pkg_check_modules(XXHASH QUIET IMPORTED_TARGET libxxhash)
if(NOT XXHASH_FOUND)
  aal_missing("xxHash (pkg-config libxxhash)" libxxhash-dev)
endif()
if(AAL_BUILD_TESTS OR AAL_FUZZ)
  aal_find_package(GTest "libgtest-dev libgmock-dev")
endif()
if(AAL_BUILD_BENCH)
  aal_find_package(benchmark libbenchmark-dev CONFIG)
endif()
# The Python module (python/): pybind11 and numpy from Debian's packages, for
# Debian's own python3 (a python3 earlier on PATH, a pyenv one say, has not
# got them); -DPython3_EXECUTABLE picks another. Built whenever both are
# there; scripts/install-deps.sh installs them.
set(AAL_PYTHON_FOUND OFF)
if(AAL_PYTHON)
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 COMPONENTS Interpreter Development.Module NumPy QUIET)
  find_package(pybind11 CONFIG QUIET)
  if(Python3_FOUND AND Python3_NumPy_FOUND AND pybind11_FOUND)
    set(AAL_PYTHON_FOUND ON)
  else()
    message(STATUS "aperture: the Python module is not built (install python3-dev "
                   "python3-numpy pybind11-dev, or run scripts/install-deps.sh)")
  endif()
endif()
# The tiled bake across MPI ranks (aal-bake-mpi); mpiexec runs its tests.
if(AAL_MPI)
  find_package(MPI COMPONENTS CXX QUIET)
  if(NOT MPI_CXX_FOUND OR NOT MPIEXEC_EXECUTABLE)
    aal_missing("MPI (Open MPI's mpicxx and mpirun)" "libopenmpi-dev openmpi-bin")
  endif()
endif()
