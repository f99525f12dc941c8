"""The docs' tables measured by the bench programs (bench/): CPU and wall times, memory, the
answers of commands. The wall-clock ones say the load average their program saw."""
import json
import re

from doc_tables import Run, Table

ROS = "source build/devel/setup.bash && "


def load_said(text):
    """'load average X at the start, Y at the end' from a program's 'load average at the
    start/end: 1 5 15' lines (the 1-minute figures)."""
    found = dict(re.findall(r"^load average at the (start|end): ([0-9.]+)", text, re.M))
    if "start" not in found:
        raise ValueError("no 'load average at the start' line in the output")
    return f"load average {found['start']} at the start" + (
        f", {found['end']} at the end" if "end" in found else "")


# --- doc/urdf.md: a spawn of rings as their hull and their decomposition -----------------------

RINGS = [(32, 8), (32, 16), (64, 16), (64, 32), (96, 26)]


def mesh_spawn_time():
    run = Run("mesh_spawn_time", ["bench/mesh_spawn_time.py", "--rings",
                                  ",".join(f"{nu}x{nv}" for nu, nv in RINGS), "--repeats", "3"])
    header = ["ring, triangles (NU x NV)"] + [
        f"**{2 * nu * nv}** ({nu} x {nv}, ring.obj)" if (nu, nv) == (64, 16)
        else f"{2 * nu * nv} ({nu} x {nv})" for nu, nv in RINGS]

    def medians(out):
        found = {(int(m.group(1)), int(m.group(2)), m.group(3)): float(m.group(4))
                 for m in re.finditer(r"^ring (\d+) x (\d+) \(\d+ triangles\), (hull|decomposed): "
                                      r".* median ([0-9.]+) s$", out[run.key], re.M)}
        for nu, nv in RINGS:
            for kind in ("hull", "decomposed"):
                if (nu, nv, kind) not in found:
                    raise ValueError(f"mesh_spawn_time output: no {kind} ring {nu} x {nv}")
        return found

    def rows(out):
        m = medians(out)

        def cell(nu, nv, kind):
            text = f"{m[(nu, nv, kind)]:.2f} s"
            return f"**{text}**" if (nu, nv) == (64, 16) and kind == "decomposed" else text
        return [["convex hull"] + [cell(nu, nv, "hull") for nu, nv in RINGS],
                ["convex decomposition"] + [cell(nu, nv, "decomposed") for nu, nv in RINGS]]

    def said(out):
        return (f"`{run.command()}` (user CPU time of a whole `flapsim_bench --urdf FILE --runs 1 "
                f"--seconds 0.001` process, the median of 3; {load_said(out[run.key])})")
    return Table("mesh_spawn_time", "doc/urdf.md", header, [run], rows, said)


# --- doc/reliability.md: the worker under the campaign's calls ---------------------------------

CAMPAIGN = Run("worker_campaign", ["bash", "-c", ROS + "/usr/bin/python3 bench/worker_campaign.py"])
CALL = re.compile(r"^(.{32}) +([0-9.]+) s +([0-9.]+) +([0-9.]+) +([0-9.]+)  (.*)$")


def campaign_memory(text):
    start = re.search(r"^worker at start: VmRSS ([0-9.]+) MB, VmHWM ([0-9.]+) MB", text, re.M)
    rounds = re.findall(r"^after round (\d): VmRSS ([0-9.]+) MB, VmHWM ([0-9.]+) MB", text, re.M)
    if not start or [r[0] for r in rounds] != ["1", "2", "3"]:
        raise ValueError("worker_campaign output: no memory at the start and after 3 rounds")
    return start.groups(), [r[1:] for r in rounds]


def worker_memory():
    def rows(out):
        (rss, hwm), rounds = campaign_memory(out[CAMPAIGN.key])
        return [["at start (one normal call made)", f"{rss} MB", f"{hwm} MB"],
                ["after round 1, 2, 3", ", ".join(r[0] for r in rounds) + " MB",
                 ", ".join(r[1] for r in rounds) + " MB"]]
    return Table("worker_memory", "doc/reliability.md", ["worker", "VmRSS", "VmHWM (peak)"],
                 [CAMPAIGN], rows,
                 f"`{CAMPAIGN.command()}` (VmRSS and VmHWM of `/proc/<pid>/status`)")


