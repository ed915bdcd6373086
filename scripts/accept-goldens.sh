#!/usr/bin/env bash
# Re-renders the golden images of tests/golden/ after a reviewed change of the
# renderer. Review the new pictures (git diff --stat, an image viewer) before
# committing them.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" --target render_tests >/dev/null
cd "${AAL_BUILD_DIR:-$root/build}/tests"
AAL_VALIDATION=1 AAL_ACCEPT_GOLDENS=1 ./render_tests --gtest_filter='Render.Golden*'
echo "goldens written to $root/tests/golden/"
