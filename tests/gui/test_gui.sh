#!/usr/bin/env bash
# GUI test, as a person would use the viewer: the real application under Xvfb at 800x500, real X
# input events (xdotool, through XTEST), the application's own screenshots (F12 with
# SDFGEN_SCREENSHOT_DIR set) and its report of where each panel widget is (widgets.txt, written
# when the layout changes), so that clicks find their targets however the panel is laid out.
# Checks: every control can be scrolled into view and Generate works; settings are validated
# (resolution 0 and 100000 refused with the reason); a band bake and a band field file show as band
# fields, said in the panel; a message appears right under the button that
# caused it; an idle viewer uses under 5% of a core; a list opened by a still click (no pointer
# motion after it) is drawn; a .npz from Recent loads as a field; a long error is shown in full;
# each 80 ms arrow tap turns 3 degrees and a held arrow 90 per second; the view checkboxes flip
# exactly their view and change the scene; the probe reports the field's trilinear value where the
# pointer is, and the iso level (within 1e-3) on the ray-marched surface; a field made from
# another mesh is warned about; an earlier action's message is greyed once another is said; at 400 ms per frame a tapped F still reframes and a click still
# toggles; the surface exports and a field compares with itself as
# equal; a field opened without a model is framed, and Shift+F frames it again; a resized window
# keeps the framing (a narrower one moves the camera back so that the scene stays in view); the
# window's title names what it shows; and (issue 40) the panel stays put under a still pointer,
# Scale works about the centre, Ctrl+Z / Ctrl+Shift+Z undo and redo removal, transforms, settings
# and a bake, Save and Export ask before replacing, a band's own memory estimate, keys in Recent
# and the file dialog, the cut following the slice, errors under the Model box, an empty view's
# hint, a field loaded in the background with progress and Cancel, the slice gizmo and its typed pose,
# the histogram range editor and the sign errors of a comparison, the field saved beside a model
# loaded in the background (the window live meanwhile), Escape closing a list first and then
# cancelling a load, and a slice move (dragged or typed) as one undo step; Ctrl+Q exits with
# status 0. Every wait
# polls with a deadline.
#
# Usage: tests/gui/test_gui.sh SDFGEN_BINARY REPO_ROOT   (ctest runs it under xvfb-run)
set -euo pipefail
sdfgen=$1
root=$2
if [ -z "${DISPLAY:-}" ]; then
  # -noreset: the server must not reset when the first viewer quits and the second connects.
  exec xvfb-run -a -s "-screen 0 1280x720x24 -noreset" "$0" "$@"
fi
work=$(mktemp -d)
pid=""
trap '[ -z "$pid" ] || kill "$pid" 2>/dev/null || true; [ -n "${SDFGEN_GUI_KEEP:-}" ] || rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  [ -f "$work/log" ] && tail -20 "$work/log" >&2
  exit 1
}
# Waits up to 30 s for a command to succeed.
until_ok() {
  local deadline=$((SECONDS + 30))
  until "$@"; do
    [ $SECONDS -lt $deadline ] || return 1
    sleep 0.05
  done
}

# The bunny with its field saved beside it (the panel's default settings, so the viewer loads it
# as current), and a small closed box with its own field for the mismatch check.
cp "$root/assets/bunny.obj" "$work/bunny.obj"
"$sdfgen" bake "$work/bunny.obj" -o "$work/bunny.sdf" >/dev/null
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/tet.obj"
"$sdfgen" bake "$work/tet.obj" -o "$work/tet.sdf" --res 8 >/dev/null
"$sdfgen" bake "$work/bunny.obj" -o "$work/bunny.npz" --res 24 >/dev/null
"$sdfgen" bake "$work/bunny.obj" -o "$work/band.npz" --res 24 --band 3 >/dev/null
mkdir -p "$work/shots" "$work/config/sdfgen"
echo "$work/bunny.npz" >"$work/config/sdfgen/recent.txt" # a field among the recent files

window=""
shots=0
# start [ENV...]: runs the viewer on the bunny (in $work, so its screenshots land there), waits
# for its window, resizes it to 800x500 and waits for the field saved beside the model to load.
# SDFGEN_GUI_OPEN names another file to open; with SDFGEN_GUI_LOADING set, start does not wait for
# the field.
start() {
  shots=0
  rm -f "$work/shots/"*
  (cd "$work" && env SDFGEN_SCREENSHOT_DIR="$work/shots" XDG_CONFIG_HOME="$work/config" "$@" "$sdfgen" "${SDFGEN_GUI_OPEN:-bunny.obj}" >"$work/log" 2>&1) &
  pid=$!
  find_window() { window=$(xdotool search --onlyvisible --name ' - sdfgen$' 2>/dev/null | head -1); [ -n "$window" ]; }
  until_ok grep -qs "^viewer ready$" "$work/log" || fail "the viewer did not start"
  until_ok find_window || fail "no viewer window appeared"
  xdotool windowsize --sync "$window" 800 500 || fail "cannot resize the window"
  until_ok xdotool windowfocus --sync "$window" 2>/dev/null || fail "cannot focus the window"
  until_ok grep -qs "^panel 0 0 [0-9]* 500 1$" "$work/shots/widgets.txt" || fail "the panel did not fill the 500-pixel height"
  [ -n "${SDFGEN_GUI_LOADING:-}" ] || until_ok eval '! grep -q "^text load_progress " "$work/shots/widgets.txt"' || fail "the saved field did not load"
}
stop() {
  xdotool key ctrl+q
  local status=0
  wait "$pid" || status=$?
  pid=""
  [ "$status" -eq 0 ] || fail "the viewer exited with status $status"
}
# Presses F12 and waits until the application reports the screenshot written.
shoot() {
  xdotool key F12
  until_ok grep -q "^screenshot $shots:" "$work/log" || fail "screenshot $shots was not taken"
  shots=$((shots + 1))
}
# widget NAME: "x0 y0 x1 y1 visible" of a panel widget, from the application's report.
widget() { grep "^$1 " "$work/shots/widgets.txt" | head -1 | cut -d' ' -f2-; }
is_visible() { [ "$(widget "$1" | cut -d' ' -f5)" = 1 ]; }
# reach NAME: scrolls the panel (wheel over it, one notch at a time, each waited for) until the
# widget is fully visible.
scroll_state() { grep "^scroll " "$work/shots/widgets.txt"; }
scrolled_from() { [ "$(scroll_state)" != "$1" ]; }
reach() {
  local deadline=$((SECONDS + 60)) rect y0 before
  until is_visible "$1"; do
    [ $SECONDS -lt $deadline ] || fail "cannot scroll '$1' into view: $(widget "$1")"
    rect=$(widget "$1")
    [ -n "$rect" ] || fail "no widget '$1' in the panel"
    y0=$(echo "$rect" | cut -d' ' -f2)
    before=$(scroll_state)
    xdotool mousemove --window "$window" 150 250
    # Above the scrolling part's top (below the probe's pinned line, when shown): scroll up.
    if [ "$y0" -lt "$(grep '^sections ' "$work/shots/widgets.txt" | cut -d' ' -f2)" ]; then xdotool click 4; else xdotool click 5; fi
    until_ok scrolled_from "$before" || fail "the panel did not scroll towards '$1' ($before)"
  done
}
# click NAME: reaches a widget and clicks its centre (its left part for wide ones).
click() {
  reach "$1"
  read -r x0 y0 x1 y1 _ <<<"$(widget "$1")"
  local x=$(((x0 + x1) / 2)) y=$(((y0 + y1) / 2))
  [ $((x1 - x0)) -lt 120 ] || x=$((x0 + 20))
  xdotool mousemove --window "$window" "$x" "$y" click 1
}
# set_text NAME TEXT: replaces a text box's content; type_into also presses Enter.
set_text() {
  click "$1"
  xdotool key ctrl+a
  xdotool type --delay 20 -- "$2"
}
type_into() {
  set_text "$1" "$2"
  xdotool key Return
}
message() { grep "^text $1 " "$work/shots/widgets.txt" | cut -d' ' -f3-; }
# The camera (yaw,pitch,distance) of screenshot N.
camera_of() { grep "^screenshot $1:" "$work/log" | sed 's/.*camera=\([^ ]*\).*/\1/'; }

