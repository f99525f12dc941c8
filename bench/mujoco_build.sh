# Sourced (not run) by bench/vs_mujoco.sh and bench/mujoco_wing.sh: which MuJoCo a comparison
# runs against, and the program built against it.
#   mujoco_options "$@"   takes --mujoco PREFIX, --mujoco-include DIR and --mujoco-lib DIR out
#                         of the arguments (the rest into the array `rest`)
#   mujoco_program NAME   sets `program` to NAME (mujoco_bench or mujoco_wing) for that MuJoCo,
#                         compiling it if needed, and `mujoco_source` to where MuJoCo came from
#                         (without its path: stored outputs name no folder outside the checkout)
#   mujoco_line PROGRAM [SETTING...]
#                         prints "MuJoCo: <version, integrator, step, Jacobian> (from <source>)"
#                         from a run of 1 ms of sim time of mujoco_bench PROGRAM at SETTING
# MuJoCo: by default Debian's (libmujoco-dev, 2.2.2: the programs the catkin build made, in
# $bin). Another one (MuJoCo 3 built from source, say): --mujoco PREFIX takes
# PREFIX/include/mujoco/mujoco.h and PREFIX/lib/libmujoco.so (an install tree); --mujoco-include
# and --mujoco-lib name the two folders apart (a build tree); without these flags the
# environment variables FLAPSIM_MUJOCO_INCLUDE and FLAPSIM_MUJOCO_LIB name them the same way
# (so a command, and the doc tables that store it, need not name them). Then
# bench/NAME.cpp is compiled against them (g++ -O3, linked to the build's flapsim_core; it opens
# the MuJoCo library at run time: bench/mujoco_api.h) into build/mujoco_bench/<key>/ and rebuilt
# when a source changes. Needs `root` (the checkout) and `bin` (the build's programs) set.
mj_include="${FLAPSIM_MUJOCO_INCLUDE:-}"
mj_lib="${FLAPSIM_MUJOCO_LIB:-}"
mujoco_source=""
[ -n "$mj_include$mj_lib" ] && mujoco_source="FLAPSIM_MUJOCO_INCLUDE and FLAPSIM_MUJOCO_LIB"

mujoco_options() {
  rest=()
  while [ $# -gt 0 ]; do
    case "$1" in
      --mujoco) mj_include="$2/include"; mj_lib="$2/lib"; mujoco_source="--mujoco"; shift 2 ;;
      --mujoco-include) mj_include="$2"; mujoco_source="--mujoco-include, --mujoco-lib"; shift 2 ;;
      --mujoco-lib) mj_lib="$2"; mujoco_source="--mujoco-include, --mujoco-lib"; shift 2 ;;
      *) rest+=("$1"); shift ;;
    esac
  done
}

mujoco_program() {
  local name="$1" tool
  tool="$(basename "$0")"
  if [ -z "$mj_include$mj_lib" ]; then
    program="$bin/$name"
    mujoco_source="the build's, Debian's libmujoco-dev"
    [ -x "$program" ] || { echo "$tool: no $program (apt-get install libmujoco-dev, build)" >&2; exit 2; }
    return
  fi
  [ -n "$mj_include" ] && [ -n "$mj_lib" ] ||
    { echo "$tool: MuJoCo's include folder and library folder go together ($mujoco_source)" >&2; exit 2; }
  [ -f "$mj_include/mujoco/mujoco.h" ] || { echo "$tool: no mujoco/mujoco.h in '$mj_include' ($mujoco_source)" >&2; exit 2; }
  [ -e "$mj_lib/libmujoco.so" ] || { echo "$tool: no libmujoco.so in '$mj_lib' ($mujoco_source)" >&2; exit 2; }
  mj_include="$(cd "$mj_include" && pwd)" mj_lib="$(cd "$mj_lib" && pwd)"
  local core out stale=no f
  core="$(cd "$bin/.." && pwd)"
  [ -e "$core/libflapsim_core.so" ] || { echo "$tool: no $core/libflapsim_core.so (build first)" >&2; exit 2; }
  out="$root/build/mujoco_bench/$(echo "$mj_include $mj_lib" | md5sum | cut -c1-12)"
  program="$out/$name"
  local sources=("$root/bench/$name.cpp" "$root/bench/bench_common.h" "$root/bench/mujoco_api.h"
                 "$core/libflapsim_core.so"
                 "$(readlink -f "$mj_lib/libmujoco.so")" "$mj_include/mujoco/mujoco.h")
  [ -x "$program" ] || stale=yes
  for f in "${sources[@]}"; do [ "$f" -nt "$program" ] && stale=yes; done
  if [ "$stale" = yes ]; then
    mkdir -p "$out"
    echo "$tool: compiling $name against MuJoCo from $mujoco_source into build/mujoco_bench/" >&2
    g++ -std=c++17 -O3 -DNDEBUG -Wall -Wextra -o "$program" "$root/bench/$name.cpp" \
      -DFLAPSIM_MUJOCO_LIBRARY="\"$mj_lib/libmujoco.so\"" \
      -I "$root/include" -isystem /usr/include/eigen3 -isystem "$mj_include" \
      -L "$core" -lflapsim_core -Wl,-rpath,"$core" -ldl
  fi
}

mujoco_line() {
  local program="$1"
  shift
  echo "MuJoCo: $("$program" "$@" --runs 1 --seconds 0.001 --only flap_unit | head -1 | sed 's/^mujoco_bench: //; s/, [0-9]* runs of.*//') (from $mujoco_source)"
}
