#!/bin/bash
# flapsim against MuJoCo 2.2.2 on the same creatures, run in turns: per creature, PAIRS
# pairs of `flapsim_bench` and `mujoco_bench` (--runs 3 --seconds 1 --cpu-time --only NAME),
# each pair's ratio, then the medians of the steps per CPU second and of the ratios. Turns
# rather than one long run each: on a shared machine the speed drifts from minute to
# minute, and both sides of a pair see about the same machine. Prints figures; never passes
# or fails on time.
#   bash bench/vs_mujoco.sh [--pairs N] [--bin DIR] [NAME...]
#   NAME: flap_unit, chain_4, chain_6, chain_12, chain_25 (default: all)
set -euo pipefail
pairs=5
bin="$(cd "$(dirname "$0")/.." && pwd)/build/devel/lib/flapsim"
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    --pairs) pairs="$2"; shift 2 ;;
    --bin) bin="$2"; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    -*) echo "vs_mujoco.sh: unknown option '$1'" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
[ ${#names[@]} -gt 0 ] || names=(flap_unit chain_4 chain_6 chain_12 chain_25)
for tool in flapsim_bench mujoco_bench; do
  [ -x "$bin/$tool" ] || { echo "vs_mujoco.sh: no $bin/$tool (build first)" >&2; exit 2; }
done

# The steps per second of NAME in a benchmark's output (its third column).
rate() { awk -v n="$2" '$1 == n { print $3 }' <<< "$1"; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

printf '%-10s %6s %12s %12s %8s\n' creature pair flapsim mujoco ratio
for name in "${names[@]}"; do
  ours=() theirs=() ratios=()
  for p in $(seq "$pairs"); do
    a=$(rate "$("$bin/flapsim_bench" --runs 3 --seconds 1 --cpu-time --only "$name")" "$name")
    b=$(rate "$("$bin/mujoco_bench" --runs 3 --seconds 1 --cpu-time --only "$name")" "$name")
    [ -n "$a" ] && [ -n "$b" ] || { echo "vs_mujoco.sh: no figure for '$name'" >&2; exit 2; }
    r=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", a / b }')
    ours+=("$a") theirs+=("$b") ratios+=("$r")
    printf '%-10s %6d %12s %12s %8s\n' "$name" "$p" "$a" "$b" "$r"
  done
  printf '%-10s %6s %12s %12s %8s\n' "$name" median \
    "$(printf '%s\n' "${ours[@]}" | median)" "$(printf '%s\n' "${theirs[@]}" | median)" \
    "$(printf '%s\n' "${ratios[@]}" | median)"
done