start
[ "$(xdotool getwindowname "$window")" = "bunny.obj - sdfgen" ] || fail "the window's title is '$(xdotool getwindowname "$window")'"
# --- idle: nothing changes, so nothing is drawn; CPU over 5 s under 5% of a core.
xdotool mousemove --window "$window" 790 490
sleep 0.5
ticks() { awk '{print $14 + $15}' "/proc/$pid/stat"; }
t0=$(ticks)
sleep 5
t1=$(ticks)
hz=$(getconf CLK_TCK)
cpu=$(awk -v t="$((t1 - t0))" -v hz="$hz" 'BEGIN { printf "%.2f", 100 * t / hz / 5 }')
awk -v c="$cpu" 'BEGIN { exit !(c < 5) }' || fail "an idle viewer used $cpu% of a core"
echo "idle viewer: $cpu% of a core over 5 s"

# --- every control of the panel can be scrolled into view at 800x500.
names=$(grep -vE '^(text|stale|panel|sections|scroll|draws) ' "$work/shots/widgets.txt" | cut -d' ' -f1)
count=0
for name in $names; do
  reach "$name"
  count=$((count + 1))
done
[ "$count" -ge 40 ] || fail "only $count widgets reported"
echo "all $count panel widgets reached at 800x500"

# --- a list opened by a still click is drawn at once: click Recent without moving the pointer
# after the click, then wait; its entries must be on screen (not hidden while ImGui measures them).
reach model_recent
read -r x0 y0 x1 y1 _ <<<"$(widget model_recent)"
xdotool mousemove --window "$window" $(((x0 + x1) / 2)) $(((y0 + y1) / 2))
sleep 0.5
xdotool click 1
sleep 1
grep -q "^recent_1 .* 1$" "$work/shots/widgets.txt" || fail "the Recent list opened by a still click is not drawn: $(grep '^recent_' "$work/shots/widgets.txt" | tr '\n' ' ')"
echo "Recent opened by a still click: drawn"
# --- a .npz picked from Recent loads as a field (not as a mesh), said under Model where it was picked.
click recent_1
until_ok grep -q "^message model info: loaded $work/bunny.npz" "$work/log" || fail "the .npz from Recent did not load as a field"
until_ok grep -q "^text stats method .* loaded" "$work/shots/widgets.txt" || fail "the panel does not show the .npz's figures"
echo "a .npz from Recent: $(grep '^message model info: loaded .*npz' "$work/log")"

# --- a long error is shown in full: wrapped, every word of it on screen.
long="$work/a-folder-with-a-rather-long-name-to-make-the-message-wrap/and-another-one-inside-it/missing-field.npz"
type_into field_path "$long"
until_ok grep -q "^message field error: .*missing-field.npz" "$work/log" || fail "no error for a missing field"
reach '##field_message'
read -r _ ey0 _ ey1 evisible <<<"$(widget '##field_message')"
line_height=$(( $(widget field_save | cut -d' ' -f4) - $(widget field_save | cut -d' ' -f2) ))
[ "$evisible" = 1 ] && [ $((ey1 - ey0)) -ge $((2 * line_height)) ] || fail "the long error is not wrapped in full view ($ey0-$ey1, visible $evisible)"
message '##field_message' | grep -q "missing-field.npz: .*)$" || fail "the error's text is cut: $(message '##field_message')"
echo "long error in full, $((ey1 - ey0)) px high: $(message '##field_message')"
type_into field_path "$work/bunny.sdf"

# --- arrows: each 80 ms tap turns 3 degrees (the frame after idle does not count the idle time);
# holding turns 90 degrees a second after the first quarter second. The rotation is measured per
# tap, over four taps: the presses and releases are timed by one xdotool process (separate ones
# start late on a busy machine, and a tap then reads as a hold). A key event that a busy machine
# delivers a quarter second late still turns a tap into a hold (about one run in ten on 2 cores
# under load): the taps are tried once more before they count as failed.
xdotool mousemove --window "$window" 790 490 click 1 # the scene has the keyboard, not a text box
sleep 0.5
taps=4
tap_keys=()
for _ in $(seq $taps); do tap_keys+=(keydown Left sleep 0.08 keyup Left sleep 0.15); done
taps_turn() { # yaw0 and yaw1 around the taps; whether each turned 3 degrees
  shoot
  xdotool "${tap_keys[@]}"
  sleep 0.3
  shoot
  yaw0=$(camera_of $((shots - 2)) | cut -d, -f1)
  yaw1=$(camera_of $((shots - 1)) | cut -d, -f1)
  awk -v a="$yaw0" -v b="$yaw1" -v n=$taps 'BEGIN { d = (a - b) / n; exit !(d >= 2.9 && d <= 3.1) }'
}
if ! taps_turn; then
  echo "$taps arrow taps of 80 ms turned from $yaw0 to $yaw1: once more"
  taps_turn || fail "$taps arrow taps of 80 ms turned from $yaw0 to $yaw1, not 3 degrees each"
fi
xdotool keydown Right sleep 1 keyup Right
sleep 0.3
shoot
yaw2=$(camera_of $((shots - 1)) | cut -d, -f1)
awk -v a="$yaw1" -v b="$yaw2" 'BEGIN { d = b - a; exit !(d >= 60 && d <= 90) }' || fail "a 1 s arrow hold turned from $yaw1 to $yaw2, not 3 + 0.75 * 90 degrees"
echo "$taps arrow taps of 80 ms: yaw $yaw0 -> $yaw1; held 1 s: -> $yaw2"
# A double click makes a slider a text box (as Ctrl+click does) without moving it first: Escape
# leaves the yaw as it was. Then the yaw back to 30 degrees typed in: the checks below expect the
# first camera.
reach yaw
read -r x0 y0 x1 y1 _ <<<"$(widget yaw)"
xdotool mousemove --window "$window" $((x0 + 5)) $(((y0 + y1) / 2)) click --repeat 2 --delay 80 1
sleep 0.3
xdotool key Escape
xdotool mousemove --window "$window" 790 490
shoot
[ "$(camera_of $((shots - 1)))" = "$(camera_of $((shots - 2)))" ] || fail "a double click on the yaw slider moved it: $(camera_of $((shots - 2))) -> $(camera_of $((shots - 1)))"
xdotool mousemove --window "$window" $((x0 + 5)) $(((y0 + y1) / 2)) click --repeat 2 --delay 80 1
xdotool key ctrl+a
xdotool type --delay 20 30
xdotool key Return
xdotool mousemove --window "$window" 790 490
shoot
[ "$(camera_of $((shots - 1)) | cut -d, -f1)" = 30.000 ] || fail "the yaw was not set back to 30: $(camera_of $((shots - 1)))"


# --- a message right under the button that caused it: a missing model.
type_into model_path "$work/missing.obj"
until_ok grep -q "^message model error: .*missing.obj" "$work/log" || fail "no error for a missing model"
read -r _ _ _ load_bottom _ <<<"$(widget model_load)"
read -r _ msg_top _ _ msg_visible <<<"$(widget '##model_message')"
[ "$msg_visible" = 1 ] && [ "$msg_top" -ge "$load_bottom" ] && [ "$msg_top" -le $((load_bottom + 12)) ] ||
  fail "the model's message is not right under Load (Load ends at $load_bottom, message at $msg_top)"
message '##model_message' | grep -q "missing.obj" || fail "the message slot does not show the error"
echo "message under Load: $(message '##model_message')"

