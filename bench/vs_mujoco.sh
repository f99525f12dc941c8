#!/bin/bash
# flapsim against MuJoCo on the same creatures, run in turns: per creature, PAIRS pairs of
# `flapsim_bench` and `mujoco_bench` (--runs 3 --seconds 1 --cpu-time --only NAME), the two in
# alternating order, each pair's ratio per simulated second (flapsim steps 1 ms; MuJoCo the
# step given), then the medians. Turns rather than one long run each: on a shared machine the
# speed drifts from minute to minute, and both sides of a pair see about the same machine.
# Before a creature is timed, its MuJoCo setting is checked for stability (mujoco_bench
# --check: warnings, non-finite or runaway speeds, the height reached, against RK4 at
# 1/16 ms); an unstable setting is reported and not timed. flapsim's setting, when it is not
# its default (--flapsim-step, --flapsim-turn-substep), is checked the same way
# (flapsim_bench --check: against flapsim at 1/16 ms). Prints figures; never passes or fails
# on time.
#   bash bench/vs_mujoco.sh [--pairs N] [--seconds S] [--bin DIR] [--mujoco PREFIX]
#        [--mujoco-include DIR] [--mujoco-lib DIR] [--integrator I] [--step S]
#        [--jacobian J] [--check-seconds T] [--flapsim-step S] [--flapsim-turn-substep S]
#        [NAME...]
#   NAME: flap_unit, chain_4, chain_6, chain_12, chain_25 (default: all)
#   --seconds S: simulated seconds per run (1; a flap unit's second is a few ms of CPU)
#   MuJoCo: by default Debian's (the catkin build's mujoco_bench). --mujoco PREFIX takes
#     PREFIX/include/mujoco/mujoco.h and PREFIX/lib/libmujoco.so (an install tree);
#     --mujoco-include and --mujoco-lib name the two folders apart (a build tree); without
#     these flags the environment variables FLAPSIM_MUJOCO_INCLUDE and FLAPSIM_MUJOCO_LIB name
#     them. Then bench/mujoco_bench.cpp is compiled against them (bench/mujoco_build.sh: g++
#     -O3, linked to the build's flapsim_core; it opens the MuJoCo library at run time) into
#     build/mujoco_bench/<key>/ and rebuilt when a source changes. The output names MuJoCo's
#     version and where it came from, never its folders, and the load average at the start and
#     the end.
#   --integrator Euler|RK4|implicit|implicitfast (implicit), --step S in s (0.001),
#   --jacobian dense|sparse|auto (auto), --check-seconds T (10; 0: no check).
#   --flapsim-step S, --flapsim-turn-substep S: flapsim's step and turn substep in s
#     (WorldParams' step_size 0.001 and turn_substep 0.0005); the ratio stays per simulated s.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
pairs=5
seconds=1
bin="$root/build/devel/lib/flapsim"
names=()
# shellcheck source=bench/mujoco_build.sh
. "$root/bench/mujoco_build.sh"
mujoco_options "$@"
set -- ${rest[@]+"${rest[@]}"}
setting=(--integrator implicit --step 0.001 --jacobian auto)
check=10
fsetting=()
while [ $# -gt 0 ]; do
  case "$1" in
    --pairs) pairs="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --bin) bin="$2"; shift 2 ;;
    --integrator) setting[1]="$2"; shift 2 ;;
    --step) setting[3]="$2"; shift 2 ;;
    --jacobian) setting[5]="$2"; shift 2 ;;
    --check-seconds) check="$2"; shift 2 ;;
    --flapsim-step) fsetting+=(--step "$2"); shift 2 ;;
    --flapsim-turn-substep) fsetting+=(--turn-substep "$2"); shift 2 ;;
    -h|--help) sed -n '2,31p' "$0"; exit 0 ;;
    -*) echo "vs_mujoco.sh: unknown option '$1'" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