def worker_calls():
    def rows(out):
        text = out[CAMPAIGN.key]
        lines = text.split("\n")
        first = lines.index(next(line for line in lines if line.startswith("call ")))
        result = []
        for line in lines[first + 1:]:
            if line.startswith("after round 1"):
                break
            m = CALL.match(line)
            if not m:
                raise ValueError(f"worker_campaign output: not a call line: {line!r}")
            result.append([m.group(1).strip(), f"{float(m.group(2)):.3f} s",
                           f"{float(m.group(3)):.3f} s", m.group(6).replace("|", "\\|")])
        slowest = re.search(r"^slowest normal call: ([0-9.]+) s", text, re.M)
        if not result or not slowest:
            raise ValueError("worker_campaign output: no calls of round 1 or no slowest call")
        result.append(["the slowest normal call of the three rounds", "-",
                       f"{float(slowest.group(1)):.3f} s", "-"])
        return result

    def said(out):
        return (f"`{CAMPAIGN.command()}` (round 1 of 3; wall-clock times, "
                f"{load_said(out[CAMPAIGN.key])})")
    return Table("worker_calls", "doc/reliability.md",
                 ["call (round 1)", "answered in", "the normal call after it", "answer"],
                 [CAMPAIGN], rows, said)


# --- doc/reliability.md: the edges campaign's commands, answered now ---------------------------

def edges_replay():
    run = Run("edges_replay", ["bash", "-c", ROS + "bench/edges_replay.py"])

    def rows(out):
        result = []
        command = ended = None
        for line in out[run.key].split("\n"):
            if line.startswith("$ "):
                command, ended = line[2:], None
            elif line.startswith("exit ") or line.startswith("still running"):
                ended = line
            elif line.startswith("answer: "):
                if command is None or ended is None:
                    raise ValueError(f"edges_replay output: an answer without its command: {line!r}")
                answer = line[len("answer: "):].replace("|", "\\|")
                result.append([f"`{command}`", f"`{answer}` ({ended})"])
                command = None
        if not result:
            raise ValueError("edges_replay output: no command answered")
        return result
    return Table("edges_replay", "doc/reliability.md", ["command", "answer now"], [run], rows,
                 f"`{run.command()}` (each command run with `rosrun flapsim` in the directory of "
                 "the files, against `roslaunch flapsim empty_world.launch paused:=true` on a "
                 "master of its own; the answer is the line that answers, the whole output is in "
                 "the raw file)")


# --- doc/ros_interface.md: the node's real-time factor against the core's ----------------------

def node_rtf():
    creatures = [("flap unit", "--pairs 1"), ("12-unit chain", "--pairs 12"),
                 ("flap unit, Python subscribers on /tf, odom, joint_states",
                  "--pairs 1 --subscribe"), ("12-unit chain, same subscribers",
                                             "--pairs 12 --subscribe")]
    runs = [Run(label, ["bash", "-c", ROS + "bench/node_rtf.py " + flags])
            for label, flags in creatures]

    def figures(text):
        node = re.search(r"wall -> real-time factor ([0-9.]+)", text)
        core = re.search(r"steps/s, real-time factor ([0-9.]+)", text)
        ratio = re.search(r"^node / core = ([0-9.]+)", text, re.M)
        if not (node and core and ratio):
            raise ValueError("node_rtf output: no node, core and node / core figures")
        return float(node.group(1)), float(core.group(1)), float(ratio.group(1))

    def rows(out):
        result = []
        for run in runs:
            node, core, ratio = figures(out[run.key])
            result.append([run.key, f"{node:.3g}", f"{core:.3g}", f"{ratio:.2f}"])
        return result

    def said(out):
        return ("`bench/node_rtf.py --pairs N [--subscribe]` after `source build/devel/setup.bash`"
                " (10 s of wall time each; " + "; ".join(
                    f"{run.key.split(',')[0]}{' with subscribers' if 'subscribe' in run.argv[-1] else ''}: "
                    f"{load_said(out[run.key])}" for run in runs) + ")")
    return Table("node_rtf", "doc/ros_interface.md", ["creature", "node", "core", "node / core"],
                 runs, rows, said)


# --- doc/farm.md: episodes per second in process and through the farm --------------------------