# --- settings are validated: 0 and 100000 are refused with the reason, Generate is disabled.
type_into resolution 0
until_ok grep -q "^text validation Resolution: res must be from 1 to 65536 voxels along the longest side (got 0)$" "$work/shots/widgets.txt" || fail "resolution 0 was not refused"
type_into resolution 100000
until_ok grep -q "^text validation Resolution: res must be from 1 to 65536 voxels along the longest side (got 100000)$" "$work/shots/widgets.txt" || fail "resolution 100000 was not refused"
click generate
sleep 0.3
! grep -q "^message generation info: generating" "$work/log" || fail "Generate ran with resolution 100000"
echo "resolution 0 and 100000 refused: $(message validation)"
# --- Generate works at 800x500 (res 32), and its message is under the button.
type_into resolution 32
settings_valid() { grep -q "^text validation" "$work/shots/widgets.txt" && return 1 || return 0; }
until_ok settings_valid || fail "resolution 32 was refused"
click generate
until_ok grep -q "^message generation info: done: 32x" "$work/log" || fail "Generate did not finish"
until_ok grep -q "^generate " "$work/shots/widgets.txt" || fail "no Generate button after the bake"
read -r _ _ _ gen_bottom _ <<<"$(widget generate)"
read -r _ msg_top _ _ _ <<<"$(widget '##generation_message')"
[ "$msg_top" -ge "$gen_bottom" ] && [ "$msg_top" -le $((gen_bottom + 12)) ] || fail "the bake's message is not under Generate"
until_ok grep -q "^text stats method exact baked" "$work/shots/widgets.txt" || fail "the panel does not show the bake's method"
echo "Generate at 800x500: $(grep '^message generation info: done' "$work/log")"
# --- a band bake (Band 2) shows as a band field, said in the panel; a band field file loads as one.
type_into band 2
click generate
until_ok grep -q "^text band band field 32x[0-9]*x[0-9]* (band 2 voxels): shown at full resolution$" "$work/shots/widgets.txt" ||
  fail "the band bake is not shown as a band field: $(grep '^text band' "$work/shots/widgets.txt")"
echo "band bake: $(grep '^text band' "$work/shots/widgets.txt")"
type_into band 0
type_into field_path "$work/band.npz"
until_ok grep -q "^text band band field 24x[0-9]*x[0-9]* (band 3 voxels): shown at full resolution$" "$work/shots/widgets.txt" ||
  fail "the band field file is not shown as one: $(grep '^text band' "$work/shots/widgets.txt")"
echo "band field file: $(grep '^text band' "$work/shots/widgets.txt")"
# --- loading a model while a (long) bake runs asks first; the answer here cancels it and loads.
type_into resolution 400
click generate
until_ok grep -q "^cancel " "$work/shots/widgets.txt" || fail "no Cancel button while baking"
type_into model_path bunny.obj
until_ok grep -q "^bake_cancel_and_load .* 1$" "$work/shots/widgets.txt" || fail "loading during a bake did not ask"
click bake_cancel_and_load
until_ok grep -q "^message generation info: generation cancelled" "$work/log" || fail "the bake was not cancelled"
until_ok grep -q "^message model info: loaded bunny.obj" "$work/log" || fail "the model was not loaded after cancelling the bake"
# The model is loaded without waiting for the bake to stop (the window stays live); Generate comes back once it has.
until_ok grep -q "^generate " "$work/shots/widgets.txt" || fail "the cancelled bake did not stop"
echo "loading during a bake asked first, then cancelled it and loaded"
type_into resolution 32

# --- loading a field made from another mesh warns, and the figures become the field's own.
type_into field_path "$work/tet.sdf"
until_ok grep -q "^message field warning: .*made from .*tet.obj, not from bunny.obj, and its grid does not cover the model" "$work/log" ||
  fail "no warning for a mismatched field (another mesh's, not covering the bunny)"
until_ok grep -q "^text stats method exact loaded" "$work/shots/widgets.txt" || fail "the panel kept the bake's figures"
echo "mismatched field: $(grep '^message field warning' "$work/log" | tail -1)"
type_into field_path "$work/bunny.sdf"
until_ok grep -q "^message field info: loaded .*bunny.sdf" "$work/log" || fail "the bunny's field did not load"
# --- the panel's surface export and comparison (as `sdfgen surface` and `compare`).
click surface_export
until_ok grep -q "^message field info: saved the surface at level 0.0* as .*bunny.surface.obj ([0-9]* triangles)" "$work/log" ||
  fail "Export did not write the surface"
grep -q "^f " "$work/bunny.surface.obj" || fail "the exported surface has no faces"
type_into compare_path "$work/bunny.sdf"
until_ok grep -q "^message field info: against bunny.sdf: max |difference| 0 " "$work/log" || fail "comparing the field with itself did not report no difference"
echo "surface export and compare: $(grep '^message field info: against' "$work/log")"
# --- sign errors: compared with a copy whose signs are flipped at 100 samples, the panel counts
# those (the core's compare) and the "Sign errors" view is shown with a cross at each.
flipped=$(/usr/bin/python3 - "$work/bunny.sdf" "$work/flipped.sdf" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
first = lines.index("values") + 1
count = 0
for i in range(first + 1000, first + 1100):
    count += float(lines[i]) != 0
    lines[i] = lines[i][1:] if lines[i].startswith("-") else "-" + lines[i]
open(sys.argv[2], "w").write("\n".join(lines))
print(count)
PY
)
type_into compare_path "$work/flipped.sdf"
until_ok grep -q "^message field info: against flipped.sdf: .*signs differ at $flipped of " "$work/log" || fail "the comparison did not count the $flipped flipped signs"
until_ok grep -q "^text sign_errors $flipped $flipped$" "$work/shots/widgets.txt" || fail "the panel does not show $flipped sign errors: $(grep '^text sign_errors' "$work/shots/widgets.txt")"
xdotool mousemove --window "$window" 790 490
shoot
grep "^screenshot $((shots - 1)):" "$work/log" | grep -q " Sign_errors=1 " || fail "the Sign errors view was not shown"
type_into compare_path "$work/bunny.sdf"
until_ok grep -q "^text sign_errors 0 0$" "$work/shots/widgets.txt" || fail "comparing with itself left sign errors: $(grep '^text sign_errors' "$work/shots/widgets.txt")"
echo "sign errors: $flipped flipped samples counted and shown"

# --- the probe: the pointer over the model reports the field's trilinear value at that point.
xdotool mousemove --window "$window" 547 262
until_ok grep -q "^probe .* pointer=547,262$" "$work/log" || fail "the probe reported nothing over the model"
read -r _ px py pz value meshdist _ <<<"$(grep '^probe .* pointer=547,262$' "$work/log" | tail -1)"
/usr/bin/python3 - "$work/bunny.sdf" "$px" "$py" "$pz" "${value#field=}" "${meshdist#mesh=}" <<'EOF' || fail "the probe's value does not match the field"
import sys
import numpy as np
path, px, py, pz, reported, mesh_distance = sys.argv[1], *map(float, sys.argv[2:])
lines = open(path).read().split("\n")
header = {l.split()[0]: l.split()[1:] for l in lines[:6] if l}
nx, ny, nz = map(int, header["dims"])
origin = np.array(list(map(float, header["origin"])))
h = float(header["voxel"][0])
values = np.array(lines[lines.index("values") + 1:][: nx * ny * nz], dtype=np.float64).reshape(nz, ny, nx)
u = np.clip((np.array([px, py, pz]) - origin) / h - 0.5, 0, [nx - 1, ny - 1, nz - 1])
i0 = np.minimum(np.floor(u).astype(int), [nx - 1, ny - 1, nz - 1]); i1 = np.minimum(i0 + 1, [nx - 1, ny - 1, nz - 1]); f = u - i0
expected = 0.0
for dz in (0, 1):
    for dy in (0, 1):
        for dx in (0, 1):
            w = (f[0] if dx else 1 - f[0]) * (f[1] if dy else 1 - f[1]) * (f[2] if dz else 1 - f[2])
            expected += w * values[(i1 if dz else i0)[2], (i1 if dy else i0)[1], (i1 if dx else i0)[0]]
print(f"probe at ({px:.4g} {py:.4g} {pz:.4g}): reported {reported:.6g}, field {expected:.6g}, voxel {h:.4g}, mesh distance {mesh_distance:.3g}")
# The probed point lies on the drawn surface (up to depth precision), so the mesh is that close.
if mesh_distance > 0.25 * h:
    sys.exit("the probed point on the model is %g from the mesh" % mesh_distance)
sys.exit(0 if abs(reported - expected) <= 1e-5 * h + 1e-7 else 1)
EOF

