#!/usr/bin/python3
"""Why each held-out start misses real air's bar: flies bin/flight_check with the arguments
given (which must hold an altitude, --altitude M), then each start that misses the bar again
with --trace, and prints for it what its trace shows after the settle time (10 s): its highest
and lowest height against the setpoint, the air's vertical speed and the mean commanded
downstroke and upstroke rates over the second before each, and its lowest up-component.

  scripts/real_air_misses.py --weights config/afc_1_shed_floor_weights.yaml \\
      --velocity-noise 0.05 --altitude 5 --roll 0.52 --pitch 0.52 --starts 20 --duration 60 \\
      --threads 2 --real-air

The last line counts the misses: flipped; on the up-component or the bank alone (the altitude
rms under the bar's 0.3 m); else on the altitude, by its larger excursion: above the setpoint
(an updraft the creature did not sink through) or below it (a downdraft it did not climb
through). Figures, not a test."""
import csv
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_tables_flight import meets_real_air_bar, starts  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SETTLE = 10.0  # s: flight_check's


def flight_check(args):
    run = subprocess.run([os.path.join(ROOT, "bin", "flight_check")] + args, cwd=ROOT,
                         capture_output=True, text=True)
    if run.returncode not in (0, 1):
        sys.exit(f"real_air_misses: flight_check failed: {run.stderr.strip()}")
    return run.stdout


def setpoint(args):
    if "--altitude" not in args:
        sys.exit("real_air_misses: give --altitude M (the bar is about holding one)")
    return float(args[args.index("--altitude") + 1])


def mean_before(rows, i, key_part, window):
    """The mean over the `window` s up to row i of the columns ending in `key_part` (_down or
    _up: every wing's; air_vz)."""
    keys = [k for k in rows[0] if k.endswith(key_part)]
    t = float(rows[i]["time"])
    picked = [r for r in rows[: i + 1] if float(r["time"]) > t - window]
    return sum(float(r[k]) for r in picked for k in keys) / (len(picked) * len(keys))


def describe(rows, height, i, name):
    r = rows[i]
    return (f"{name} {float(r['height']) - height:+.2f} m at {float(r['time']):.1f} s (the 2 s "
            f"before: air {mean_before(rows, i, 'air_vz', 2.0):+.2f} m/s, commanded down "
            f"{mean_before(rows, i, '_down', 2.0):.0f} / up {mean_before(rows, i, '_up', 2.0):.0f}"
            " rad/s)")


def main(args):
    height = setpoint(args)
    missed = [r for r in starts(flight_check(args)) if not meets_real_air_bar(r)]
    kinds = {"flipped": 0, "attitude": 0, "above": 0, "below": 0}
    with tempfile.TemporaryDirectory() as tmp:
        for row in missed:
            n = int(row["start"])
            path = os.path.join(tmp, f"start{n}.csv")
            flight_check(args + ["--trace", str(n), path])
            with open(path) as f:
                rows = [r for r in csv.DictReader(f) if float(r["time"]) >= SETTLE]
            hi = max(range(len(rows)), key=lambda i: float(rows[i]["height"]))
            lo = min(range(len(rows)), key=lambda i: float(rows[i]["height"]))
            up = min(float(r["upright"]) for r in rows)
            above = float(rows[hi]["height"]) - height
            below = height - float(rows[lo]["height"])
            kind = ("flipped" if row["flipped"] != "no" else
                    "attitude" if row["alt_rms"] is not None and row["alt_rms"] < 0.3 else
                    "above" if above > below else "below")
            kinds[kind] += 1
            print(f"start {n}: rms {row['alt_rms']} m, lowest up {up:.3f}, bank {row['bank']} deg; "
                  f"{describe(rows, height, hi, 'highest')}; {describe(rows, height, lo, 'lowest')}")
    print(f"{len(missed)} starts miss the bar: {kinds['flipped']} flip, {kinds['attitude']} on "
          f"the up-component or the bank alone, {kinds['above']} on the altitude, furthest above "
          f"the setpoint, {kinds['below']} furthest below")


if __name__ == "__main__":
    main(sys.argv[1:])
