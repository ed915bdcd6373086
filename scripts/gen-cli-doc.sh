#!/usr/bin/env bash
# Writes every tool's --help into docs/cli.md, below its marker line; the
# hand-written part above the marker is kept as it is.
#   scripts/gen-cli-doc.sh [BUILD_DIR]           regenerate docs/cli.md
#   scripts/gen-cli-doc.sh --check [BUILD_DIR]   fail when docs/cli.md differs
#                                                from the tools' --help (the
#                                                CliDoc.MatchesTheToolsHelp test)
# BUILD_DIR defaults to $AAL_BUILD_DIR, else build/; the tools are in its bin/.
# In --check, a tool that was not built (aal-bake-mpi with -DAAL_MPI=OFF)
# keeps its section from docs/cli.md, unchecked.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
check=0
if [ "${1:-}" = --check ]; then
  check=1
  shift
fi
build_dir=${1:-${AAL_BUILD_DIR:-$root/build}}
doc=$root/docs/cli.md
marker='<!-- Generated below by scripts/gen-cli-doc.sh from each tool'"'"'s --help. Do not edit below this line. -->'
tools=(aal-bake aal-bake-mpi aal-render aal-relief aal-view aal-info aal-synth aal-caps)

# The help must not depend on the machine: CLI11 ignores the terminal's
# width, but fix it anyway, with the locale; no display for aal-view; no
# leak report at exit in a sanitizer build (Open MPI's start-up leaks).
export LC_ALL=C COLUMNS=100
unset DISPLAY WAYLAND_DISPLAY
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"

if ! grep -qxF -- "$marker" "$doc"; then
  echo "$doc has no marker line; it must hold this line, with the generated part below it:" >&2
  echo "$marker" >&2
  exit 1
fi

# The section of one tool in the current docs/cli.md: from its heading to
# the next one.
section_in_doc() {
  awk -v head="## $1" '
    $0 == head { on = 1; print; next }
    on && /^## / { exit }
    on { print }' "$doc"
}

generate() {
  awk -v marker="$marker" '{ print } $0 == marker { exit }' "$doc"
  for tool in "${tools[@]}"; do
    echo
    if [ ! -x "$build_dir/bin/$tool" ]; then
      if [ "$check" = 1 ] && section_in_doc "$tool" | grep -q .; then
        echo "note: $build_dir/bin/$tool was not built: its section is not checked" >&2
        section_in_doc "$tool" | sed -e :a -e '/^\n*$/{$d;N;ba' -e '}'
        continue
      fi
      echo "$build_dir/bin/$tool is missing: build the tools first (scripts/build.sh)" >&2
      return 1
    fi
    echo "## $tool"
    echo
    echo '```text'
    if ! "$build_dir/bin/$tool" --help; then
      echo "$tool --help failed" >&2
      return 1
    fi
    echo '```'
  done
}

tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
generate >"$tmp"

if [ "$check" = 0 ]; then
  cp "$tmp" "$doc"
  echo "wrote $doc"
  exit 0
fi
if ! diff -u "$doc" "$tmp" >&2; then
  echo >&2
  echo "docs/cli.md differs from the tools' --help (above: - the page, + the tools)." >&2
  echo "Regenerate it with: scripts/gen-cli-doc.sh $build_dir" >&2
  exit 1
fi
echo "docs/cli.md matches the --help of every tool"
