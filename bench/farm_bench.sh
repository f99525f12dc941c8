#!/bin/bash
# Episodes per second of one robust-preset generation (the preset's 32 individuals x 12
# episodes of 20 s) in process on 1 and 2 threads and through the episode farm with 1 and 2
# one-thread workers, on a master of its own; checks that all four wrote the same
# fitness.csv. Flags after `--` go to every evolve (another creature or preset, e.g. `-- --pairs
# 12 --init config/afc_1_extended_weights.yaml`, or `-- --preset hover`); each line then gives
# the generation's wall time too. Prints figures; never passes or fails on time.
#   bash bench/farm_bench.sh [build/devel/lib/flapsim] [-- EVOLVE_FLAGS...]
set -euo pipefail
bin="$(cd "$(dirname "$0")/.." && pwd)/build/devel/lib/flapsim"
if [ $# -gt 0 ] && [ "$1" != "--" ]; then bin="$1"; shift; fi
if [ $# -gt 0 ]; then
  [ "$1" = "--" ] || { echo "farm_bench.sh: '$1': the evolve flags go after --" >&2; exit 2; }
  shift
fi
out="$(mktemp -d)"
port=$((20000 + RANDOM % 20000))
export ROS_MASTER_URI="http://localhost:$port" ROS_HOME="$out/ros"
flags=(--generations 0 --seed 5 --no-plot "$@")
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$out"
}
trap cleanup EXIT

# The generation's episodes per second, and evolve's wall time (the generation's, and the robust
# preset's step choice, made once before it).
rate() {
  echo "$(grep -o '[0-9.]* episodes/s' "$1" | head -1), $(grep -o 'wall time [0-9.]* s' "$1" | head -1)"
}
load() { python3 -c 'import os, sys; print("load average at the %s: %.2f %.2f %.2f" % ((sys.argv[1],) + os.getloadavg()))' "$1"; }
load start

for t in 1 2; do
  "$bin/evolve" "${flags[@]}" --threads "$t" --out "$out/threads$t" > "$out/threads$t.log"
  echo "in process, $t thread(s): $(rate "$out/threads$t.log")"
done

rosmaster --core -p "$port" > "$out/master.log" 2>&1 &
pids+=($!)
worker() {
  "$bin/flapsim_worker" __ns:=/flapsim_farm __name:="$1" _threads:=1 > "$out/$1.log" 2>&1 &
  pids+=($!)
}
for n in 1 2; do
  worker "bench_$n"
  # Timed from the first look at the master: let the new worker register first.
  for _ in $(seq 100); do
    rosservice list 2>/dev/null | grep -q "bench_$n/evaluate_episodes" && break
    sleep 0.1
  done
  "$bin/evolve" "${flags[@]}" --farm --farm-wait 30 --out "$out/farm$n" > "$out/farm$n.log" 2>&1
  echo "farm, $n worker(s): $(rate "$out/farm$n.log") ($(grep -o '[0-9][0-9]* workers ' "$out/farm$n.log" | head -1)up)"
done

same=yes
for d in threads2 farm1 farm2; do
  cmp -s "$out/threads1/fitness.csv" "$out/$d/fitness.csv" || same=no
done
echo "fitness.csv the same in all four: $same"
load end