[ ${#names[@]} -gt 0 ] || names=(flap_unit chain_4 chain_6 chain_12 chain_25)
[ -x "$bin/flapsim_bench" ] || { echo "vs_mujoco.sh: no $bin/flapsim_bench (build first)" >&2; exit 2; }

mujoco_program mujoco_bench
mujoco="$program"

# The steps per second of NAME in a benchmark's output (its third column), and the step (s)
# its header line names ("... steps of X ms").
rate() { awk -v n="$2" '$1 == n { print $3 }' <<< "$1"; }
step_of() { grep -o 'steps of [0-9.e+-]* ms' <<< "$1" | head -1 | awk '{ print $3 / 1000 }'; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
flags=(--runs 3 --seconds "$seconds" --cpu-time)
fflags=("${flags[@]}" "${fsetting[@]}")

load() { python3 -c 'import os, sys; print("load average at the %s: %.2f %.2f %.2f" % ((sys.argv[1],) + os.getloadavg()))' "$1"; }
load start
mujoco_line "$mujoco" "${setting[@]}"
echo "ratio: flapsim / MuJoCo per simulated second (steps/s x step), CPU time; order: which ran first"
printf '%-10s %6s %6s %12s %12s %10s %10s %8s\n' creature pair order 'flapsim st/s' 'mujoco st/s' \
  'flapsim s/s' 'mujoco s/s' ratio
for name in "${names[@]}"; do
  if [ "$check" != 0 ]; then
    probe="$("$mujoco" "${setting[@]}" --check "$check" --only "$name")"
    sed -n '2,$p' <<< "$probe"
    if ! grep -q 'verdict: stable' <<< "$probe"; then
      echo "$name: not counted: MuJoCo unstable at this setting"
      continue
    fi
    if [ ${#fsetting[@]} -gt 0 ]; then
      probe="$("$bin/flapsim_bench" "${fsetting[@]}" --check "$check" --only "$name")"
      sed -n '2,$p' <<< "$probe" | sed 's/^/  flapsim /'
      if ! grep -q 'verdict: stable' <<< "$probe"; then
        echo "$name: not counted: flapsim unstable at ${fsetting[*]}"
        continue
      fi
    fi
  fi
  ours=() theirs=() ratios=()
  for p in $(seq "$pairs"); do
    if [ $((p % 2)) = 1 ]; then
      order=fm
      a_out="$("$bin/flapsim_bench" "${fflags[@]}" --only "$name")"
      b_out="$("$mujoco" "${setting[@]}" "${flags[@]}" --only "$name")"
    else
      order=mf
      b_out="$("$mujoco" "${setting[@]}" "${flags[@]}" --only "$name")"
      a_out="$("$bin/flapsim_bench" "${fflags[@]}" --only "$name")"
    fi
    a=$(rate "$a_out" "$name") b=$(rate "$b_out" "$name")
    ha=$(step_of "$a_out") hb=$(step_of "$b_out")
    [ -n "$a" ] && [ -n "$b" ] && [ -n "$ha" ] && [ -n "$hb" ] ||
      { echo "vs_mujoco.sh: no figure for '$name'" >&2; exit 2; }
    sa=$(awk -v r="$a" -v h="$ha" 'BEGIN { printf "%.1f", r * h }')
    sb=$(awk -v r="$b" -v h="$hb" 'BEGIN { printf "%.2f", r * h }')
    r=$(awk -v a="$a" -v b="$b" -v ha="$ha" -v hb="$hb" 'BEGIN { printf "%.2f", a * ha / (b * hb) }')
    ours+=("$sa") theirs+=("$sb") ratios+=("$r")
    printf '%-10s %6d %6s %12s %12s %10s %10s %8s\n' "$name" "$p" "$order" "$a" "$b" "$sa" "$sb" "$r"
  done
  printf '%-10s %6s %6s %12s %12s %10s %10s %8s\n' "$name" median '' '' '' \
    "$(printf '%s\n' "${ours[@]}" | median)" "$(printf '%s\n' "${theirs[@]}" | median)" \
    "$(printf '%s\n' "${ratios[@]}" | median)"
done
load end
