#!/usr/bin/env bash
# Run one GUI test file (plain unittest) inside the real FreeCAD GUI, under a
# virtual X server (Debian's xvfb), and turn its outcome into this script's
# exit status. Used by ctest, or by hand:
#   tests/gui/run_gui_test.sh tests/gui/test_round_trip.py
#
# FreeCAD gets a private HOME and settings folder (user.cfg written below, in
# the folder FreeCAD names: a minute-based unit schema, so activating the Path
# workbench opens no modal warning; no start page; English) and finds the
# built addon as Mod/IsoCAM there. Nothing of the user's FreeCAD set-up is
# read or changed.
#
# No hangs: the runner inside FreeCAD fails the test with a screenshot when a
# dialog nobody expects stays open, or when ISOCAM_GUI_TIMEOUT seconds pass;
# `timeout` kills FreeCAD a little later if even that cannot run. The result
# counts only if the runner wrote PASS.
#
# Environment (ctest sets the first three; by hand they default to this
# checkout):
#   ISOCAM_ADDON_DIR     the built addon (freecad_ext + isocam_core)
#   ISOCAM_TEST_DATA     the test models (tests/data)
#   ISOCAM_BUILD_DIR     the build tree; screenshots go to
#                        $ISOCAM_BUILD_DIR/gui-screenshots/<test name>/
#   ISOCAM_GUI_TIMEOUT   seconds for the whole test (default 150)
set -euo pipefail

