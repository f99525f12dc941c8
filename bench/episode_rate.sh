#!/bin/bash
# Evolution's own speed: episodes per core-second of a robust-preset evolution (and of the
# hover preset's), in process on one thread. Each run is one generation of `evolve` (the first:
# every individual is flown, none is a copy), seeded from a shipped controller so that the
# episodes fly as an evolution's do, crashes of its mutants included:
#   afc_N: evolve --preset robust --pairs N --init config/afc_1_extended_weights.yaml
#   hover: evolve --preset hover --init config/hover_1_gains.yaml
# with --generations 0 --population P --episodes E --threads 1, and the flags after `--`
# (e.g. `-- --step-sizes 0.001,0.0005`, the steps the robust preset flew before it chose its
# own). The robust preset finds its step sizes and turn substep once per evolution
# (flapsim/step_accuracy.h): the script asks evolve for that choice first (a one-episode run
# whose weights file names it), prints it and the CPU it took, and times the episodes with
# the choice given, so that the figure is the episodes' alone; with --step-sizes among the
# flags after `--` there is no choice to find. The flags after `--` must not be --generations,
# --population, --episodes or --duration (the script sets them). Episodes per core-second
# = P x E / (user + system CPU seconds of the process), the median of the runs; for a
# comparison of two builds or settings, run the two in turns on the same machine. Prints
# figures; never passes or fails on time.
#   bash bench/episode_rate.sh [--bin DIR] [--population P] [--episodes E] [--runs R]
#        [NAME...] [-- EVOLVE_FLAGS...]
#   NAME: afc_1, afc_4, afc_12, hover (default: afc_1 afc_4 afc_12 hover)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/devel/lib/flapsim"
population=8
episodes=4
runs=3
names=()
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin="$2"; shift 2 ;;
    --population) population="$2"; shift 2 ;;
    --episodes) episodes="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | grep '^#'; exit 0 ;;
    -*) echo "episode_rate.sh: unknown option '$1'" >&2; exit 2 ;;
    afc_[0-9]*|hover) names+=("$1"); shift ;;
    *) echo "episode_rate.sh: unknown creature '$1' (afc_N or hover)" >&2; exit 2 ;;
  esac
done
[ ${#names[@]} -gt 0 ] || names=(afc_1 afc_4 afc_12 hover)
[ -x "$bin/evolve" ] || { echo "episode_rate.sh: no $bin/evolve (build first)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "episode_rate.sh: needs /usr/bin/time (apt-get install time)" >&2; exit 2; }
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

echo "commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)," \
     "load average $(cut -d' ' -f1-3 /proc/loadavg), $population x $episodes episodes a run," \
     "$runs runs${extra[*]:+, flags: ${extra[*]}}"
printf '%-8s %-24s %8s %10s %10s %18s\n' creature "steps, turn substep" "check s" episodes "CPU s" "episodes/core-s"
for name in "${names[@]}"; do
  if [ "$name" = hover ]; then
    cmd=("$bin/evolve" --preset hover --init "$root/config/hover_1_gains.yaml")
  else
    cmd=("$bin/evolve" --preset robust --pairs "${name#afc_}"
         --init "$root/config/afc_1_extended_weights.yaml")
  fi
  cmd+=(--generations 0 --threads 1 --no-plot --out "$out/run" "${extra[@]}")
  # The steps the evolution flies: as its weights file's command names them (the hover
  # preset flies its own, found by no check).
  chosen="" steps="preset" check="-"
  if [[ " ${extra[*]} " == *" --step-sizes "* ]]; then
    steps="given"
  elif [ "$name" != hover ]; then
    /usr/bin/time -f '%U %S' -o "$out/time" "${cmd[@]}" --population 2 --episodes 1 \
      --duration 0.1 >"$out/log" 2>&1 || {
      echo "episode_rate.sh: $name: evolve failed:" >&2
      tail -3 "$out/log" >&2
      exit 1
    }
    check="$(awk '{printf "%.3f", $1 + $2}' "$out/time")"
    chosen="$(grep -m1 '^  command: ' "$out/run/weights.yaml" |
              grep -o -E -- '--(step-sizes|turn-substep) [^ ]+' | tr '\n' ' ' || true)"
    steps="$(echo "$chosen" | awk '{for (i = 2; i <= NF; i += 2) printf "%s%s", (i > 2 ? ", " : ""), $i}')"
  fi
  cpus=()
  for ((r = 0; r < runs; r++)); do
    # shellcheck disable=SC2086
    if ! /usr/bin/time -f '%U %S' -o "$out/time" "${cmd[@]}" $chosen --population "$population" \
         --episodes "$episodes" >"$out/log" 2>&1; then
      echo "episode_rate.sh: $name: evolve failed:" >&2
      tail -3 "$out/log" >&2
      exit 1
    fi
    cpus+=("$(awk '{printf "%.3f", $1 + $2}' "$out/time")")
  done
  median="$(printf '%s\n' "${cpus[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')"
  n=$((population * episodes))
  printf '%-8s %-24s %8s %10d %10.3f %18.2f\n' "$name" "${steps:-default}" "$check" "$n" "$median" \
         "$(awk -v n="$n" -v c="$median" 'BEGIN {print n / c}')"
done
