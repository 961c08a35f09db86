#!/usr/bin/env bash
# Usage: bench/channels.sh [--res 256] [--runs 7] [--out DIR] [--sdfgen PATH] [--bunny PATH] [MESH]
#
# What every channel costs a bake: the whole `sdfgen bake MESH -o F.npz` process (load, trees,
# distances, signs, save) with the distance alone and with --channels sdf,gradient,closest,triangle,
# the two alternating --runs times under /usr/bin/time. Prints each run, then the medians of wall
# and CPU (user + system) seconds and peak memory, and their ratios (channels / distance only).
# The output goes to --out (default /dev/shm when it exists, so that the disk's speed does not
# decide: with channels the file is 8 times larger), removed afterwards.
#
# Mesh: the one given, else the Stanford bunny (../shared/meshes/ next to the repository when
# present, or --bunny PATH; else assets/bunny.obj). The machine is usually shared: compare the
# ratios, and repeat.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sdfgen=$root/build/sdfgen
res=256
runs=7
out=
mesh=
bunny=
while [ $# -gt 0 ]; do
  case $1 in
    --res) res=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --sdfgen) sdfgen=$2; shift 2 ;;
    --bunny) bunny=$2; shift 2 ;;
    *) mesh=$1; shift ;;
  esac
done
if [ -z "$mesh" ]; then
  mesh=${bunny:-$root/../shared/meshes/stanford-bunny.obj}
  [ -f "$mesh" ] || mesh=$root/assets/bunny.obj
fi
if [ -z "$out" ]; then
  if [ -d /dev/shm ]; then out=/dev/shm; else out=${TMPDIR:-/tmp}; fi
fi
work=$(mktemp -d "$out/sdfgen-channels.XXXXXX")
trap 'rm -rf "$work"' EXIT

echo "$(basename "$mesh") at res $res, output in $out, $runs runs each, alternating"
echo "run      wall s  cpu s  peak MB"
for run in $(seq 1 "$runs"); do
  for kind in sdf all; do
    extra=()
    [ "$kind" = all ] && extra=(--channels sdf,gradient,closest,triangle)
    line=$(/usr/bin/time -f "%e %U %S %M" "$sdfgen" bake "$mesh" --res "$res" -o "$work/$kind.npz" "${extra[@]}" 2>&1 >/dev/null | tail -1)
    read -r wall user system kib <<<"$line"
    echo "$kind $wall $(echo "$user + $system" | bc) $((kib / 1024))" | tee -a "$work/runs"
  done
done | awk '{ printf "%-6s %7.2f %6.2f %8d\n", $1, $2, $3, $4 }'

median() { # median KIND COLUMN
  awk -v k="$1" -v c="$2" '$1 == k { print $c }' "$work/runs" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
for column in 2:wall 3:cpu 4:peak; do
  c=${column%%:*} name=${column#*:}
  a=$(median sdf "$c") b=$(median all "$c")
  printf 'median %-4s: distance only %s, every channel %s, ratio %.2f\n' "$name" "$a" "$b" "$(echo "$b / $a" | bc -l)"
done