FARM_RUNS = [Run(f"run {i}", ["bash", "bench/farm_bench.sh"]) for i in (1, 2)]
FARM_ROWS = [("in process, 1 thread", r"^in process, 1 thread\(s\): ([0-9.]+) episodes/s"),
             ("in process, 2 threads", r"^in process, 2 thread\(s\): ([0-9.]+) episodes/s"),
             ("farm, 1 worker", r"^farm, 1 worker\(s\): ([0-9.]+) episodes/s"),
             ("farm, 2 workers", r"^farm, 2 worker\(s\): ([0-9.]+) episodes/s")]
# The run projected: the robust preset's, generations 0-100 of the generation farm_bench.sh
# times (32 individuals x 12 episodes).
GENERATIONS, TASKS = 100, 32 * 12


def farm_rates(out):
    """{row label: [episodes/s of each run]}; every run's fitness.csv files must agree."""
    rates = {}
    for run in FARM_RUNS:
        text = out[run.key]
        if "fitness.csv the same in all four: yes" not in text:
            raise ValueError(f"farm_bench.sh {run.key}: the four fitness.csv files differ")
        for label, pattern in FARM_ROWS:
            m = re.search(pattern, text, re.M)
            if not m:
                raise ValueError(f"farm_bench.sh {run.key}: no {label} rate")
            rates.setdefault(label, []).append(float(m.group(1)))
    return rates


def farm_said(out):
    return ("`bash bench/farm_bench.sh`, twice (generation 0 of `evolve --generations 0 --seed "
            "5`, the robust preset: 32 individuals x 12 episodes of 20 s; fitness.csv the same in "
            "all four evaluations of each run; " + "; ".join(
                f"{run.key}: {load_said(out[run.key])}" for run in FARM_RUNS) + ")")


def farm_speed():
    def rows(out):
        rates = farm_rates(out)
        one = rates["in process, 1 thread"]
        result = []
        for label, _ in FARM_ROWS:
            ratios = [r / o for r, o in zip(rates[label], one)]
            lo, hi = f"{min(ratios):.2f}", f"{max(ratios):.2f}"
            result.append([label, ", ".join(f"{r:.1f}" for r in rates[label]),
                           lo if lo == hi else f"{lo}-{hi}"])
        return result
    return Table("farm_speed", "doc/farm.md", ["evaluation", "episodes/s", "vs 1 thread"],
                 FARM_RUNS, rows, farm_said)


def farm_projection():
    def rows(out):
        per_worker = sum(farm_rates(out)["farm, 2 workers"]) / len(FARM_RUNS) / 2
        episodes = TASKS * (GENERATIONS + 1)
        result = []
        for machines in (1, 4, 16):
            workers = 2 * machines
            wall = episodes / (per_worker * workers) + GENERATIONS / per_worker
            when = f"about {wall / 60:.1f} min" if wall >= 120 else f"about {wall:.0f} s"
            if machines == 16:
                when += f" (a generation has {TASKS} tasks: {TASKS // workers} per worker)"
            result.append([str(machines), str(workers), when])
        return result

    def said(out):
        per_worker = sum(farm_rates(out)["farm, 2 workers"]) / len(FARM_RUNS) / 2
        return (f"projected from the two workers' rate of the table above, {per_worker:.1f} "
                f"episodes/s per worker, for {GENERATIONS + 1} generations of {TASKS} episodes: "
                f"{TASKS * (GENERATIONS + 1)} / (rate x workers) + {GENERATIONS} / rate; "
                + farm_said(out))
    return Table("farm_projection", "doc/farm.md", ["machines", "workers", "projected wall time"],
                 FARM_RUNS, rows, said)


# --- doc/farm.md: a generation's wall time, creature by creature -----------------------------

SEED_WEIGHTS = "config/afc_1_extended_weights.yaml"
# (creature, evolve's flags): generation 0 seeded from a shipped controller, so that its
# episodes fly as a learnt population's do (most to their end), as bench/episode_rate.sh's.
GENERATION_CREATURES = [
    ("afc_1", ["--pairs", "1", "--init", SEED_WEIGHTS]),
    ("afc_4", ["--pairs", "4", "--init", SEED_WEIGHTS]),
    ("afc_12", ["--pairs", "12", "--init", SEED_WEIGHTS]),
    ("hover", ["--preset", "hover", "--init", "config/hover_1_gains.yaml"]),
]
GENERATION_RUNS = [Run(name, ["bash", "bench/farm_bench.sh", "--"] + flags)
                   for name, flags in GENERATION_CREATURES]


