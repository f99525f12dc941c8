#!/bin/bash
# The flight tables of doc/flight_and_evolution.md: flight_check of one controller in the
# disturbance conditions (20 held-out starts within +-30 deg, 60 s), one markdown row per
# condition and step size.
# usage: scripts/flight_table.sh [--altitude M] WEIGHTS PAIRS [STEP_SIZES...]
#   (default steps: 0.001 0.0005; --altitude M: every row holds M m instead of climbing, and the
#   rows "hold 5 m" are left out)
set -u
hold=""
if [ "${1:-}" = "--altitude" ]; then
  hold=$2
  shift 2
fi
weights=$1
pairs=$2
shift 2
steps=${*:-0.001 0.0005}
fc=$(dirname "$0")/../build/devel/lib/flapsim/flight_check
conditions=("still air|" "wind 1 m/s|--wind 1" "wind 2 m/s|--wind 2"
  "roll torque 0.05 N m, 0.5 s|--gust-torque 0.05 --gust-time 0.5"
  "1 N up on one wing, 0.2 s|--gust-force 1 --gust-time 0.2"
  "attitude noise 0.1 rad|--noise 0.1")
if [ -z "$hold" ]; then
  conditions+=("hold 5 m|--altitude 5" "hold 5 m, wind 1 m/s|--altitude 5 --wind 1")
else
  for i in "${!conditions[@]}"; do
    conditions[i]="${conditions[i]%%|*}, hold $hold m|${conditions[i]#*|} --altitude $hold"
  done
fi
echo "| condition | step | passed | flips | lowest up | lowest up after 10 s | final height | mean abs bank | max drift | alt. rms after 10 s |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for c in "${conditions[@]}"; do
  name=${c%%|*}
  flags=${c#*|}
  for dt in $steps; do
    # shellcheck disable=SC2086
    "$fc" --weights "$weights" --pairs "$pairs" --roll 0.52 --pitch 0.52 --starts 20 \
      --duration 60 --step-size "$dt" --threads 2 $flags |
      awk -v name="$name" -v dt="$dt" '
        $1 ~ /^[0-9]+$/ && $2 != "of" {
          n++; if ($5 == "yes") flips++; if ($NF == "pass") passed++
          up = $6 + 0; if (n == 1 || up < minup) minup = up
          us = $11 + 0; if (n == 1 || us < minset) minset = us
          z = $7 + 0; if (n == 1 || z < zlo) zlo = z; if (n == 1 || z > zhi) zhi = z
          b = $13 + 0; bank += (b < 0 ? -b : b)
          d = $12 + 0; if (d > drift) drift = d
          if ($10 != "-") { r = $10 + 0; if (r > rms) rms = r; hold = 1 }
        }
        END {
          printf "| %s | %g ms | %d/%d | %d | %.3f | %.3f | %.1f to %.1f m | %.2f deg | %.1f m | %s |\n",
            name, dt * 1000, passed, n, flips, minup, minset, zlo, zhi, bank / n, drift,
            hold ? sprintf("max %.2f m", rms) : "-"
        }'
  done
done
