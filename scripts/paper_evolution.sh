#!/bin/bash
# Regenerates doc/evolution/paper/ (doc/flight_and_evolution.md: Fig. 7 and 8): the paper
# preset (the paper's unit without ballast, its 2-2-2 network, no phase lock; 10 individuals,
# 200 generations, elitism, rank selection, crossover 0.1, mutation 0.05, fitness the
# accumulated height) on one 10 s flight per evaluation, seed 1. Results do not depend on
# --threads. usage: scripts/paper_evolution.sh [OUT_DIR]   (default doc/evolution/paper)
set -eu
cd "$(dirname "$0")/.."
out=${1:-doc/evolution/paper}
nice -n 5 build/devel/lib/flapsim/evolve --preset paper --seed 1 --duration 10 --episodes 1 \
  --threads 2 --out "$out"
