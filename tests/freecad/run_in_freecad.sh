#!/usr/bin/env bash
# Run one headless FreeCAD test file (plain unittest) under freecadcmd and turn
# its outcome into this script's exit status. Used by ctest, or by hand:
#   tests/freecad/run_in_freecad.sh tests/freecad/test_bad_input.py
#
# freecadcmd swallows exceptions (exit status 0), so the runner writes PASS or
# FAIL to a result file and this script trusts only that file and the exit
# status together: a crash, a hang killed by ctest or an import error all end
# without "PASS" in the file.
#
# Environment (ctest sets all three; by hand they default to this checkout):
#   ISOCAM_ADDON_DIR  the built addon (freecad_ext + isocam_core), put on sys.path
#   ISOCAM_TEST_DATA  the test models (tests/data)
#   ISOCAM_BUILD_DIR  the build tree
set -euo pipefail

if [ $# -ne 1 ] || [ ! -f "$1" ]; then
  echo "usage: $0 tests/freecad/test_something.py" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
test_file=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")

export ISOCAM_BUILD_DIR=${ISOCAM_BUILD_DIR:-$root/build}
export ISOCAM_ADDON_DIR=${ISOCAM_ADDON_DIR:-$ISOCAM_BUILD_DIR/addon/IsoCAM}
export ISOCAM_TEST_DATA=${ISOCAM_TEST_DATA:-$root/tests/data}

FREECADCMD=${FREECADCMD:-$(command -v freecadcmd || command -v FreeCADCmd || true)}
if [ -z "$FREECADCMD" ]; then
  echo "run_in_freecad: freecadcmd not found (Debian package freecad-python3)" >&2
  exit 1
fi

# A private HOME: the test must not depend on (or change) the user's FreeCAD
# preferences, Mod folder or recent-file list.
scratch=$(mktemp -d "${TMPDIR:-/tmp}/isocam-fctest.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/home" "$scratch/tmp"
export HOME=$scratch/home
unset XDG_CONFIG_HOME XDG_DATA_HOME XDG_CACHE_HOME
export XDG_RUNTIME_DIR=$scratch/tmp
export TMPDIR=$scratch/tmp
export ISOCAM_TEST_FILE=$test_file
export ISOCAM_RESULT_FILE=$scratch/result

status=0
"$FREECADCMD" "$here/freecad_runner.py" || status=$?

result=$(cat "$ISOCAM_RESULT_FILE" 2>/dev/null || echo "NO RESULT (freecadcmd ended before the runner finished)")
echo "run_in_freecad: $(basename "$test_file"): $result (freecadcmd exit status $status)"
if [ "$result" = "PASS" ] && [ "$status" -eq 0 ]; then
  exit 0
fi
exit 1
