#!/usr/bin/python3
"""Writes a flap-unit weights file widened by a new input, its weights 0, or by hidden neurons.

The climb input (FlapControllerParams::climb_input: the root's vertical speed / climb_scale)
comes after the altitude error in the network's inputs, the chain input (chain_input: the
unit's place along the chain times the chain's pitch) last; each hidden neuron gets a weight 0
for the new one, so the widened network commands what the file's does, and `evolve
--climb-input on --init` (or `--chain-input on`) can start from a controller evolved without it.

With --hidden H the network gets H hidden neurons instead: neuron k of the new ones copies the
input weights and bias of the file's neuron k mod (its hidden count), and every output's weight
from it is 0, so the widened network too commands what the file's does and `evolve --hidden H
--init` starts from it.

usage: scripts/widen_weights.py FILE [--input climb|chain] [--climb-scale S] > WIDENED.yaml
       scripts/widen_weights.py FILE --hidden H > WIDENED.yaml
"""
import argparse
import sys

import yaml


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="a weights file without the input to add")
    ap.add_argument("--input", choices=["climb", "chain"], default="climb",
                    help="the input to add (climb)")
    ap.add_argument("--climb-scale", type=float, default=1.0, help="m/s per unit input (1)")
    ap.add_argument("--hidden", type=int, help="hidden neurons to widen to, instead of an input")
    a = ap.parse_args()
    with open(a.file) as f:
        doc = yaml.safe_load(f)
    c = doc["flap_unit_controller"]
    if a.hidden is not None:
        return widen_hidden(a.file, doc, a.hidden)
    key = a.input + "_input"
    if c.get(key):
        sys.exit(f"widen_weights: {a.file} already has the {a.input} input")
    inputs = list(c["inputs"])
    if a.input == "chain":
        at, name = len(inputs), "chain_position.chain_pitch"
    else:
        at, name = len(inputs), "climb_rate"
        if "altitude_error" in inputs:
            at = inputs.index("altitude_error") + 1
        if "chain_position.chain_pitch" in inputs:
            at = min(at, inputs.index("chain_position.chain_pitch"))
    n, hidden, w = len(inputs), int(c["hidden"]), list(c["weights"])
    widened = []
    for k in range(hidden):
        neuron = w[k * (n + 1):(k + 1) * (n + 1)]
        widened += neuron[:at] + [0.0] + neuron[at:]
    widened += w[hidden * (n + 1):]
    c["inputs"] = inputs[:at] + [name] + inputs[at:]
    c[key] = True
    if a.input == "climb":
        c["climb_scale"] = a.climb_scale
    c["weights"] = widened
    doc.pop("evolution", None)
    print(f"# {a.file} widened by a {a.input} input whose weights are 0 "
          "(scripts/widen_weights.py)")
    print(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100000), end="")


def widen_hidden(path, doc, wanted):
    """Prints `doc` (the weights file at `path`) with `wanted` hidden neurons."""
    c = doc["flap_unit_controller"]
    n, hidden, w = len(c["inputs"]), int(c["hidden"]), list(c["weights"])
    if wanted <= hidden:
        sys.exit(f"widen_weights: --hidden {wanted} is not more than {path}'s {hidden} hidden "
                 "neurons")
    outputs = (len(w) - hidden * (n + 1)) // (hidden + 1)
    if hidden * (n + 1) + outputs * (hidden + 1) != len(w):
        sys.exit(f"widen_weights: {path} has {len(w)} weights, not a {n}-{hidden}-N network's")
    layer = w[:hidden * (n + 1)]
    for k in range(hidden, wanted):
        j = k % hidden
        layer += w[j * (n + 1):(j + 1) * (n + 1)]
    out_at = hidden * (n + 1)
    for o in range(outputs):
        neuron = w[out_at + o * (hidden + 1):out_at + (o + 1) * (hidden + 1)]
        layer += neuron[:hidden] + [0.0] * (wanted - hidden) + neuron[hidden:]
    c["hidden"] = wanted
    c["weights"] = layer
    doc.pop("evolution", None)
    print(f"# {path} widened to {wanted} hidden neurons, the new ones copies whose output "
          "weights are 0 (scripts/widen_weights.py --hidden)")
    print(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100000), end="")


if __name__ == "__main__":
    main()
