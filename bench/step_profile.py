#!/usr/bin/python3
"""Where a step's time goes: instructions per 1 ms step of flapsim's core world, by stage.

  bench/step_profile.py [--bin DIR] [--seconds 2] [--skip 0] [--units 1,12] [--no-timing]

For each creature of N flap units (make_creature --pairs N, flying from z = 50 m with every
wing stroking at 30/10 rad/s and amplitude 0.8 rad, as flapsim_bench does) it runs
`flapsim_bench --urdf` under valgrind's callgrind, counting only World::step (instruction
counts repeat to a few in a million whatever else the machine runs), and prints per step,
per body and per air cell: the whole step, the air model (its per-face work and per-cell
sums apart), the servo solve (which on a lean step takes the velocity update into its own
pass over the tree), the articulated-body velocity update (its velocities and bias forces,
and its own passes when no servo acts and the fluid has no implicit part), Bullet's own stages
(position integration; collision and constraint solving, which lean steps skip), the
momentum balance, the drives, the watchdog and the rest. Unless --no-timing, it then times
the same creature natively (`flapsim_bench --urdf --cpu-time --runs 5`, CPU time of the
thread) for nanoseconds per step and per instruction. With --skip S the profile is of the
stretch [S, S + seconds] of the flight: the difference of two callgrind runs, over S + seconds
and over S (the runs are deterministic, so the counts subtract exactly), and the timing skips
S untimed. Prints figures; never passes or fails.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

STEP = 0.001  # s, WorldParams::step_size

# Bullet's constraint solve: its solver, and on a lean step the frames and islands it needs.
CONSTRAINTS = [("incl", "btMultiBodyDynamicsWorld::solveInternalConstraints("),
               ("in", "flapsim::ServoWorld::solveConstraintsAfterServos(", "btMultiBodyDynamicsWorld::forwardKinematics("),
               ("in", "flapsim::ServoWorld::solveConstraintsAfterServos(", "btMultiBodyDynamicsWorld::calculateSimulationIslands("),
               ("in", "flapsim::ServoWorld::solveConstraintsAfterServos(", "btMultiBodyDynamicsWorld::buildIslands(")]

# The lean step's velocity update (TreeDynamics): its bias forces when the step begins, and its
# own passes in the constraint phase when the servo solve did not take it.
TREE = [("in", "flapsim::ServoWorld::", "flapsim::TreeDynamics::")]

# Bullet's step: the phases of ServoWorld that the creature's (sub)step calls (whichever of
# them and of their halves the compiler kept apart), from wherever it inlined the (sub)step.
BULLET_STEP = [("in", caller, "flapsim::ServoWorld::")
               for caller in ("flapsim::(anonymous namespace)::", "flapsim::stepCreature(")]

# Stages: (label, how its instructions are found). "incl F": F's inclusive count; "in P > F":
# what F cost when called from P. Sub-stages are indented under their stage and included
# in it. Each pattern is the start of a demangled name.
STAGES = [
    ("air model (fluid stage)", [("incl", "flapsim::AirStage::apply(")]),
    ("  pressure law (per face and per cell)", [("incl", "flapsim::pressureLaw("),
                                               ("incl", "flapsim::PressureBatch::")]),
    ("  link kinematics for the air", [("in", "flapsim::AirStage::apply(", "flapsim::LinkFrames::kinematics(")]),
    ("  added mass turned, buoyancy, drag test", [("in", "flapsim::AirStage::apply(", "flapsim::CreatureFluid::addedMass("),
                                                  ("in", "flapsim::AirStage::apply(", "flapsim::buoyancyLaw("),
                                                  ("in", "flapsim::AirStage::apply(", "flapsim::needsImplicitDrag("),
                                                  ("in", "flapsim::AirStage::apply(", "flapsim::pressureDragDamping(")]),
    ("servo solve (+ velocity update, lean steps)", [("incl", "flapsim::ServoStage::solve(")]),
    ("velocity update: bias (+ own passes)", TREE),
    ("Bullet: its articulated-body pass", [("incl", "btMultiBody::computeAccelerationsArticulatedBodyAlgorithmMultiDof(")]),
    ("Bullet: position integration", [("incl", "btMultiBody::stepPositionsMultiDof(")]),
    ("Bullet: collision detection", [("incl", "flapsim::ServoWorld::performDiscreteCollisionDetection(")]),
    ("Bullet: constraint solve (joint limits, contacts)", CONSTRAINTS),
    ("Bullet: rest of its step", BULLET_STEP
     + [("-" + r[0],) + r[1:] for r in TREE]
     + [("-incl", "btMultiBody::computeAccelerationsArticulatedBodyAlgorithmMultiDof("),
        ("-incl", "btMultiBody::stepPositionsMultiDof("),
        ("-incl", "flapsim::ServoWorld::performDiscreteCollisionDetection(")]
     + [("-" + r[0],) + r[1:] for r in CONSTRAINTS]),
    ("momentum balance (begin and end)", [("incl", "flapsim::MomentumBalance::end("),
                                          ("incl", "flapsim::MomentumBalance::begin(")]),
    ("drives, stroke turns, servo bookkeeping", [("incl", "flapsim::applyDrives("), ("incl", "flapsim::strokeTurn("),
                                                 ("incl", "flapsim::ServoStage::begin("),
                                                 ("incl", "flapsim::ServoStage::integrateSaturated(")]),
    ("watchdog (snapshot, motion check)", [("incl", "flapsim::BulletBody::motionFault"),
                                           ("incl", "flapsim::BodySnapshot::take(")]),
]
TOTAL = "flapsim::World::step(int)"


def parse_tree(text):
    """{function: inclusive Ir}, {(caller, callee): Ir}, {callee: calls} from
    callgrind_annotate --tree=calling."""
    inclusive, calls, times, current = {}, {}, {}, None
    line_re = re.compile(r"^\s*([\d,]+) \([ \d.%]+\)\s+([*>])\s+\S*?:(.*?)( \(\d[\d,]*x\))? \[")
    for line in text.splitlines():
        m = line_re.match(line)
        if not m:
            if not line.strip():
                current = None
            continue
        ir, mark, name = int(m.group(1).replace(",", "")), m.group(2), m.group(3)
        if mark == "*":
            current = name
            inclusive[name] = inclusive.get(name, 0) + ir
        elif current is not None:
            calls[(current, name)] = calls.get((current, name), 0) + ir
            if m.group(4):
                n = int(m.group(4).strip(" (x)").replace(",", ""))
                times[name] = times.get(name, 0) + n
    return inclusive, calls, times


def profile(bench, urdf, seconds, tmp):
    """parse_tree() of a callgrind run of `seconds` of flight, World::step only."""
    out = os.path.join(tmp, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", f"--toggle-collect={TOTAL}",
                    f"--callgrind-out-file={out}", bench, "--urdf", urdf, "--runs", "1",
                    "--seconds", str(seconds)],
                   check=True, capture_output=True)
    tree = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--tree=calling",
                           "--threshold=100", out],
                          check=True, capture_output=True, text=True).stdout
    return parse_tree(tree)


def subtract(runs):
    """The first run's counts less the second's (if any), per key."""
    if len(runs) == 1:
        return runs[0]
    return tuple({k: v - b.get(k, 0) for k, v in a.items()} for a, b in zip(runs[0], runs[1]))


def count(inclusive, calls, rules):
    def incl(prefix):
        return sum(v for k, v in inclusive.items() if k.startswith(prefix))
    total = 0
    for rule in rules:
        if rule[0] == "incl":
            total += incl(rule[1])
        elif rule[0] == "-incl":
            total -= incl(rule[1])
        elif rule[0] == "-in":
            total -= sum(v for (p, c), v in calls.items()
                         if p.startswith(rule[1]) and c.startswith(rule[2]))
        else:
            total += sum(v for (p, c), v in calls.items()
                         if p.startswith(rule[1]) and c.startswith(rule[2]))
    return total


def flapsim_bench(bench, urdf, seconds, extra):
    out = subprocess.run([bench, "--urdf", urdf, "--seconds", str(seconds)] + extra,
                         check=True, capture_output=True, text=True).stdout
    m = re.search(r"(\d+) bodies, (\d+) air cells, .*: (\d+) steps/s", out)
    return int(m.group(1)), int(m.group(2)), float(m.group(3))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(here, "..", "build", "devel", "lib", "flapsim"))
    ap.add_argument("--seconds", type=float, default=2.0, help="simulated seconds profiled")
    ap.add_argument("--skip", type=float, default=0.0, help="simulated seconds before them")
    ap.add_argument("--units", default="1,12", help="flap units per creature, comma-separated")
    ap.add_argument("--no-timing", action="store_true", help="instructions only")
    args = ap.parse_args()
    bench = os.path.join(args.bin, "flapsim_bench")
    make = os.path.join(args.bin, "make_creature")
    steps = int(args.seconds / STEP)
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(u) for u in args.units.split(",")]:
            urdf = os.path.join(tmp, f"units_{n}.urdf")
            subprocess.run([make, "--pairs", str(n), "--output", urdf], check=True,
                           capture_output=True)
            runs = [profile(bench, urdf, args.skip + args.seconds, tmp)]
            if args.skip > 0:
                runs.append(profile(bench, urdf, args.skip, tmp))
            inclusive, calls, times = subtract(runs)
            bodies, cells, _ = flapsim_bench(bench, urdf, 0.001, ["--runs", "1"])
            total = count(inclusive, calls, [("incl", TOTAL)])
            substeps = sum(v for k, v in times.items() if k.startswith("flapsim::ServoWorld::beginStep("))
            # Only Bullet's full step calls its external-forces stage (a lean step does not).
            full = sum(v for k, v in times.items()
                       if k.startswith("btMultiBodyDynamicsWorld::solveExternalForces("))
            print(f"\n{n} unit(s): {bodies} bodies, {cells} air cells; callgrind over {steps} "
                  f"steps of 1 ms after {args.skip:g} s of flight from rest at z = 50 m: "
                  f"{substeps} substeps, {full} of them Bullet's full step")
            print(f"{'stage':46s} {'instr/step':>11s} {'share':>7s} {'/body':>8s} {'/cell':>7s}")
            named = 0
            for label, rules in STAGES:
                ir = count(inclusive, calls, rules)
                if not label.startswith(" "):
                    named += ir
                print(f"{label:46s} {ir / steps:11.0f} {100 * ir / total:6.1f}% "
                      f"{ir / steps / bodies:8.0f} {ir / steps / cells:7.1f}")
            rest = total - named
            print(f"{'rest (snapshot, wrenches, loop)':46s} {rest / steps:11.0f} "
                  f"{100 * rest / total:6.1f}% {rest / steps / bodies:8.0f} "
                  f"{rest / steps / cells:7.1f}")
            print(f"{'whole step (World::step)':46s} {total / steps:11.0f} {100.0:6.1f}% "
                  f"{total / steps / bodies:8.0f} {total / steps / cells:7.1f}")
            if not args.no_timing:
                _, _, sps = flapsim_bench(bench, urdf, args.seconds,
                                          ["--runs", "5", "--cpu-time", "--skip", str(args.skip)])
                ns = 1e9 / sps
                print(f"native, CPU time, median of 5 runs: {sps:.0f} steps/s = "
                      f"{ns:.0f} ns/step, {ns / bodies:.0f} ns/body, {ns / cells:.1f} ns/cell, "
                      f"{ns / (total / steps):.3f} ns/instruction")
    return 0


if __name__ == "__main__":
    sys.exit(main())