# --- the probe on the ray-marched surface reads the iso level (within 1e-3; the march stops short
# of it and its depth is drawn a voxel nearer, which read +0.087), at iso 0 and 0.5, on the dense
# field and on a band field (the band's own samples).
# probe_reads LEVEL: a reading at 547,262 since line $mark of the log, within 1e-3 of LEVEL.
probe_reads() {
  tail -n +"$mark" "$work/log" | grep '^probe .* pointer=547,262$' | tail -1 |
    awk -v level="$1" '{ v = substr($5, 7) + 0; d = v - level; if (d < 0) d = -d; found = 1; exit !(d <= 1e-3) } END { if (!found) exit 1 }'
}
# probe_marched LEVEL: the pointer off the scene, then over the model; waits for the reading.
probe_marched() {
  xdotool mousemove --window "$window" 790 490
  sleep 0.3
  mark=$(($(wc -l <"$work/log") + 1))
  xdotool mousemove --window "$window" 547 262
  until_ok probe_reads "$1" ||
    fail "the probe on the ray-marched surface at iso $1 read $(tail -n +"$mark" "$work/log" | grep '^probe .* pointer=547,262$' | tail -1)"
  echo "ray-marched surface at iso $1: $(tail -n +"$mark" "$work/log" | grep '^probe .* pointer=547,262$' | tail -1)"
}
set_iso() {
  reach Iso_level
  read -r x0 y0 x1 y1 _ <<<"$(widget Iso_level)"
  xdotool mousemove --window "$window" $(((x0 + x1) / 2)) $(((y0 + y1) / 2)) keydown ctrl click 1 keyup ctrl
  xdotool key ctrl+a
  xdotool type --delay 20 "$1"
  xdotool key Return
}
click Ray-marched
probe_marched 0
set_iso 0.5
probe_marched 0.5
logged_since_mark() { tail -n +"$mark" "$work/log" | grep -q "$1"; }
mark=$(($(wc -l <"$work/log") + 1))
type_into field_path "$work/band.npz"
until_ok logged_since_mark "^message field info: loaded .*band.npz" || fail "the band field did not load"
probe_marched 0.5
set_iso 0
probe_marched 0
mark=$(($(wc -l <"$work/log") + 1))
type_into field_path "$work/bunny.sdf"
until_ok logged_since_mark "^message field info: loaded .*bunny.sdf" || fail "the bunny's field did not load again"
click Ray-marched

# --- the view checkboxes: each flips exactly its view and changes the scene. The views are the
# registry's, as the screenshot line lists them (LABEL=0|1), in its order; Sign errors has no
# crosses to draw here (the last comparison found none; its drawing is checked above).
shoot
previous=$((shots - 1))
views_of() { grep "^screenshot $1:" "$work/log" | tr ' ' '\n' | grep -E '^[^=]+=[01]$' | grep -v '^cut='; }
registered=$(views_of "$previous" | cut -d= -f1 | tr '\n' ' ')
[ "$(echo $registered | wc -w)" -ge 8 ] || fail "the screenshot line lists too few views: $registered"
for name in $registered; do
  click "$name"
  xdotool mousemove --window "$window" 790 490 # off the model: no probe marker in the picture
  shoot
  flipped=$(diff <(views_of "$previous") <(views_of $((shots - 1))) | grep '^>' | cut -d' ' -f2 | cut -d= -f1 || true)
  [ "$flipped" = "$name" ] || fail "clicking $name flipped '${flipped}' instead"
  if [ "$name" != Sign_errors ] && cmp -s "$work/shots/scene-$previous.png" "$work/shots/scene-$((shots - 1)).png"; then
    fail "toggling $name did not change the scene"
  fi
  previous=$((shots - 1))
done
echo "each view checkbox flips its view and changes the scene: $registered"

# --- the Screenshot button writes the scene as a PNG beside the viewer.
click screenshot
until_ok grep -q "^message screenshot info: saved $work/sdfgen-1.png" "$work/log" || fail "the Screenshot button wrote nothing"
[ "$(head -c 8 "$work/sdfgen-1.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "the screenshot is not a PNG"
echo "Screenshot button: $work/sdfgen-1.png"

# --- left-drag orbits (the slice stays); Ctrl+left-drag moves the slice along its normal (the
# camera stays); Ctrl+Shift+left-drag tilts it, 0.15 degrees a pixel: at most 15 for this drag
# (the former 0.4 a pixel turned it up to 37).
click Slice
xdotool mousemove --window "$window" 790 490
shoot
# drag MODIFIERS: a left-drag of 72 x 60 pixels over the scene with those keys held ("" for none).
drag() {
  [ -z "$1" ] || xdotool keydown "$1"
  xdotool mousemove --window "$window" 500 300 mousedown 1
  for step in 1 2 3 4 5 6; do xdotool mousemove --window "$window" $((500 + 12 * step)) $((300 + 10 * step)); done
  xdotool mouseup 1
  [ -z "$1" ] || xdotool keyup "$1"
  xdotool mousemove --window "$window" 790 490
  shoot
}
field_of() { grep "^screenshot $1:" "$work/log" | grep -o "$2=[^ ]*"; }
drag ""
[ "$(field_of $((shots - 2)) slice)" = "$(field_of $((shots - 1)) slice)" ] || fail "a left-drag moved the slice"
[ "$(camera_of $((shots - 2)))" != "$(camera_of $((shots - 1)))" ] || fail "a left-drag did not orbit"
echo "left-drag orbits: camera $(camera_of $((shots - 2))) -> $(camera_of $((shots - 1)))"
drag ctrl
[ "$(field_of $((shots - 2)) slice)" != "$(field_of $((shots - 1)) slice)" ] || fail "Ctrl+left-drag did not move the slice"
[ "$(camera_of $((shots - 2)))" = "$(camera_of $((shots - 1)))" ] || fail "Ctrl+left-drag turned the camera"
echo "Ctrl+left-drag moves the slice: $(field_of $((shots - 2)) slice) -> $(field_of $((shots - 1)) slice)"
drag ctrl+shift
/usr/bin/python3 - "$(field_of $((shots - 2)) normal)" "$(field_of $((shots - 1)) normal)" <<'PY' || fail "Ctrl+Shift+left-drag did not tilt the slice by 1 to 15 degrees"
import math, sys
a, b = ([float(v) for v in arg.split("=")[1].split(",")] for arg in sys.argv[1:])
angle = math.degrees(math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b))))))
print(f"Ctrl+Shift+left-drag of 72 x 60 pixels tilts the slice {angle:.2f} degrees")
sys.exit(0 if 1 <= angle <= 15 else 1)
PY

# --- a scene of two models: adding one outside the field's box warns, and Generate bakes the
# union, whose saved field names both.
printf 'v 20 0 0\nv 21 0 0\nv 20 1 0\nv 20 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/far.obj"
set_text model_path "$work/far.obj"
click model_add
until_ok grep -q "^message model info: added far.obj: 3678 triangles in the scene" "$work/log" || fail "Add to scene did not add the model"
# The Screenshot button's message is about an earlier action now: greyed (kept, nothing moves).
until_ok grep -qx "stale ##screenshot_message" "$work/shots/widgets.txt" || fail "the screenshot's message is not shown as stale after Add to scene"
! grep -qx "stale ##model_message" "$work/shots/widgets.txt" || fail "the newest message is shown as stale"
until_ok grep -q "^message field warning: the field shown does not fit the scene: .*not from bunny.obj+far.obj" "$work/log" ||
  fail "no warning that the field is not the scene's"
until_ok grep -q "^generate " "$work/shots/widgets.txt"
bakes=$(grep -c "^message generation info: done:" "$work/log")
more_bakes() { [ "$(grep -c "^message generation info: done:" "$work/log")" -gt "$bakes" ]; }
click generate
until_ok more_bakes || fail "the scene did not bake"
set_text field_path "$work/union.sdf"
click field_save
until_ok grep -q "^message field info: saved $work/union.sdf" "$work/log" || fail "the scene's field was not saved"
[ "$(sed -n 2p "$work/union.sdf")" = "source bunny.obj+far.obj" ] || fail "the scene's field does not name both models: $(sed -n 2p "$work/union.sdf")"
echo "scene of two models baked: $(sed -n 2,3p "$work/union.sdf" | tr '\n' ' ')"
grep -qx "$work/bunny.obj" "$work/config/sdfgen/recent.txt" || fail "the recent files do not list the bunny"

stop

