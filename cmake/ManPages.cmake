# A manual page per tool, made from its --help and --version by help2man
# (Debian's help2man) at build time and installed in share/man/man1, so that
# `man aal-bake` works after `apt-get install ./aperture_*.deb`. Skipped,
# with a message, when help2man is missing: the pages are documentation,
# not something the tools need.
find_program(AAL_HELP2MAN help2man)
if(NOT AAL_HELP2MAN)
  message(STATUS "aperture: no manual pages (install help2man, or run scripts/install-deps.sh)")
  return()
endif()

set(aal_man_names
  "aal-bake|bake aperture maps (the visible sky of every texel) from a DEM"
  "aal-bake-mpi|bake an aperture map in tiles across the ranks of an MPI job"
  "aal-render|render a DEM lit by the sun and the sky, headless"
  "aal-view|fly over a DEM lit by the sun and the sky"
  "aal-relief|write a shaded-relief GeoTIFF of a DEM, lit through its aperture map"
  "aal-info|describe what aperture reads from a DEM"
  "aal-caps|exact and approximate intersection areas of spherical caps"
  "aal-synth|write a deterministic synthetic DEM")
set(aal_man_pages)
foreach(entry IN LISTS aal_man_names)
  string(REPLACE "|" ";" entry "${entry}")
  list(GET entry 0 tool)
  list(GET entry 1 name)
  if(NOT TARGET ${tool})
    continue()
  endif()
  set(page ${CMAKE_BINARY_DIR}/man/${tool}.1)
  add_custom_command(
    OUTPUT ${page}.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/man
    # No leak report at exit in a sanitizer build (Open MPI's start-up
    # leaks in aal-bake-mpi --help): help2man reads stdout only and fails
    # on the non-zero exit LeakSanitizer gives.
    COMMAND ${CMAKE_COMMAND} -E env --unset=DISPLAY ASAN_OPTIONS=detect_leaks=0
            ${AAL_HELP2MAN} --no-info --name=${name} --output=${page} $<TARGET_FILE:${tool}>
    COMMAND gzip -9nf ${page}
    DEPENDS ${tool}
    COMMENT "man page ${tool}.1"
    VERBATIM)
  list(APPEND aal_man_pages ${page}.gz)
endforeach()
add_custom_target(aal_man_pages ALL DEPENDS ${aal_man_pages})
install(FILES ${aal_man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
