#!/usr/bin/env bash
# Configures and builds aperture into build/ (or $AAL_BUILD_DIR).
# Environment: AAL_WERROR=ON for warnings as errors, AAL_SANITIZE=ON for
# ASan+UBSan (default build folder build-sanitize/), AAL_BUILD_TYPE (Release),
# AAL_MPI=OFF to leave out aal-bake-mpi and its tests (on by default: CI
# and the README's test command build it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sanitize=${AAL_SANITIZE:-OFF}
default_dir="$root/build"
[ "$sanitize" = ON ] && default_dir="$root/build-sanitize"
build_dir=${AAL_BUILD_DIR:-$default_dir}
build_type=${AAL_BUILD_TYPE:-Release}
[ "$sanitize" = ON ] && build_type=${AAL_BUILD_TYPE:-RelWithDebInfo}

"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
  -DAAL_WERROR="${AAL_WERROR:-OFF}" -DAAL_SANITIZE="$sanitize" -DAAL_MPI="${AAL_MPI:-ON}" \
  >/dev/null
cmake --build "$build_dir" "$@"
