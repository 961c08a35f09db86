#!/usr/bin/env bash
# Usage: bench/peers.sh [MESH.obj ...] [--res 128] [--method rays]
#
# Bakes each mesh (default: ../shared/meshes/stanford-bunny.obj next to the repository if it is
# there, else assets/bunny.obj) with `sdfgen bake` (default settings) and with each peer driver that
# could be built (bench/CMakeLists.txt: peer_openvdb needs libopenvdb-dev libboost-iostreams-dev,
# peer_embree needs libembree-dev), all on the same grid, then prints for each tool the wall-clock
# seconds of the whole process and the ratio to sdfgen's, followed by `sdfgen compare` of sdfgen's
# field against each peer's (when this sdfgen has the compare command).
#
# --method rays compares the ray method (the original report's: distance = nearest hit of 64 rays,
# sign by their back-face vote) instead: `sdfgen bake --method rays` against `peer_embree --method
# rays`, the same method on Embree (OpenVDB has no ray method and is left out).
#
# Builds sdfgen and the peers in build-peers/ (Release; BUILD=DIR uses another build folder). The
# fields go to BUILD/peers-out/. JOBS=N limits the build's parallel jobs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build-peers}
out=$build/peers-out

usage() { sed -n '2,/^set -e/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; }
res=128
method=exact
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
    --res) [ $# -ge 2 ] || { echo "peers.sh: --res needs a value" >&2; exit 2; }; res=$2; shift 2 ;;
    --res=*) res=${1#--res=}; shift ;;
    --method) [ $# -ge 2 ] || { echo "peers.sh: --method needs a value" >&2; exit 2; }; method=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "peers.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
    *) meshes+=("$1"); shift ;;
  esac
done
[[ $res =~ ^[1-9][0-9]*$ ]] || { echo "peers.sh: --res must be a positive integer (got '$res')" >&2; exit 2; }
case $method in
  exact) candidates=(openvdb embree); method_args=() ;;
  rays) candidates=(embree); method_args=(--method rays) ;;
  *) echo "peers.sh: --method must be exact or rays (got '$method')" >&2; exit 2 ;;
esac
if [ ${#meshes[@]} -eq 0 ]; then
  if [ -f "$root/../shared/meshes/stanford-bunny.obj" ]; then
    meshes=("$(cd "$root/../shared/meshes" && pwd)/stanford-bunny.obj")
  else
    meshes=("$root/assets/bunny.obj")
  fi
fi
for mesh in "${meshes[@]}"; do
  [ -f "$mesh" ] || { echo "peers.sh: no such mesh: $mesh" >&2; exit 1; }
done

# Build: sdfgen and whichever peer targets the configure step defined. Configuring every time is
# quick and picks up a peer library installed since the last run.
generator=()
[ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null && generator=(-G Ninja)
mkdir -p "$build"
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >"$build/peers-configure.log" 2>&1 ||
  { cat "$build/peers-configure.log" >&2; echo "peers.sh: configuring $build failed" >&2; exit 1; }
targets=$(cmake --build "$build" --target help 2>/dev/null || true)
peers=()
for peer in "${candidates[@]}"; do
  if grep -qw "peer_$peer" <<<"$targets"; then
    peers+=("$peer")
  else
    echo "peers.sh: note: peer_$peer is not available (its library was not found when $build was configured)"
  fi
done
build_targets=(sdfgen)
for peer in "${peers[@]}"; do build_targets+=("peer_$peer"); done
jobs=()
[ -n "${JOBS:-}" ] && jobs=(-j "$JOBS")
cmake --build "$build" "${jobs[@]}" --target "${build_targets[@]}" >"$build/peers-build.log" 2>&1 ||
  { tail -n 40 "$build/peers-build.log" >&2; echo "peers.sh: building ${build_targets[*]} failed (log: $build/peers-build.log)" >&2; exit 1; }

sdfgen=$build/sdfgen
have_compare=0
"$sdfgen" compare --help >/dev/null 2>&1 && have_compare=1
mkdir -p "$out"

# run NAME LOG COMMAND...: runs a command, its output to LOG; sets $seconds (wall clock, whole process).
seconds=
run() {
  local log=$2
  shift 2
  local timing status=0
  timing=$( { TIMEFORMAT=%R; time "$@" >"$log" 2>&1; } 2>&1 ) || status=$?
  seconds=$timing
  return $status
}

status=0
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .obj)
  echo
  echo "== $mesh, --res $res, --method $method, $(nproc) cores"
  names=() times=() notes=()
  base=$out/$name-sdfgen.sdf
  if ! run sdfgen "$out/$name-sdfgen.log" "$sdfgen" bake "$mesh" --res "$res" "${method_args[@]}" -o "$base"; then
    echo "peers.sh: sdfgen bake failed on $mesh:" >&2
    tail -n 5 "$out/$name-sdfgen.log" >&2
    status=1
    continue
  fi
  names+=(sdfgen) times+=("$seconds") notes+=("$(grep -- ' -> ' "$out/$name-sdfgen.log" | tail -n 1 || tail -n 1 "$out/$name-sdfgen.log")")
  ran=()
  for peer in "${peers[@]}"; do
    if run "$peer" "$out/$name-$peer.log" "$build/bench/peer_$peer" "$mesh" --res "$res" "${method_args[@]}" -o "$out/$name-$peer.sdf"; then
      names+=("$peer") times+=("$seconds") notes+=("$(grep "^$peer:" "$out/$name-$peer.log" | tail -n 1)")
      ran+=("$peer")
    else
      names+=("$peer") times+=("-") notes+=("FAILED: $(tail -n 1 "$out/$name-$peer.log")")
      status=1
    fi
  done

  printf '%-8s %9s %9s  %s\n' tool seconds ratio "the tool's own line"
  for i in "${!names[@]}"; do
    ratio=-
    [ "${times[i]}" != - ] && ratio=$(awk -v a="${times[i]}" -v b="${times[0]}" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "-" }')
    printf '%-8s %9s %9s  %s\n' "${names[i]}" "${times[i]}" "$ratio" "${notes[i]}"
  done
  echo "(seconds: wall clock of the whole process; ratio: tool / sdfgen; fields in $out)"

  for peer in "${ran[@]}"; do
    if [ $have_compare = 1 ]; then
      echo "-- sdfgen compare $name-sdfgen.sdf $name-$peer.sdf"
      "$sdfgen" compare "$base" "$out/$name-$peer.sdf" || echo "(sdfgen compare exited with $?)"
    fi
  done
  [ $have_compare = 1 ] || echo "(this sdfgen has no compare command; no field comparison)"
done
exit $status