# --- at 400 ms per frame: a tapped F reframes, a click toggles.
start SDFGEN_DEBUG_FRAME_DELAY_MS=400
xdotool mousemove --window "$window" 545 250
xdotool key f
shoot
framed=$(grep "^screenshot 0:" "$work/log" | sed 's/.*camera=//')
xdotool click 5 click 5 click 5 # zoom out over the scene
shoot
zoomed=$(grep "^screenshot 1:" "$work/log" | sed 's/.*camera=//')
[ "$zoomed" != "$framed" ] || fail "the wheel did not zoom"
xdotool key f
shoot
reframed=$(grep "^screenshot 2:" "$work/log" | sed 's/.*camera=//')
[ "$reframed" = "$framed" ] || fail "a tapped F did not reframe at 400 ms per frame ($framed, then $zoomed, then $reframed)"
echo "tapped F at 400 ms/frame: camera $zoomed -> $reframed"
grid_before=$(grep "^screenshot 2:" "$work/log" | grep -o 'Grid=[01]')
click Grid
shoot
grid_after=$(grep "^screenshot 3:" "$work/log" | grep -o 'Grid=[01]')
[ "$grid_before" != "$grid_after" ] || fail "a click at 400 ms per frame was lost"
echo "click at 400 ms/frame: $grid_before -> $grid_after"
stop

# --- the field saved beside a model loads in the background too: with each progress report of the
# read held back 6 s, the model shows at once, the saved field's progress shows under Model and the
# window stays live (an arrow turns the camera); then the field is shown, as part of the model's load.
SDFGEN_GUI_LOADING=1 start SDFGEN_DEBUG_READ_DELAY_MS=6000
until_ok grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "no progress while the saved field loads"
grep -q "^text ##model_message loaded bunny.obj: .*; reading the field saved beside it, bunny.sdf...$" "$work/shots/widgets.txt" ||
  fail "the Model section does not say the saved field is being read: $(message '##model_message')"
read -r _ py0 _ _ _ <<<"$(widget load_progress)"
read -r _ _ _ my1 _ <<<"$(widget '##model_message')"
[ "$py0" -ge "$my1" ] && [ "$py0" -lt "$(widget model_0 | cut -d' ' -f2)" ] || fail "the saved field's progress is not under the Model message"
xdotool mousemove --window "$window" 790 490
shoot
xdotool key Left
shoot
grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "the saved field loaded before the window was checked (too fast to test)"
yaw0=$(camera_of $((shots - 2)) | cut -d, -f1)
yaw1=$(camera_of $((shots - 1)) | cut -d, -f1)
awk -v a="$yaw0" -v b="$yaw1" 'BEGIN { d = a - b; exit !(d > 2.9 && d < 3.1) }' || fail "the view did not turn while the saved field loaded ($yaw0 -> $yaw1)"
until_ok grep -q "^message model info: loaded bunny.obj: .*; the field saved beside it, bunny.sdf, is shown" "$work/log" || fail "the saved field was not shown"
until_ok grep -q "^text stats method exact loaded" "$work/shots/widgets.txt" || fail "the saved field's figures are not shown"
! grep -q "^undo step: load bunny.sdf" "$work/log" || fail "the saved field made an undo step of its own"
echo "saved field loaded in the background: the view turned $yaw0 -> $yaw1 meanwhile"
# Escape first closes an open list, then cancels the load, leaving the scene as it was.
xdotool mousemove --window "$window" 790 490
shoot
scene_before=$(md5sum <"$work/shots/scene-$((shots - 1)).png")
stats_before=$(grep "^text stats " "$work/shots/widgets.txt")
cancels() { grep -c "^message field info: not loaded: $work/bunny.npz (cancelled)" "$work/log" || true; }
cancels0=$(cancels)
type_into field_path "$work/bunny.npz"
until_ok grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "no progress for the load to cancel with Escape"
click model_recent
until_ok grep -q "^recent_0 .* 1$" "$work/shots/widgets.txt" || fail "Recent did not open during the load"
xdotool key Escape
until_ok eval '! grep -q "^recent_0 " "$work/shots/widgets.txt"' || fail "Escape did not close Recent first"
grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "the Escape that closed Recent stopped the load (or it ended too soon to test)"
[ "$(cancels)" = "$cancels0" ] || fail "the Escape that closed Recent cancelled the load"
xdotool mousemove --window "$window" 790 490 key Escape
cancelled_at=$SECONDS
until_ok eval '[ "$(cancels)" -gt "$cancels0" ]' || fail "Escape did not cancel the load"
[ $((SECONDS - cancelled_at)) -le 3 ] || fail "Escape took $((SECONDS - cancelled_at)) s to stop the load"
[ "$(grep "^text stats " "$work/shots/widgets.txt")" = "$stats_before" ] || fail "Escape changed the field's figures"
shoot
[ "$(md5sum <"$work/shots/scene-$((shots - 1)).png")" = "$scene_before" ] || fail "Escape did not leave the scene as it was"
echo "Escape closed Recent, then cancelled the load in $((SECONDS - cancelled_at)) s; the scene as it was"
stop

# --- a field loads in the background (issue 40, item 4): a 25 MB field, each progress report of
# the read held back 400 ms (a slow disk), so that the load takes seconds however fast this disk is.
# While it loads the window is live (a screenshot is taken, an arrow turns the camera) and shows the
# load's progress; Cancel stops it soon and leaves the scene as it was; loaded again, it is shown.
"$sdfgen" bake "$work/bunny.obj" -o "$work/big.npz" --res 200 >/dev/null
start SDFGEN_DEBUG_READ_DELAY_MS=400
xdotool mousemove --window "$window" 790 490
shoot
scene_before=$(md5sum <"$work/shots/scene-$((shots - 1)).png")
stats_before=$(grep "^text stats " "$work/shots/widgets.txt")
type_into field_path "$work/big.npz"
until_ok grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "no progress shown while the field loads"
reach load_cancel
xdotool mousemove --window "$window" 790 490
xdotool key Left
shoot
grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "the load ended before the window was checked (too fast to test)"
yaw_loading=$(camera_of $((shots - 1)) | cut -d, -f1)
yaw_before=$(camera_of $((shots - 2)) | cut -d, -f1)
awk -v a="$yaw_before" -v b="$yaw_loading" 'BEGIN { d = a - b; exit !(d > 2.9 && d < 3.1) }' || fail "the view did not turn while loading ($yaw_before -> $yaw_loading)"
xdotool key Right
click load_cancel
cancelled_at=$SECONDS
until_ok grep -q "^message field info: not loaded: $work/big.npz (cancelled)" "$work/log" || fail "Cancel did not stop the load"
[ $((SECONDS - cancelled_at)) -le 3 ] || fail "Cancel took $((SECONDS - cancelled_at)) s to stop the load"
! grep -q "^message field .*: loaded $work/big.npz" "$work/log" || fail "the cancelled field was shown"
until_ok eval '! grep -q "^text load_progress " "$work/shots/widgets.txt"' || fail "the progress stayed after Cancel"
[ "$(grep "^text stats " "$work/shots/widgets.txt")" = "$stats_before" ] || fail "Cancel changed the field's figures: $(grep "^text stats " "$work/shots/widgets.txt")"
xdotool mousemove --window "$window" 790 490
shoot
[ "$(md5sum <"$work/shots/scene-$((shots - 1)).png")" = "$scene_before" ] || fail "Cancel did not leave the scene as it was"
echo "background load: live window (yaw $yaw_before -> $yaw_loading while loading), Cancel stopped it in $((SECONDS - cancelled_at)) s, the scene as it was"
# A load asked for while another runs takes its place: the first is stopped, never shown.
type_into field_path "$work/big.npz"
until_ok grep -q "^text load_progress " "$work/shots/widgets.txt" || fail "the second load of big.npz shows no progress"
type_into field_path "$work/bunny.sdf"
until_ok grep -q "^message field info: loaded $work/bunny.sdf" "$work/log" || fail "the load that replaced another did not complete"
grep -q "^message field info: stopped loading $work/big.npz to load $work/bunny.sdf" "$work/log" || fail "the replaced load was not said to be stopped"
! grep -q "^message field .*: loaded $work/big.npz" "$work/log" || fail "the replaced load was shown"
echo "a load asked for during another replaced it"
type_into field_path "$work/big.npz"
until_ok grep -q "^message field info: loaded $work/big.npz" "$work/log" || fail "the field did not load once not cancelled"
until_ok grep -q "^text stats .* loaded" "$work/shots/widgets.txt" || fail "the loaded field's figures are not shown"
grep -q "^undo step: load big.npz" "$work/log" || fail "the load made no undo step"
echo "background load completed: $(grep "^message field info: loaded $work/big.npz" "$work/log")"
stop

