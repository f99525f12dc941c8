#!/bin/bash
# The turbulence a creature feels against the model (bench/turbulence_spectra.cpp): writes
# doc/turbulence_spectra.csv and doc/turbulence_spectra.png (log-log, the three components and
# the model's lines). Usage: bench/turbulence_spectra.sh [light|moderate|severe]
set -euo pipefail
cd "$(dirname "$0")/.."
level=${1:-light}
csv=doc/turbulence_spectra.csv
png=doc/turbulence_spectra.png
./bin/turbulence_spectra "$level" >"$csv"
gnuplot -e "set datafile separator ','; set terminal pngcairo size 900,560;
  set output '$png'; set logscale xy; set format y '10^{%L}';
  set title 'Dryden turbulence ($level, 5 m, 1 m/s wind) felt at rest: Welch, 1/6 octaves, vs the model seen through T_L';
  set xlabel 'frequency (Hz)'; set ylabel 'power spectral density ((m/s)^2/Hz)';
  set xrange [0.002:12]; set yrange [1e-6:1e3]; set key bottom left;
  plot '$csv' skip 1 using 1:2 with linespoints pt 7 ps 0.5 lc rgb '#1f77b4' title 'u (along the wind)',
       '' skip 1 using 1:3 with lines lw 2 dt 2 lc rgb '#0b3d66' title 'u model',
       '' skip 1 using 1:4 with linespoints pt 7 ps 0.5 lc rgb '#2ca02c' title 'v (across)',
       '' skip 1 using 1:5 with lines lw 2 dt 2 lc rgb '#145214' title 'v model',
       '' skip 1 using 1:6 with linespoints pt 7 ps 0.5 lc rgb '#d62728' title 'w (up)',
       '' skip 1 using 1:7 with lines lw 2 dt 2 lc rgb '#6b1010' title 'w model'"
echo "wrote $csv and $png"
