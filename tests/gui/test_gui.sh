#!/usr/bin/env bash
# GUI test, as a person would use the viewer: run the real application under Xvfb, click the
# Visibility checkboxes with real X input events (xdotool, through XTEST), take screenshots with
# the application's own F12 (SDFGEN_SCREENSHOT_DIR), check that each toggle changes the drawn scene,
# and that Ctrl+Q exits with status 0. Every wait polls for a condition with a deadline; none is a
# fixed sleep that could race.
#
# Usage: tests/gui/test_gui.sh SDFGEN_BINARY REPO_ROOT   (ctest runs it under xvfb-run)
set -euo pipefail
sdfgen=$1
root=$2
if [ -z "${DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1280x720x24" "$0" "$@"
fi
work=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null || true; [ -n "${SDFGEN_GUI_KEEP:-}" ] || rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# Waits up to 30 s for a command to succeed.
until_ok() {
  local deadline=$((SECONDS + 30))
  until "$@"; do
    [ $SECONDS -lt $deadline ] || return 1
    sleep 0.05
  done
}

# The bunny with its field saved beside it, so that the viewer loads both at once.
cp "$root/assets/bunny.obj" "$work/bunny.obj"
"$sdfgen" bake "$work/bunny.obj" -o "$work/bunny.sdf" >/dev/null  # the panel's default settings, so the viewer takes it as current
mkdir "$work/shots"
SDFGEN_SCREENSHOT_DIR="$work/shots" "$sdfgen" view "$work/bunny.obj" >"$work/log" 2>&1 &
pid=$!

window=""
find_window() { window=$(xdotool search --onlyvisible --name '^sdfgen$' 2>/dev/null | head -1); [ -n "$window" ]; }
until_ok grep -q "^viewer ready$" "$work/log" || fail "the viewer did not start: $(cat "$work/log")"
until_ok find_window || fail "no viewer window appeared"
until_ok xdotool windowfocus --sync "$window" 2>/dev/null || fail "cannot focus the window"

xdotool mousemove --window "$window" 640 360   # keys go where the pointer is without a window manager
shots=0
# Presses F12 and waits until the application reports the screenshot written.
shoot() {
  xdotool key F12
  until_ok grep -q "^screenshot $shots:" "$work/log" || fail "screenshot $shots was not taken: $(cat "$work/log"; xdotool getwindowfocus getwindowname)"
  shots=$((shots + 1))
}
# Clicks a checkbox of the Visibility section (ImGui's default layout, panel at the top left).
click() {
  xdotool mousemove --window "$window" 27 "$1"
  xdotool click 1
}

shoot   # 0: grid + coloured model, as it starts
declare -A rows=([Grid]=86 [Polygon]=110 [Coloured_Model]=133 [SDF_volume]=156 [Ray-marched]=179 [Slice]=202)
previous=0
for name in Grid Polygon Coloured_Model SDF_volume Ray-marched Slice; do
  click "${rows[$name]}"
  shoot
  # The application reports its checkboxes with each screenshot: exactly this one must have flipped.
  before=$(grep "^screenshot $previous:" "$work/log" | tr ' ' '\n' | grep =)
  after=$(grep "^screenshot $((shots - 1)):" "$work/log" | tr ' ' '\n' | grep =)
  flipped=$(diff <(echo "$before") <(echo "$after") | grep '^>' | cut -d' ' -f2 | cut -d= -f1 || true)
  [ "$flipped" = "$name" ] || fail "clicking $name flipped '${flipped}' instead"
  if cmp -s "$work/shots/scene-$previous.png" "$work/shots/scene-$((shots - 1)).png"; then
    fail "toggling $name did not change the scene"
  fi
  echo "toggling $name changed the scene"
  previous=$((shots - 1))
done
# Toggling Slice again restores the previous scene exactly: the click really hit that checkbox.
click "${rows[Slice]}"
shoot
cmp -s "$work/shots/scene-$((previous - 1)).png" "$work/shots/scene-$((shots - 1)).png" ||
  fail "toggling Slice twice did not restore the scene"
echo "toggling Slice back restored the scene"

xdotool key ctrl+q
status=0
wait "$pid" || status=$?
[ "$status" -eq 0 ] || fail "the viewer exited with status $status: $(cat "$work/log")"
if [ -n "${SDFGEN_GUI_SHOT:-}" ]; then cp "$work/shots/window-$((shots - 2)).png" "$SDFGEN_GUI_SHOT"; fi
echo "GUI test passed: $shots screenshots, clean exit"