if [ -n "${SDFGEN_GUI_SHOT:-}" ]; then cp "$work/shots/window-3.png" "$SDFGEN_GUI_SHOT"; fi

# --- a field opened without a model is framed (the camera aims at its box's centre), and F, with
# Shift too, frames it again after a zoom.
SDFGEN_GUI_OPEN=bunny.npz start
[ "$(xdotool getwindowname "$window")" = "bunny.npz - sdfgen" ] || fail "the window's title is '$(xdotool getwindowname "$window")'"
xdotool mousemove --window "$window" 790 490
shoot
target=$(grep "^screenshot 0:" "$work/log" | sed 's/.*target=//')
/usr/bin/python3 - "$work/bunny.npz" "$target" <<'EOF' || fail "the field alone is not framed (camera target $target)"
import sys
import numpy as np
archive = np.load(sys.argv[1])
centre = np.asarray(archive["origin"], float) + 0.5 * np.asarray(archive["dims"], float) * float(archive["voxel_size"])
target = np.array([float(v) for v in sys.argv[2].split(",")])
print(f"field alone: camera target {target}, box centre {centre}")
sys.exit(0 if np.all(np.abs(target - centre) <= 1e-3 * np.abs(centre).max() + 1e-4) else 1)
EOF
xdotool key f
shoot
framed=$(camera_of 1)
xdotool click 5 click 5
shoot
xdotool key shift+f
shoot
[ "$(camera_of 3)" = "$framed" ] && [ "$(camera_of 2)" != "$framed" ] || fail "Shift+F did not frame the field ($framed, $(camera_of 2), $(camera_of 3))"
echo "field alone framed; Shift+F frames it again: $framed"
# --- a resized window keeps the framing: the camera the resize from 1280x720 left is the one F
# gives at 800x500; narrowed to 560x500 the field is framed as F frames it there; a zoomed view
# resized and back is as it was.
same_camera() { awk -v a="$1" -v b="$2" 'BEGIN { split(a, x, ","); split(b, y, ","); d = x[3] - y[3]; exit !(x[1] == y[1] && x[2] == y[2] && (d < 0 ? -d : d) <= 1e-3 * x[3]) }'; }
same_camera "$(camera_of 0)" "$framed" || fail "the resize did not keep the framing ($(camera_of 0), framed at the new size $framed)"
resize() {
  xdotool windowsize --sync "$window" "$1" "$2"
  until_ok grep -qs "^panel 0 0 [0-9]* $2 1$" "$work/shots/widgets.txt" || fail "the window did not become $1x$2"
  xdotool mousemove --window "$window" $(($1 - 10)) $(($2 - 10))
}
resize 560 500
shoot
xdotool key f
shoot
same_camera "$(camera_of 4)" "$(camera_of 5)" || fail "narrowing the window did not keep the field framed ($(camera_of 4), framed $(camera_of 5))"
xdotool click 4 click 4 click 4
shoot
resize 1000 500
resize 560 500
shoot
same_camera "$(camera_of 6)" "$(camera_of 7)" || fail "a zoomed view resized and back changed ($(camera_of 6), then $(camera_of 7))"
echo "resizing keeps the framing: at 800x500 $(camera_of 0), at 560x500 $(camera_of 4), zoomed $(camera_of 6) -> $(camera_of 7)"
stop

# --- work is never lost by one click (issue 40): the panel does not move under a still pointer
# (the probe's line is always reserved), Scale works about the model's centre, removal and every
# scene edit can be undone (Ctrl+Z) and redone (Ctrl+Shift+Z), Save and Export ask before
# replacing a file, the band's own memory estimate, keys in Recent and the file dialog, the cut
# following the slice, errors under the section the action was taken in, a hint for an empty view.
mkdir -p "$work/sub"
cp "$work/tet.obj" "$work/sub/tet.obj"
start
sections() { grep '^sections ' "$work/shots/widgets.txt" | cut -d' ' -f2; }
top=$(sections)
xdotool mousemove --window "$window" 547 262
until_ok grep -q "^probe .* pointer=547,262$" "$work/log" || fail "no probe reading over the model"
[ "$(sections)" = "$top" ] || fail "a probe reading moved the panel ($top -> $(sections))"
xdotool mousemove --window "$window" 790 490
# Keys in Recent: Escape closes it; Down and Enter open its first entry (the bunny).
click model_recent
until_ok grep -q "^recent_0 .* 1$" "$work/shots/widgets.txt" || fail "Recent did not open"
xdotool key Escape
until_ok eval '! grep -q "^recent_0 " "$work/shots/widgets.txt"' || fail "Escape did not close Recent"
loads=$(grep -c "^message model info: loaded bunny.obj" "$work/log")
click model_recent
until_ok grep -q "^recent_0 .* 1$" "$work/shots/widgets.txt" || fail "Recent did not open again"
xdotool key Down Return
until_ok eval '[ "$(grep -c "^message model info: loaded bunny.obj" "$work/log")" -gt "$loads" ]' || fail "Down and Enter in Recent opened nothing"
[ "$(sections)" = "$top" ] || fail "loading a model moved the panel ($top -> $(sections))"
echo "Recent: Escape closes it, Down and Enter open its first entry"
# Keys in the file dialog: Escape closes it; a click selects a folder without entering it; Enter
# enters it; Down and Enter open a file; a double click on ../ goes up.
click model_browse
until_ok is_visible browse_name || fail "the file dialog did not open"
xdotool key Escape
until_ok eval '! grep -q "^browse_name " "$work/shots/widgets.txt"' || fail "Escape did not close the file dialog"
click model_browse
until_ok is_visible browse_name || fail "the file dialog did not open again"
shoot
xdotool key Left Right Down Up
shoot
[ "$(camera_of $((shots - 2)))" = "$(camera_of $((shots - 1)))" ] || fail "arrows in the dialog turned the camera"
sub=3 # ../ config/ shots/ sub/
click "browse_entry_$sub"
until_ok grep -q "^browse_entry_${sub}_selected " "$work/shots/widgets.txt" || fail "a click did not select the folder sub/"
grep -qx "text browse_folder $work" "$work/shots/widgets.txt" || fail "one click entered a folder: $(grep browse_folder "$work/shots/widgets.txt")"
xdotool key Return
until_ok grep -qx "text browse_folder $work/sub" "$work/shots/widgets.txt" || fail "Enter did not enter the selected folder"
xdotool key Down Down Return
until_ok grep -q "^message model info: loaded tet.obj" "$work/log" || fail "Down, Down, Enter in the dialog did not open tet.obj"
click model_browse
until_ok grep -qx "text browse_folder $work/sub" "$work/shots/widgets.txt" || fail "the dialog did not open at the model's folder"
read -r x0 y0 x1 y1 _ <<<"$(widget browse_entry_0)"
xdotool mousemove --window "$window" $((x0 + 20)) $(((y0 + y1) / 2)) click --repeat 2 --delay 80 1
until_ok grep -qx "text browse_folder $work" "$work/shots/widgets.txt" || fail "a double click on ../ did not go up"
xdotool key Escape
until_ok eval '! grep -q "^browse_name " "$work/shots/widgets.txt"' || fail "Escape did not close the file dialog"
echo "file dialog: Escape closes, a click selects, Enter and a double click open, arrows move"
# A field path typed into the Model box: its error is said under Model, not under Field.
type_into model_path "$work/missing.npz"
until_ok grep -q "^message model error: .*missing.npz" "$work/log" || fail "the missing field typed into Model gave no error under Model"
! grep -q "^message field error: .*missing.npz" "$work/log" || fail "the error of the Model box was said under Field"
type_into model_path bunny.obj
until_ok eval '[ "$(grep -c "^message model info: loaded bunny.obj" "$work/log")" -gt "$((loads + 1))" ]' || fail "the bunny did not load again"
# Its saved field loads in the background after it (a progress line above the models), and is then
# uploaded and drawn: the click below waits until it is shown, and a second more (a click sent in
# the frames right after it was lost in about half the runs on a 2-core machine, the placement
# left closed).
field_settled() { ! grep "^message model " "$work/log" | tail -n 1 | grep -q "reading the field saved beside it"; }
until_ok field_settled || fail "the bunny's saved field did not finish loading: $(grep "^message model " "$work/log" | tail -n 1)"
sleep 1
[ "$(sections)" = "$top" ] || fail "the panel moved ($top -> $(sections))"

