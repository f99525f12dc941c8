#!/usr/bin/python3
"""Writes the extended (mirror) flap-unit network set by hand as a PD controller, not evolved.

The mirror network (ann.h, FlapNetwork::kMirror: inputs up.forward, up.left, the roll, pitch and
yaw rates / rate_scale, the altitude error; 4 tanh hidden neurons; one sigmoid output, the right
wing's downstroke rate; the left wing's is the same net on mirrored inputs) can hold a linear
controller in its weights:

  hidden 0 = tanh(s (k_roll up.left + k_rate roll_rate / rate_scale))   attitude, odd under mirror
  hidden 1 = tanh(s altitude_error)                                     altitude, even under mirror
  right rate = min + (max - min) sigmoid(trim + hidden 0 / s + k_alt hidden 1 / s)

With a small s (0.1) the tanh stays near its linear part, so the logit of the rate is
trim + k_roll up.left + k_rate roll_rate / rate_scale + k_alt altitude_error: a proportional
roll term (right wing low, up.left > 0: the right wing beats faster), a roll-rate damping term and
a proportional altitude term; the left wing gets the mirror image, so the roll terms act
differentially and the altitude term in common. `trim` is the logit at which the flap unit
neither climbs nor sinks (measured: -0.7, 20 + 40 sigmoid(-0.7) = 33.2 rad/s with the phase lock).

usage: scripts/pd_flap_weights.py [--trim T] [--roll K] [--rate K] [--altitude K] > FILE.yaml
"""
import argparse

S = 0.1  # the hidden neurons' input scale (tanh near linear)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trim", type=float, default=-0.7, help="logit of the level rate")
    ap.add_argument("--roll", type=float, default=8.0, help="logit per unit of up.left")
    ap.add_argument("--rate", type=float, default=3.0, help="logit per 10 rad/s of roll rate")
    ap.add_argument("--altitude", type=float, default=5.0, help="logit per m of altitude error")
    ap.add_argument("--altitude-neuron-gain", type=float, default=S,
                    help="the altitude neuron's input weight g (its output weight is K / g): "
                         "0.5 keeps every weight within evolve's gene range of +-10, for --init")
    a = ap.parse_args()
    attitude = [0.0, S * a.roll, S * a.rate, 0.0, 0.0, 0.0, 0.0]
    g = a.altitude_neuron_gain
    altitude = [0.0, 0.0, 0.0, 0.0, 0.0, g, 0.0]
    unused = [0.0] * 14
    output = [1.0 / S, a.altitude / g, 0.0, 0.0, a.trim]
    weights = attitude + altitude + unused + output
    print(f"""# Flap-unit controller set by hand (not evolved): the mirror network as a PD controller.
# Reproduce: scripts/pd_flap_weights.py --trim {a.trim:g} --roll {a.roll:g} --rate {a.rate:g} --altitude {a.altitude:g} --altitude-neuron-gain {g:g}
# Weights: per neuron its input weights then its bias; hidden (tanh) neurons first, then the output (the right wing; the left is the net on mirrored inputs).
flap_unit_controller:
  network: mirror
  inputs: [world_up.body_forward, world_up.body_left, roll_rate, pitch_rate, yaw_rate, altitude_error]
  outputs: [right_downstroke_rate]
  rate_inputs: true
  rate_scale: 10
  altitude_input: true
  altitude_scale: 1
  hidden: 4
  hidden_activation: tanh
  output_activation: sigmoid
  min_downstroke_rate: 20
  max_downstroke_rate: 60
  upstroke_rate: 10
  amplitude: 1.2
  control_period: 0.02
  phase_lock: true
  pitch_gain: 0
  pitch_limit: 0.2
  pitch_max_downstroke_rate: 75
  weights: [{", ".join(f"{w:g}" for w in weights)}]""")


if __name__ == "__main__":
    main()
