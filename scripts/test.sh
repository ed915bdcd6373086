#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (packages via apt-get), builds aperture
# and runs the whole test suite. Exits non-zero if any test fails.
#   scripts/test.sh              Release build in build/
#   AAL_SANITIZE=ON scripts/test.sh   ASan+UBSan build in build-sanitize/
#   AAL_WERROR=ON scripts/test.sh     warnings are errors (CI)
# Extra arguments go to ctest, e.g. scripts/test.sh -R Caps
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${AAL_BUILD_DIR:-$root/build}
[ "${AAL_SANITIZE:-OFF}" = ON ] && build_dir=${AAL_BUILD_DIR:-$root/build-sanitize}
export AAL_BUILD_DIR=$build_dir

"$root/scripts/build.sh"
if [ "${AAL_SANITIZE:-OFF}" = ON ]; then
  # Leaks inside the Vulkan loader and Mesa's drivers are not ours to fix
  # (the validation layer, on in every test, reports any Vulkan object we
  # fail to destroy).
  export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  # GCC 12's sanitizer runtime can take a dynamic-TLS block of glibc 2.36 for
  # one of an older layout and record a bogus range, which LeakSanitizer then
  # faults on at exit ("Tracer caught signal 11", after the work is done;
  # seen with aal-render --max-tile --mode horizon). Not tracking
  # __tls_get_addr avoids it; LeakSanitizer then scans no dynamic TLS, which
  # can only add leak reports, never hide one.
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}intercept_tls_get_addr=0"
  # The loader unloads the driver when the instance goes, and LeakSanitizer
  # then cannot name the driver's leaks to suppress them: keep lavapipe
  # loaded for the whole process (the ASan runtime must come first).
  lavapipe=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' \
    /usr/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null | head -n 1)
  if [ -n "$lavapipe" ] && [ -f "$lavapipe" ]; then
    export LD_PRELOAD="$(c++ -print-file-name=libasan.so) $lavapipe"
  fi
fi
cd "$build_dir"
ctest --output-on-failure -j"$(nproc)" "$@"