# Scale 2 typed in (Ctrl+click, Enter): about the model's centre, nothing moves under the pointer.
click model_0
until_ok is_visible model_scale_0 || fail "the model's placement did not open"
bounds() { grep '^text scene_bounds ' "$work/shots/widgets.txt" | cut -d' ' -f3-; }
bounds0=$(bounds)
remove0=$(widget model_remove_0)
read -r x0 y0 x1 y1 _ <<<"$(widget model_scale_0)"
xdotool mousemove --window "$window" $(((x0 + x1) / 2)) $(((y0 + y1) / 2)) keydown ctrl click 1 keyup ctrl
xdotool key ctrl+a
xdotool type --delay 20 2
xdotool key Return
until_ok grep -q "^undo step: scale" "$work/log" || fail "Scale 2 made no undo step"
bounds1=$(bounds)
[ "$(widget model_remove_0)" = "$remove0" ] || fail "Scale moved Remove from scene ($remove0 -> $(widget model_remove_0))"
[ "$(sections)" = "$top" ] || fail "Scale moved the panel"
/usr/bin/python3 - "$bounds0" "$bounds1" <<'PY' || fail "Scale 2 did not scale about the centre ($bounds0 -> $bounds1)"
import sys
a = [float(v) for v in sys.argv[1].split()]
b = [float(v) for v in sys.argv[2].split()]
for i in range(3):
    ca, cb = (a[i] + a[i + 3]) / 2, (b[i] + b[i + 3]) / 2
    ea, eb = a[i + 3] - a[i], b[i + 3] - b[i]
    if abs(ca - cb) > 1e-3 * ea or abs(eb - 2 * ea) > 1e-3 * ea:
        sys.exit(f"axis {i}: centre {ca} -> {cb}, extent {ea} -> {eb}")
print(f"scaled about the centre: {sys.argv[1]} -> {sys.argv[2]}")
PY
# Undo and redo the scale; Remove, then Ctrl+Z brings the model back (as scaled).
xdotool mousemove --window "$window" 790 490
xdotool key ctrl+z
until_ok grep -q "^message model info: undone: scale" "$work/log" || fail "Ctrl+Z did not undo the scale"
until_ok eval '[ "$(bounds)" = "$bounds0" ]' || fail "Ctrl+Z did not give the bounds back: $(bounds)"
xdotool key ctrl+shift+z
until_ok grep -q "^message model info: redone: scale" "$work/log" || fail "Ctrl+Shift+Z did not redo the scale"
until_ok eval '[ "$(bounds)" = "$bounds1" ]' || fail "Ctrl+Shift+Z did not scale again: $(bounds)"
click model_remove_0
until_ok grep -q "^message model info: removed bunny.obj from the scene" "$work/log" || fail "Remove did not remove the model"
until_ok eval '! grep -q "^model_0 " "$work/shots/widgets.txt"' || fail "the model is still listed"
xdotool mousemove --window "$window" 790 490
xdotool key ctrl+z
until_ok grep -q "^message model info: undone: remove bunny.obj" "$work/log" || fail "Ctrl+Z did not undo the removal"
until_ok eval '[ "$(bounds)" = "$bounds1" ]' || fail "the model came back elsewhere: $(bounds)"
xdotool key ctrl+z
until_ok eval '[ "$(bounds)" = "$bounds0" ]' || fail "a second Ctrl+Z did not undo the scale: $(bounds)"
echo "Scale 2 about the centre, Remove, both undone with Ctrl+Z: $(bounds)"
# Settings and a bake are undone too.
grid_line() { grep '^text grid ' "$work/shots/widgets.txt" | cut -d' ' -f3-; }
grid0=$(grid_line)
type_into resolution 32
until_ok grep -q "^text grid 32x" "$work/shots/widgets.txt" || fail "resolution 32 not taken"
click generate
until_ok grep -q "^text stats method exact baked" "$work/shots/widgets.txt" || fail "the bake did not finish"
[ "$(sections)" = "$top" ] || fail "the bake moved the panel ($top -> $(sections))"
xdotool mousemove --window "$window" 790 490
xdotool key ctrl+z
until_ok grep -q "^message model info: undone: bake" "$work/log" || fail "Ctrl+Z did not undo the bake"
until_ok grep -q "^text stats method exact loaded" "$work/shots/widgets.txt" || fail "undoing the bake did not bring the loaded field back"
xdotool key ctrl+z
until_ok eval '[ "$(grid_line)" = "$grid0" ]' || fail "Ctrl+Z did not undo the resolution ($(grid_line), was $grid0)"
echo "settings and bake undone: $(grid_line)"

# Save and Export ask before replacing a file; Cancel (or Escape) keeps it.
set_text field_path "$work/bunny.sdf"
before=$(stat -c %Y.%s "$work/bunny.sdf")
sleep 1
click field_save
until_ok is_visible overwrite_cancel || fail "Save did not ask before replacing bunny.sdf"
click overwrite_cancel
until_ok grep -q "^message field info: not saved: $work/bunny.sdf is kept" "$work/log" || fail "Cancel did not keep the file"
[ "$(stat -c %Y.%s "$work/bunny.sdf")" = "$before" ] || fail "Cancel changed the file"
click field_save
until_ok is_visible overwrite_replace || fail "Save did not ask again"
click overwrite_replace
until_ok grep -q "^message field info: saved $work/bunny.sdf" "$work/log" || fail "Replace did not save"
rm -f "$work/bunny.surface.obj"
click surface_export
until_ok grep -q "^message field info: saved the surface .*bunny.surface.obj" "$work/log" || fail "Export of a new file asked or failed"
click surface_export
until_ok is_visible overwrite_cancel || fail "Export did not ask before replacing the surface"
xdotool key Escape
until_ok grep -q "^message field info: not saved: .*bunny.surface.obj is kept" "$work/log" || fail "Escape did not keep the surface"
echo "Save and Export ask before replacing a file"

# The band's own estimate: res 4096 with band 3 is offered (the CLI bakes it in under 1 GB).
type_into resolution 4096
type_into band 3
until_ok grep -q "^text grid 4096x[0-9]*x[0-9]* band 3 bytes " "$work/shots/widgets.txt" || fail "res 4096 band 3 was refused: $(message validation)"
# The estimate is estimateBandBakeBytes' (the one `bake` checks), far below the dense grid's.
read -r dims _ _ _ band_bytes <<<"$(grep '^text grid ' "$work/shots/widgets.txt" | cut -d' ' -f3-)"
dense_bytes=$(echo "$dims" | awk -Fx '{ printf "%.0f", 4 * $1 * $2 * $3 }')
awk -v b="$band_bytes" -v d="$dense_bytes" 'BEGIN { exit !(b > 0 && b < d / 8) }' || fail "the band's estimate is $band_bytes bytes (dense $dense_bytes)"
! grep -q "^text validation" "$work/shots/widgets.txt" || fail "Generate is not offered for res 4096 band 3: $(message validation)"
echo "res 4096, band 3: $(grep '^text grid ' "$work/shots/widgets.txt")"
type_into band 0
type_into resolution 64

