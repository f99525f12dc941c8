#!/bin/bash
# Runs a shipped controller file's `# Reproduce:` command into a fresh directory and compares
# what it writes with the file, bit for bit: the weights (or the hover gains) and the best
# fitness. Exit 0 if they are the same, 1 if not, 2 if the file has no Reproduce line.
# Usage: scripts/reproduce_controller.sh config/afc_1_real_air_weights.yaml [--threads N]
# (the threads do not change the result; evolve's own default is used otherwise). Not run by
# the tests: an evolution takes minutes (afc_1_real_air: 31 min on 2 threads here, 6 December;
# 44 min beside another evolution).
set -euo pipefail
cd "$(dirname "$0")/.."
file=$1
shift || true
line=$(grep -m1 '^# Reproduce: evolve ' "$file" || true)
if [ -z "$line" ]; then
  echo "reproduce_controller: $file has no '# Reproduce: evolve ...' line" >&2
  exit 2
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
command=${line#\# Reproduce: evolve }
command=${command//<dir>/$out}
echo "evolve $command $*"
# shellcheck disable=SC2086
./bin/evolve $command --no-plot "$@" >"$out/log" 2>&1 || { tail -5 "$out/log"; exit 1; }
written="$out/weights.yaml"
[ -f "$written" ] || written="$out/gains.yaml"
key() { grep -E '^  (weights|best_fitness):|^[a-z_]+: ' "$1" | grep -v -E 'wall_time|threads|evaluated_on' || true; }
if diff <(key "$file") <(key "$written") >/dev/null; then
  echo "reproduced bit for bit: $file"
  exit 0
fi
echo "NOT reproduced: $file differs from the run's $written:"
diff <(key "$file") <(key "$written") | head -10
exit 1