if [ $# -ne 1 ] || [ ! -f "$1" ]; then
  echo "usage: $0 tests/gui/test_something.py" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
test_file=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
test_name=$(basename "$test_file" .py)

export ISOCAM_BUILD_DIR=${ISOCAM_BUILD_DIR:-$root/build}
export ISOCAM_ADDON_DIR=${ISOCAM_ADDON_DIR:-$ISOCAM_BUILD_DIR/addon/IsoCAM}
export ISOCAM_TEST_DATA=${ISOCAM_TEST_DATA:-$root/tests/data}
export ISOCAM_GUI_TIMEOUT=${ISOCAM_GUI_TIMEOUT:-150}

FREECAD=${FREECAD:-$(command -v freecad || command -v FreeCAD || true)}
if [ -z "$FREECAD" ]; then
  echo "run_gui_test: the FreeCAD GUI (freecad) is not installed" >&2
  exit 1
fi
if ! command -v xvfb-run >/dev/null || ! command -v xauth >/dev/null; then
  echo "run_gui_test: xvfb-run and xauth are needed (Debian packages xvfb, xauth)" >&2
  exit 1
fi
if [ ! -d "$ISOCAM_ADDON_DIR/freecad_ext" ]; then
  echo "run_gui_test: no built addon at $ISOCAM_ADDON_DIR (./run build)" >&2
  exit 1
fi

scratch=$(mktemp -d "${TMPDIR:-/tmp}/isocam-guitest.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/home" "$scratch/config" "$scratch/data" \
  "$scratch/cache" "$scratch/run" "$scratch/tmp"
chmod 700 "$scratch/run"
export HOME=$scratch/home
export XDG_CONFIG_HOME=$scratch/config
export XDG_DATA_HOME=$scratch/data
export XDG_CACHE_HOME=$scratch/cache
export XDG_RUNTIME_DIR=$scratch/run
export TMPDIR=$scratch/tmp

# FreeCAD is asked where its settings and Mod folder are: FreeCAD 1.1 keeps
# them per version (.../FreeCAD/v1-1/) and, finding settings in the
# unversioned folder instead, opens a modal "migrate" dialog at start.
FREECADCMD=${FREECADCMD:-$(command -v freecadcmd || command -v FreeCADCmd || true)}
if [ -z "$FREECADCMD" ]; then
  echo "run_gui_test: freecadcmd not found (Debian package freecad-python3)" >&2
  exit 1
fi
folders=$("$FREECADCMD" -c "import FreeCAD
print('ISOCAM_CONFIG=' + FreeCAD.getUserConfigDir())
print('ISOCAM_DATA=' + FreeCAD.getUserAppDataDir())" </dev/null 2>/dev/null || true)
config_dir=$(printf '%s\n' "$folders" | sed -n 's/^ISOCAM_CONFIG=//p' | tail -n 1)
data_dir=$(printf '%s\n' "$folders" | sed -n 's/^ISOCAM_DATA=//p' | tail -n 1)
if [ -z "$config_dir" ] || [ -z "$data_dir" ]; then
  echo "run_gui_test: $FREECADCMD did not say where its user folders are" >&2
  exit 1
fi
mkdir -p "$config_dir" "$data_dir/Mod"
ln -sfn "$ISOCAM_ADDON_DIR" "$data_dir/Mod/IsoCAM"
cat > "$config_dir/user.cfg" <<'CFG'
<?xml version="1.0" encoding="UTF-8" standalone="no" ?>
<FCParameters>
  <FCParamGroup Name="Root">
    <FCParamGroup Name="BaseApp">
      <FCParamGroup Name="Preferences">
        <FCParamGroup Name="General">
          <FCText Name="AutoloadModule">NoneWorkbench</FCText>
          <FCText Name="Language">English</FCText>
        </FCParamGroup>
        <FCParamGroup Name="Units">
          <FCInt Name="UserSchema" Value="6"/>
        </FCParamGroup>
        <FCParamGroup Name="Document">
          <FCBool Name="AutoSaveEnabled" Value="0"/>
          <FCBool Name="CreateNewDoc" Value="0"/>
        </FCParamGroup>
        <FCParamGroup Name="Mod">
          <FCParamGroup Name="Path">
            <FCBool Name="WarningSuppressVelocity" Value="1"/>
            <FCBool Name="WarningSuppressSelectionMode" Value="1"/>
          </FCParamGroup>
          <FCParamGroup Name="CAM">
            <FCBool Name="WarningSuppressVelocity" Value="1"/>
            <FCBool Name="WarningSuppressSelectionMode" Value="1"/>
          </FCParamGroup>
        </FCParamGroup>
      </FCParamGroup>
    </FCParamGroup>
  </FCParamGroup>
</FCParameters>
CFG

export QTWEBENGINE_CHROMIUM_FLAGS=--no-sandbox  # FreeCAD's web views as root
export ISOCAM_TEST_FILE=$test_file
export ISOCAM_RESULT_FILE=$scratch/result
export ISOCAM_LOG_FILE=$scratch/log
export ISOCAM_SCREENSHOT_DIR=$ISOCAM_BUILD_DIR/gui-screenshots/$test_name
rm -rf "$ISOCAM_SCREENSHOT_DIR"
mkdir -p "$ISOCAM_SCREENSHOT_DIR"

# -a looks for a free display from -n on; starting from a number of our own
# keeps two tests started together (ctest -j) from racing for the same one.
status=0
timeout -k 10 $((ISOCAM_GUI_TIMEOUT + 30)) \
  xvfb-run -a -n $((100 + $$ % 800)) -s "-screen 0 1600x1000x24 -nolisten tcp" \
  "$FREECAD" "$here/gui_runner.py" </dev/null >"$scratch/freecad.out" 2>&1 || status=$?

cat "$ISOCAM_LOG_FILE" 2>/dev/null || true
result=$(cat "$ISOCAM_RESULT_FILE" 2>/dev/null || echo "NO RESULT (FreeCAD ended before the runner finished)")
if [ "$result" != "PASS" ]; then
  echo "--- FreeCAD's own output (last 60 lines) ---"
  tail -n 60 "$scratch/freecad.out" || true
fi
echo "run_gui_test: $test_name: $result (exit status $status); screenshots in $ISOCAM_SCREENSHOT_DIR"
if [ "$result" = "PASS" ] && [ "$status" -eq 0 ]; then
  exit 0
fi
exit 1
