#!/usr/bin/env bash
# Re-renders the golden images of tests/golden/ after a reviewed change of the
# renderer. First run the render tests: a failing golden leaves NAME.actual.png
# and NAME.diff.png beside the test binary; look at them, then accept. Review
# the new pictures (git diff --stat, an image viewer) before committing them.
# Only AAL_ACCEPT_GOLDENS=1 overwrites goldens (tests/engine/render_test.cpp).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${AAL_BUILD_DIR:-$root/build}
"$root/scripts/build.sh" --target render_tests >/dev/null
cd "$build_dir/tests"
# The test binary is not beside the image plugin that writes PNGs.
AAL_IMAGE_PLUGIN="$build_dir/bin/aal_oiio_images.so" AAL_VALIDATION=1 AAL_ACCEPT_GOLDENS=1 \
  ./render_tests --gtest_filter='Render.Golden*'
echo "goldens written to $root/tests/golden/"
