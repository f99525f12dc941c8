#!/usr/bin/python3
"""Writes a flap-unit weights file given the attitude-first mixer, its trims and slopes kept.

With mixer_headroom h (FlapControllerParams::mixer_headroom) each sigmoid output maps onto its
rate range widened by h of its span at both ends: (1 + 2h) times the slope of the paper's map.
Scaling the output neurons' weights and biases by (1 + 2 h0) / (1 + 2h), h0 the file's headroom
(0 without the mixer), gives each output the file's trim and its slope at the trim again, so
`evolve --mixer-headroom H --init` can start near a controller evolved with another headroom or
none. Away from the trim the two differ, and where the widened rates leave the range the mixer
keeps the wings' difference first: the seed is not the file's controller.

usage: scripts/mixer_seed.py FILE --headroom H > SEED.yaml
"""
import argparse
import sys

import yaml


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="a weights file")
    ap.add_argument("--headroom", type=float, required=True, help="the mixer's headroom, (0, 1]")
    a = ap.parse_args()
    if not 0.0 < a.headroom <= 1.0:
        sys.exit(f"mixer_seed: --headroom must be in (0, 1], got {a.headroom}")
    with open(a.file) as f:
        doc = yaml.safe_load(f)
    c = doc["flap_unit_controller"]
    h0 = float(c.get("mixer_headroom", 0.0))
    if h0 == a.headroom:
        sys.exit(f"mixer_seed: {a.file} already has mixer_headroom {h0}")
    hidden, outputs, w = int(c["hidden"]), len(c["outputs"]), list(c["weights"])
    first = len(w) - outputs * (hidden + 1)  # the output neurons' weights and biases
    k = (1.0 + 2.0 * h0) / (1.0 + 2.0 * a.headroom)
    c["weights"] = w[:first] + [x * k for x in w[first:]]
    seeded = {}
    for key, value in c.items():  # the key where the controller file writes it
        if key == "amplitude":
            seeded["mixer_headroom"] = a.headroom
        if key != "mixer_headroom":
            seeded[key] = value
    doc["flap_unit_controller"] = seeded
    doc.pop("evolution", None)
    times = (f"1/(1 + 2 x {a.headroom})" if h0 == 0.0 else
             f"(1 + 2 x {h0})/(1 + 2 x {a.headroom})")
    print(f"# {a.file} given the attitude-first mixer, headroom {a.headroom}, its output "
          f"neurons' weights and biases times {times} (scripts/mixer_seed.py)")
    print(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100000), end="")


if __name__ == "__main__":
    main()
