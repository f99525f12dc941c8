#!/bin/bash
# Where a simulator's step stops passing the comparison's check: for one creature, the check
# of vs_mujoco.sh (10 s of flight against the simulator's own reference at 1/16 ms; the
# verdict of bench/bench_common.h) at each setting given, one line per setting, with the height
# error as a share of the reference's own change (the verdict allows 0.1 m when that change is
# under 1 m, more than 10% of the flap unit's 0.60 m; the share shows what the floor lets by).
#   bash bench/step_boundary.sh [--mujoco PREFIX | --mujoco-include DIR --mujoco-lib DIR]
#        [--bin DIR] [--check-seconds T] NAME mujoco INTEGRATOR STEP...
#   bash bench/step_boundary.sh [--bin DIR] [--check-seconds T] NAME flapsim STEP/PIECES...
#   NAME: flap_unit, chain_4, chain_6, chain_12, chain_25; STEP and PIECES in s (PIECES: the
#   turn substep; 0 is off). MuJoCo as bench/mujoco_build.sh finds it. Prints:
#   <side> <setting> <verdict> <height error %>. Never times anything.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/devel/lib/flapsim"
check=10
# shellcheck source=bench/mujoco_build.sh
. "$root/bench/mujoco_build.sh"
mujoco_options "$@"
set -- ${rest[@]+"${rest[@]}"}
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin="$2"; shift 2 ;;
    --check-seconds) check="$2"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    -*) echo "step_boundary.sh: unknown option '$1'" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -ge 3 ] || { sed -n '7,11p' "$0" >&2; exit 2; }
name="$1" side="$2"
shift 2
# The verdict and the height error as a share of the reference's change, from a check's lines.
verdict() {
  local v pct
  v="$(grep -o 'verdict: .*' <<< "$1" | sed 's/^verdict: //')"
  pct="$(awk '/^  setting / { for (i = 1; i <= NF; ++i) if ($i == "change") s = $(i + 1) }
              /^  reference / { for (i = 1; i <= NF; ++i) if ($i == "change") r = $(i + 1) }
              END { if (r != "" && s != "") printf "%.1f", 100 * (s - r) / (r < 0 ? -r : r) }' <<< "$1")"
  [ -n "$v" ] && [ -n "$pct" ] || { echo "step_boundary.sh: no verdict in the check's output" >&2; exit 2; }
  echo "$v | ${pct} %"
}
case "$side" in
  mujoco)
    mujoco_program mujoco_bench
    integrator="$1"
    shift
    mujoco_line "$program"
    for step in "$@"; do
      out="$("$program" --integrator "$integrator" --step "$step" --check "$check" --only "$name")"
      echo "mujoco $name $integrator $step | $(verdict "$out")"
    done ;;
  flapsim)
    [ -x "$bin/flapsim_bench" ] || { echo "step_boundary.sh: no $bin/flapsim_bench (build first)" >&2; exit 2; }
    for setting in "$@"; do
      step="${setting%/*}" pieces="${setting#*/}"
      [ "$setting" != "$step" ] || { echo "step_boundary.sh: '$setting' is not STEP/PIECES" >&2; exit 2; }
      out="$("$bin/flapsim_bench" --step "$step" --turn-substep "$pieces" --check "$check" --only "$name")"
      echo "flapsim $name $step/$pieces | $(verdict "$out")"
    done ;;
  *) echo "step_boundary.sh: the side is mujoco or flapsim, not '$side'" >&2; exit 2 ;;
esac
