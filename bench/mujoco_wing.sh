#!/bin/bash
# The hover wing's plate in MuJoCo's ellipsoid fluid model and in flapsim's two air models
# (bench/mujoco_wing.cpp: force coefficients at 0-90 deg, the start in water), against the
# MuJoCo chosen as for bench/vs_mujoco.sh. Prints its table; never passes or fails.
#   bash bench/mujoco_wing.sh [--bin DIR] [--mujoco PREFIX] [--mujoco-include DIR]
#        [--mujoco-lib DIR]
#   MuJoCo: by default Debian's (the catkin build's mujoco_wing); --mujoco PREFIX, or
#     --mujoco-include and --mujoco-lib, or without these flags the environment variables
#     FLAPSIM_MUJOCO_INCLUDE and FLAPSIM_MUJOCO_LIB: another one, which bench/mujoco_wing.cpp is
#     compiled against into build/mujoco_bench/<key>/ (bench/mujoco_build.sh). The output names
#     MuJoCo's version and where it came from, never its folders.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/devel/lib/flapsim"
# shellcheck source=bench/mujoco_build.sh
. "$root/bench/mujoco_build.sh"
mujoco_options "$@"
set -- ${rest[@]+"${rest[@]}"}
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin="$2"; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "mujoco_wing.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
mujoco_program mujoco_wing
echo "MuJoCo from $mujoco_source"
"$program"