def generation_cells(text, label, pattern):
    m = re.search(pattern + r", wall time ([0-9.]+) s", text, re.M)
    if not m:
        raise ValueError(f"farm_bench.sh: no {label} rate and wall time")
    return f"{float(m.group(1)):.1f} /s, {float(m.group(2)):.1f} s"


def generation_wall_time():
    def rows(out):
        result = []
        for run in GENERATION_RUNS:
            text = out[run.key]
            same = "yes" if "fitness.csv the same in all four: yes" in text else "**no**"
            result.append([run.key] + [generation_cells(text, label, pattern)
                                       for label, pattern in FARM_ROWS] + [same])
        return result

    def said(out):
        return ("`bash bench/farm_bench.sh -- FLAGS` for each creature (FLAGS: "
                + "; ".join(f"{name} `{' '.join(flags)}`" for name, flags in GENERATION_CREATURES)
                + "): generation 0 of `evolve --generations 0 --seed 5` with the preset's "
                "population and episodes (robust: 32 x 12 of 20 s; hover: its own), in process "
                "and on a farm of one-thread workers on this 2-core machine; the wall time is "
                "evolve's, the robust preset's step choice (made once per evolution) included ("
                + "; ".join(f"{run.key}: {load_said(out[run.key])}" for run in GENERATION_RUNS)
                + ")")
    return Table("generation_wall_time", "doc/farm.md",
                 ["creature"] + [f"{label}: episodes/s, wall time" for label, _ in FARM_ROWS]
                 + ["fitness.csv the same in all four"], GENERATION_RUNS, rows, said)


# --- doc/performance.md: what a step costs, creature by creature -------------------------------

STEP_COST = Run("flapsim_bench", ["bin/flapsim_bench", "--runs", "5", "--seconds", "2",
                                  "--cpu-time", "--json"])


def step_cost():
    def rows(out):
        data = json.loads(out[STEP_COST.key])
        result = []
        for c in data["creatures"]:
            step_us = 1e6 / c["steps_per_second"]
            cells = c["air_cells"]
            per_cell = f"{1e3 * step_us * c['air_share'] / cells:.1f}" if cells else "-"
            result.append([c["creature"], str(c["bodies"]), str(cells),
                           f"{c['steps_per_second'] / 1e3:.1f} k", f"{step_us:.2f}",
                           f"{1e3 * c['us_per_body_step']:.0f}", f"{100 * c['air_share']:.0f} %",
                           per_cell])
        flock = data["flock_16"]
        unit = next(c for c in data["creatures"] if c["creature"] == "flap_unit")
        result.append(["16 flap units, a flock (1 / 2 threads)", str(16 * unit["bodies"]),
                       str(16 * unit["air_cells"]),
                       f"{flock['steps_per_second_1_thread'] / 1e3:.1f} k / "
                       f"{flock['steps_per_second_2_threads'] / 1e3:.1f} k "
                       f"(x{flock['speedup']:.2f}, results "
                       f"{'identical' if flock['identical'] else '**not identical**'})",
                       f"{1e6 / flock['steps_per_second_1_thread']:.2f} / "
                       f"{1e6 / flock['steps_per_second_2_threads']:.2f}", "-", "-", "-"])
        return result

    def said(out):
        data = json.loads(out[STEP_COST.key])
        return (f"`{STEP_COST.command()}` (medians of 5 runs of 2 simulated s at 1 ms, CPU time; "
                "every wing 30/10 rad/s, amplitude 0.8 rad, from 50 m; the air's share from the "
                "same runs with the air off; the flock in wall time, its 16 creatures stepped on 1 "
                "and on 2 threads; a finer grid of 8 x 8 cells per face makes the flap "
                f"unit's step x{data['grid_8x8_step_time_ratio']:.2f})")
    return Table("step_cost", "doc/performance.md",
                 ["creature", "bodies", "air cells", "steps/s", "us a step", "ns per body a step",
                  "air's share", "ns per air cell a step"], [STEP_COST], rows, said)


TABLES = [mesh_spawn_time, worker_memory, worker_calls, edges_replay, node_rtf, farm_speed,
          farm_projection, generation_wall_time, step_cost]