# The cut away follows the slice: hidden, nothing is cut; shown again, the choice is back.
click slice_cut
until_ok is_visible slice_cut_1 || fail "the Cut away list did not open"
click slice_cut_1
xdotool mousemove --window "$window" 790 490
shoot
grep "^screenshot $((shots - 1)):" "$work/log" | grep -q "Slice=1 .*cut=1 " || fail "the cut was not set: $(grep "^screenshot $((shots - 1)):" "$work/log")"
click Slice
xdotool mousemove --window "$window" 790 490
shoot
grep "^screenshot $((shots - 1)):" "$work/log" | grep -q "Slice=0 .*cut=0 " || fail "the cut stayed with the slice hidden: $(grep "^screenshot $((shots - 1)):" "$work/log")"
# With Coloured Model off too, nothing shows the model: the view says why.
click Coloured_Model
until_ok grep -q "^text scene_hint Coloured Model and Polygon are off" "$work/shots/widgets.txt" || fail "no hint in an empty view"
click Coloured_Model
until_ok eval '! grep -q "^text scene_hint" "$work/shots/widgets.txt"' || fail "the hint stayed"
click Slice
xdotool mousemove --window "$window" 790 490
shoot
grep "^screenshot $((shots - 1)):" "$work/log" | grep -q "Slice=1 .*cut=1 " || fail "the cut did not come back with the slice"
echo "the cut follows the slice; an empty view says why"
# The slice's gizmo: its arrow dragged (no modifier) moves the plane and its ring tilts it, the
# camera staying put; a left-drag off the gizmo still orbits; the pose shows and can be typed.
xdotool mousemove --window "$window" 790 490
until_ok grep -q "^text gizmo_arrow " "$work/shots/widgets.txt" || fail "no gizmo on the slice"
shoot
# drag_from X Y DX DY: a left-drag in steps, then a screenshot.
drag_from() {
  xdotool mousemove --window "$window" "$1" "$2" sleep 0.2 mousedown 1
  for step in 1 2 3 4; do xdotool mousemove --window "$window" $(($1 + $3 * step / 4)) $(($2 + $4 * step / 4)) sleep 0.05; done
  xdotool mouseup 1 mousemove --window "$window" 790 490
  shoot
}
pose_of() { grep "^screenshot $1:" "$work/log" | sed 's/.* slice=\([^ ]*\) normal=\([^ ]*\) .*/\1 \2/'; }
read -r ax ay tx ty <<<"$(grep '^text gizmo_arrow ' "$work/shots/widgets.txt" | cut -d' ' -f3-)"
drag_from "$ax" "$ay" $(((tx - ax) / 2)) $(((ty - ay) / 2))
[ "$(camera_of $((shots - 1)))" = "$(camera_of $((shots - 2)))" ] || fail "dragging the gizmo's arrow turned the camera"
read -r pos0 normal0 <<<"$(pose_of $((shots - 2)))"
read -r pos1 normal1 <<<"$(pose_of $((shots - 1)))"
awk -v a="$pos0" -v b="$pos1" 'BEGIN { exit !(b > a + 0.02) }' || fail "dragging the arrow towards its tip did not move the slice ($pos0 -> $pos1)"
[ "$normal1" = "$normal0" ] || fail "dragging the arrow tilted the slice"
# The drag is one undo step (not one per frame): Ctrl+Z puts the slice back, Ctrl+Shift+Z moves it again.
until_ok grep -q "^undo step: move the slice" "$work/log" || fail "the slice's drag made no undo step"
[ "$(grep -c "^undo step: move the slice" "$work/log")" = 1 ] || fail "the drag made $(grep -c "^undo step: move the slice" "$work/log") undo steps"
xdotool key ctrl+z
until_ok grep -q "^message model info: undone: move the slice" "$work/log" || fail "Ctrl+Z did not undo the slice's move"
shoot
[ "$(pose_of $((shots - 1)))" = "$pos0 $normal0" ] || fail "Ctrl+Z left the slice at $(pose_of $((shots - 1))), not $pos0 $normal0"
xdotool key ctrl+shift+z
until_ok grep -q "^message model info: redone: move the slice" "$work/log" || fail "Ctrl+Shift+Z did not redo the slice's move"
shoot
[ "$(pose_of $((shots - 1)))" = "$pos1 $normal1" ] || fail "Ctrl+Shift+Z left the slice at $(pose_of $((shots - 1))), not $pos1 $normal1"
echo "the slice's drag is one undo step: undone to $pos0, redone to $pos1"
read -r rx ry <<<"$(grep '^text gizmo_ring ' "$work/shots/widgets.txt" | cut -d' ' -f3-)"
drag_from "$rx" "$ry" 0 60
[ "$(camera_of $((shots - 1)))" = "$(camera_of $((shots - 2)))" ] || fail "dragging the gizmo's ring turned the camera"
read -r _ normal2 <<<"$(pose_of $((shots - 1)))"
[ "$normal2" != "$normal1" ] || fail "dragging the ring did not tilt the slice"
drag_from 700 60 -40 0
[ "$(camera_of $((shots - 1)))" != "$(camera_of $((shots - 2)))" ] || fail "a left-drag off the gizmo did not orbit"
[ "$(pose_of $((shots - 1)))" = "$(pose_of $((shots - 2)))" ] || fail "a left-drag off the gizmo moved the slice"
echo "slice gizmo: arrow moved the slice $pos0 -> $pos1, ring tilted it to $normal2, a drag off it orbits"
type_into slice_normal "1 0 0"
xdotool mousemove --window "$window" 790 490
shoot
grep "^screenshot $((shots - 1)):" "$work/log" | grep -q " normal=1.00000,0.00000,0.00000 " || fail "the typed normal was not taken: $(pose_of $((shots - 1)))"
read -r bx0 _ _ bx1 _ <<<"$(grep '^text scene_bounds ' "$work/shots/widgets.txt" | cut -d' ' -f3-)"
x=$(awk -v a="$bx0" -v b="$bx1" 'BEGIN { printf "%.5g", a + 0.3 * (b - a) }')
pose_before_point=$(pose_of $((shots - 1)))
type_into slice_point "$x 0 0"
until_ok eval 'grep "^text slice_pose " "$work/shots/widgets.txt" | awk -v x="$x" -v a="$bx0" -v b="$bx1" "{ d = \$3 - x; exit !(d * d < 1e-6 * (b - a) * (b - a)) }"' ||
  fail "the typed point was not taken: $(grep '^text slice_pose ' "$work/shots/widgets.txt") (typed x $x)"
type_into slice_normal "0 0 0"
until_ok grep -q "^message slice error: the slice normal '0 0 0' is not three numbers, not all 0" "$work/log" || fail "a zero normal was not refused"
# A typed pose is one undo step too.
xdotool mousemove --window "$window" 790 490
undone=$(grep -c "^message model info: undone: move the slice" "$work/log" || true)
xdotool key ctrl+z
until_ok eval '[ "$(grep -c "^message model info: undone: move the slice" "$work/log")" -gt "$undone" ]' || fail "Ctrl+Z did not undo the typed point"
shoot
[ "$(pose_of $((shots - 1)))" = "$pose_before_point" ] || fail "Ctrl+Z left the slice at $(pose_of $((shots - 1))), not $pose_before_point"
echo "slice pose typed: $(grep '^text slice_pose ' "$work/shots/widgets.txt")"
click slice_z
# The slice's colour range over a histogram of the values: dragging its outside end (the right
# line) towards 0 makes the range fixed at a smaller positive limit.
reach slice_range_histogram
read -r _ _ xin xout hy low0 high0 <<<"$(grep '^text slice_range_ends ' "$work/shots/widgets.txt")"
xdotool mousemove --window "$window" "$xout" "$hy" sleep 0.2 mousedown 1
for step in 1 2 3 4; do xdotool mousemove --window "$window" $((xout - (xout - xin) * step / 16)) "$hy" sleep 0.05; done
xdotool mouseup 1
xdotool mousemove --window "$window" 790 490
until_ok eval '[ "$(grep "^text slice_range_ends " "$work/shots/widgets.txt" | cut -d" " -f7)" != "$high0" ]' || fail "dragging the histogram's right line did not change the range"
read -r _ _ _ _ _ low1 high1 <<<"$(grep '^text slice_range_ends ' "$work/shots/widgets.txt")"
awk -v a="$high0" -v b="$high1" -v l0="$low0" -v l1="$low1" 'BEGIN { exit !(b > 0 && b < a && l0 == l1) }' ||
  fail "the range's outside end went from $high0 to $high1 (inside $low0 -> $low1)"
echo "histogram range editor: outside end dragged $high0 -> $high1"
# Adding a model is undone too.
set_text model_path "$work/tet.obj"
click model_add
until_ok grep -q "^undo step: add tet.obj" "$work/log" || fail "Add to scene made no undo step"
until_ok grep -q "^model_1 " "$work/shots/widgets.txt" || fail "the second model is not listed"
xdotool mousemove --window "$window" 790 490
xdotool key ctrl+z
until_ok grep -q "^message model info: undone: add tet.obj" "$work/log" || fail "Ctrl+Z did not undo Add to scene"
until_ok eval '! grep -q "^model_1 " "$work/shots/widgets.txt"' || fail "the added model is still listed"
echo "Add to scene undone"
stop
echo "GUI test passed"
