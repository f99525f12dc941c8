"""The registry of the docs' measured tables (scripts/doc_tables.py): name -> Table."""
import re

from doc_tables import Run, Table
from doc_tables_flight import (CONDITIONS, FLIGHT_CHECK, HOLD_CONDITIONS, TABLE_HEADER,
                               WIDE_STARTS, flips, height_range, hover_report, lowest,
                               max_abs_bank, mean_abs_bank, meets_real_air_bar, passed,
                               power_per_mass, real_air_argv, starts, step_argv, step_cell,
                               table_cells)

FLIGHT_DOC = "doc/flight_and_evolution.md"
TABLES = {}


def register(table):
    if table.name in TABLES:
        raise ValueError(f"two tables named {table.name}")
    TABLES[table.name] = table


def key(*parts):
    return " | ".join(str(p) for p in parts)


def flight_table(name, weights, pairs, steps, conditions, hold=None, creature=None):
    """scripts/flight_table.sh's table: each condition at each step, 20 starts within +-30 deg,
    60 s; `hold` M: every row holds M m; `creature`: the rows' first cell prefixed with it."""
    base = [FLIGHT_CHECK, "--weights", weights, "--pairs", str(pairs)] + WIDE_STARTS
    runs = []
    labels = []
    for condition, flags in conditions:
        label = condition + (f", hold {hold} m" if hold is not None else "")
        label = f"{creature}, {label}" if creature else label
        flags = flags + (["--altitude", str(hold)] if hold is not None else [])
        for step in steps:
            runs.append(Run(key(label, step), base + flags + step_argv(step)))
            labels.append((label, step))
    return runs, labels


def flight_rows(labels, with_up_set=True):
    def rows(out):
        return [[label, step_cell(step)] + table_cells(out[key(label, step)], with_up_set)
                for label, step in labels]
    return rows


def register_flight_table(name, weights, pairs, steps, conditions, hold=None, said_extra=""):
    runs, labels = flight_table(name, weights, pairs, steps, conditions, hold)
    said = (f"each row `{FLIGHT_CHECK} --weights {weights} --pairs {pairs} "
            f"{' '.join(WIDE_STARTS)}` with the condition's flags"
            f"{' and `--altitude ' + str(hold) + '`' if hold is not None else ''}"
            f" and the step's `--step-size`{said_extra}")
    register(Table(name, FLIGHT_DOC, TABLE_HEADER, runs, flight_rows(labels), said))


# --- doc/flight_and_evolution.md ------------------------------------------------------------

def held_out_starts():
    """The paper's Fig. 7/8 section: every committed climbing controller from 20 held-out
    starts within +-15 deg, 60 s, at three step sizes."""
    # 0.25 ms for the one-pair flyers only: a chain's 20 starts take 4-10 min of CPU there.
    one_pair = (1, 0.5, 0.25)
    flyers = [("afc_1, robust (`config/afc_1_weights.yaml`)", "afc_1, robust",
               ["--weights", "config/afc_1_weights.yaml", "--pairs", "1"], one_pair),
              ("afc_1, paper preset (`doc/evolution/paper/weights.yaml`, on `urdf/afc_1.urdf`)",
               "afc_1, paper preset",
               ["--weights", "doc/evolution/paper/weights.yaml", "--urdf", "urdf/afc_1.urdf"],
               one_pair)]
    for n, gain in ((4, 1), (6, 3), (12, 5)):
        extra = ", rates to 80 rad/s, attitude filter 0.05 s" if n in (4, 6) else ""
        flyers.append((f"afc_{n}, chain controller (`config/afc_{n}_weights.yaml`, pitch gain "
                       f"{gain}{extra})", f"afc_{n}, the same",
                       ["--weights", f"config/afc_{n}_weights.yaml", "--pairs", str(n)], (1, 0.5)))
    runs = []
    for label, _, argv, steps in flyers:
        for step in steps:
            runs.append(Run(key(label, step), [FLIGHT_CHECK] + argv + [
                "--starts", "20", "--duration", "60", "--threads", "2"] + step_argv(step)))

    def rows(out):
        result = []
        for label, again, _, steps in flyers:
            for i, step in enumerate(steps):
                s = starts(out[key(label, step)])
                result.append([label if i == 0 else again, step_cell(step),
                               f"{passed(s)}/{len(s)}", str(flips(s)),
                               f"{lowest(s, 'min_up'):.3f}", height_range(s),
                               f"{sum(r['upright'] for r in s) / len(s):.1f} %"])
        return result
    register(Table("held_out_starts", FLIGHT_DOC,
                   ["creature, controller", "step", "passed", "flips", "lowest up",
                    "final height", "time upright"], runs, rows,
                   f"each row `{FLIGHT_CHECK} --weights FILE --pairs N --starts 20 --duration 60 "
                   "--threads 2` (the paper preset's `--urdf urdf/afc_1.urdf` instead of "
                   "`--pairs`; 20 starts within +-15 deg, seed 2024) with the step's "
                   "`--step-size` (0.25 ms for afc_1 only)"))


def steady_wind():
    """The chains and afc_1 in a steady 1 m/s wind from a heading drawn per start, against
    still air."""
    flyers = [("afc_1 (`config/afc_1_weights.yaml`), climbing", "config/afc_1_weights.yaml", 1, []),
              ("afc_4 (`config/afc_4_weights.yaml`), climbing", "config/afc_4_weights.yaml", 4, []),
              ("afc_6 (`config/afc_6_weights.yaml`), climbing", "config/afc_6_weights.yaml", 6, []),
              ("afc_12 (`config/afc_12_altitude_weights.yaml`), holding 5 m",
               "config/afc_12_altitude_weights.yaml", 12, ["--altitude", "5"])]
    steps = (1, 0.5)
    runs = []
    for label, weights, pairs, flags in flyers:
        for step in steps:
            base = [FLIGHT_CHECK, "--weights", weights, "--pairs", str(pairs)] + WIDE_STARTS
            runs.append(Run(key(label, step, "wind"), base + ["--wind", "1"] + flags +
                            step_argv(step)))
            runs.append(Run(key(label, step, "still"), base + flags + step_argv(step)))

    def bank(s):
        return f"{mean_abs_bank(s):.2f} deg (max {max_abs_bank(s):.2f})"

    def rows(out):
        result = []
        for label, _, _, _ in flyers:
            for step in steps:
                w = starts(out[key(label, step, "wind")])
                s = starts(out[key(label, step, "still")])
                result.append([label, step_cell(step), f"{passed(w)}/{len(w)}", str(flips(w)),
                               f"{lowest(w, 'min_up'):.3f}", height_range(w), bank(w), bank(s),
                               f"{power_per_mass(out[key(label, step, 'wind')]):.0f} W/kg"])
        return result
    register(Table("steady_wind", FLIGHT_DOC,
                   ["creature", "step", "passed (1 m/s)", "flips", "lowest up", "heights",
                    "mean abs bank (largest)", "same, still air", "power (1 m/s)"], runs, rows,
                   f"each row `{FLIGHT_CHECK} --weights FILE --pairs N {' '.join(WIDE_STARTS)} "
                   "--wind 1 [--altitude 5]` with the step's `--step-size`, and the same without "
                   "`--wind` for the still-air column"))


def hover_cells(r):
    return [f"{r['z_lo']:.3f}-{r['z_hi']:.3f} m (rms {r['rms'] * 1000:.1f} mm)", f"{r['up']:.4f}",
            f"{r['p_pos']:.3f} W, {r['w_per_kg']:.1f} W/kg"]


def steady_wind_hover():
    """hover_1 under its evolved gains holding 3 m against a 1 m/s side wind, and in still air."""
    steps = (1, 0.5)
    base = [FLIGHT_CHECK, "--hover", "--gains", "config/hover_1_gains.yaml"]
    runs = []
    for step in steps:
        runs.append(Run(key("wind", step), base + ["--wind", "1"] + step_argv(step)))
        runs.append(Run(key("still", step), base + step_argv(step)))

    def rows(out):
        result = []
        for step in steps:
            w = hover_report(out[key("wind", step)])
            s = hover_report(out[key("still", step)])
            result.append(["hover_1, evolved gains, holding 3 m", step_cell(step),
                           "pass" if w["pass"] else "FAIL"] + hover_cells(w) + hover_cells(s))
        return result
    register(Table("steady_wind_hover", FLIGHT_DOC,
                   ["creature", "step", "1 m/s side wind", "height", "lowest up", "power",
                    "still air: height", "lowest up", "power"], runs, rows,
                   f"`{FLIGHT_CHECK} --hover --gains config/hover_1_gains.yaml [--wind 1]` with "
                   "the step's `--step-size` (figures after 10 s of 60)"))


def real_air():
    """afc_1's altitude controllers holding 5 m under the disturbances of real air, one at a
    time and all at once (--real-air)."""
    hand = "config/afc_1_altitude_weights.yaml"
    evolved = "config/afc_1_real_air_weights.yaml"
    climb = "config/afc_1_climb_weights.yaml"
    flyers = [
        (f"`{hand}` (hand-set reflex, rate cap, dihedral)", hand, ["--wind", "1"]),
        ("same", hand, ["--wind", "1", "--turbulence", "light"]),
        ("same", hand, ["--wind", "1", "--noise", "0.05", "--gyro-bias", "0.02",
                        "--altitude-noise", "0.05"]),
        ("same", hand, ["--wind", "1", "--gust-torque", "0.043", "--gust-time", "0.5"]),
        ("same", hand, ["--wind", "1", "--gust-force", "0.9", "--gust-time", "0.2"]),
        ("same", hand, ["--real-air"]),
        (f"`{evolved}` (evolved: the upstroke a second output, no hand-set term)", evolved,
         ["--real-air"]),
        ("same", evolved, ["--wind", "1", "--turbulence", "light"]),
        (f"`{climb}` (evolved on from it with a climb input)", climb,
         ["--real-air", "--velocity-noise", "0.05"]),
        ("same", climb, ["--wind", "1", "--turbulence", "light", "--velocity-noise", "0.05"]),
    ]
    steps = (1, 0.5)
    runs = []
    for label, weights, flags in flyers:
        for step in steps:
            runs.append(Run(key(weights, " ".join(flags), step),
                            [FLIGHT_CHECK, "--weights", weights, "--altitude", "5"] + WIDE_STARTS
                            + flags + step_argv(step)))

    def rows(out):
        result = []
        for label, weights, flags in flyers:
            outs = [out[key(weights, " ".join(flags), step)] for step in steps]
            s = [starts(o) for o in outs]
            rms = [max((r["alt_rms"] for r in x if r["alt_rms"] is not None), default=0) for x in s]
            result.append([label, f"`{' '.join(flags)}`",
                           " / ".join(str(flips(x)) for x in s),
                           " / ".join(str(passed(x)) for x in s) + f" of {len(s[0])}",
                           " / ".join(f"{mean_abs_bank(x):.1f} deg" for x in s),
                           " / ".join(f"{v:.2f} m" for v in rms),
                           f"{power_per_mass(outs[0]):.0f} W/kg"])
        return result
    register(Table("real_air", FLIGHT_DOC,
                   ["controller", "conditions", "flips (1 ms / 0.5 ms)", "passed (1 ms / 0.5 ms)",
                    "mean abs bank", "alt. rms after 10 s, max", "power (1 ms)"], runs, rows,
                   f"each row `{FLIGHT_CHECK} --weights FILE --altitude 5 {' '.join(WIDE_STARTS)}"
                   "` with its conditions, at 1 ms and with `--step-size 0.0005`"))



def bar_table(name, flyers, air, air_text):
    """The real-air bar's table `name` in flight_and_evolution.md: each (label, flags) of `flyers` in real air at
    1 and 0.5 ms, with `air` (flight_check flags of the air itself)."""
    steps = (1, 0.5)
    runs = [Run(key(label, step), real_air_argv(flags, air, step))
            for label, flags in flyers for step in steps]

    def rows(out):
        result = []
        for label, _ in flyers:
            for step in steps:
                text = out[key(label, step)]
                r = starts(text)
                rms = [x["alt_rms"] for x in r if x["alt_rms"] is not None]
                spin = re.search(r"at ([0-9]+) and ([0-9]+) rad/s", text)
                if not spin:
                    raise ValueError("flight_check --real-air output: no spin-up line")
                result.append([label, step_cell(step), str(flips(r)),
                               f"{lowest(r, 'up_set'):.3f}",
                               f"{max(rms):.2f} m" if rms else "-",
                               f"{max_abs_bank(r):.1f} deg",
                               f"**{sum(meets_real_air_bar(x) for x in r)} of {len(r)}**",
                               f"{sum(x['P+/m'] for x in r) / len(r):.0f} W/kg",
                               f"{spin.group(1)} / {spin.group(2)} rad/s"])
        return result
    air_flags = (" " + " ".join(air)) if air else ""
    register(Table(name, FLIGHT_DOC,
                   ["creature, controller", "step", "flips", "lowest up after 10 s",
                    "largest alt. rms after 10 s", "largest abs mean bank", "meet the bar",
                    "mean power", "torque / push, held rigid in vacuum"], runs, rows,
                   f"each row `{FLIGHT_CHECK} FLAGS --altitude 5 {' '.join(WIDE_STARTS)} "
                   f"--real-air{air_flags}` with the step's `--step-size` (FLAGS: the "
                   "controller's, `--hover --gains FILE` for the hover creature)" + air_text +
                   "; the bar: no flip, lowest "
                   "up-component above 0.5 after 10 s, altitude rms under 0.3 m, mean bank "
                   "under 5 deg; the last column: the roll rate real air's torque and push "
                   "would give the creature held rigid in vacuum, its angular impulse over its "
                   "roll inertia, as flight_check prints it (flapsim::realAirSpinUp)"))


def real_air_bar():
    """Every creature with a controller that holds an altitude, in real air, against the bar."""
    chain = "config/afc_4_real_air_weights.yaml"
    flyers = [
        ("afc_1, `config/afc_1_real_air_weights.yaml` (evolved)",
         ["--weights", "config/afc_1_real_air_weights.yaml"]),
        ("afc_1, `config/afc_1_climb_weights.yaml` (evolved on with a climb input; ground-speed "
         "noise 0.05 m/s)",
         ["--weights", "config/afc_1_climb_weights.yaml", "--velocity-noise", "0.05"]),
        ("afc_12, `config/afc_12_altitude_weights.yaml` (afc_1's altitude network, hand-set "
         "chain terms)", ["--weights", "config/afc_12_altitude_weights.yaml", "--pairs", "12"]),
        *((f"afc_{n}, `{chain}` ({how}; ground-speed noise 0.05 m/s)",
           ["--weights", chain, "--pairs", str(n), "--velocity-noise", "0.05"])
          for n, how in ((4, "evolved on afc_4 with a chain input"), (6, "the same, carried"),
                         (12, "the same, carried"))),
        ("hover_1, `config/hover_1_gains.yaml` (evolved gains)",
         ["--hover", "--gains", "config/hover_1_gains.yaml"]),
        ("`config/morph_116wkg` (body and gains co-evolved)",
         ["--hover", "--urdf", "config/morph_116wkg/creature.urdf", "--gains",
          "config/morph_116wkg/gains.yaml"]),
    ]
    bar_table("real_air_bar", flyers, [], "")


def shed_air_bar():
    """The same bar in the air with the added mass's products shed into the wake (the default
    since 7 December 2026): controllers evolved with the products omitted, and afc_1's evolved
    in it."""
    noise = ["--velocity-noise", "0.05"]
    flyers = [
        ("afc_1, `config/afc_1_climb_weights.yaml` (evolved with the products omitted)",
         ["--weights", "config/afc_1_climb_weights.yaml"] + noise),
        ("afc_1, `config/afc_1_shed_seed_weights.yaml` (evolved on from it in this air, 20 s "
         "episodes)", ["--weights", "config/afc_1_shed_seed_weights.yaml"] + noise),
        ("afc_1, `config/afc_1_shed_air_weights.yaml` (evolved on from that, 60 s episodes)",
         ["--weights", "config/afc_1_shed_air_weights.yaml"] + noise),
        ("afc_1, `config/afc_1_shed_floor_weights.yaml` (evolved on from that, 24 episodes, "
         "an upright floor)", ["--weights", "config/afc_1_shed_floor_weights.yaml"] + noise),
        ("afc_4, `config/afc_4_real_air_weights.yaml` (evolved with the products omitted)",
         ["--weights", "config/afc_4_real_air_weights.yaml", "--pairs", "4"] + noise),
        ("afc_4, `config/afc_4_shed_air_weights.yaml` (evolved on from it in this air)",
         ["--weights", "config/afc_4_shed_air_weights.yaml", "--pairs", "4"] + noise),
        ("afc_6, `config/afc_4_shed_air_weights.yaml` (the same)",
         ["--weights", "config/afc_4_shed_air_weights.yaml", "--pairs", "6"] + noise),
        ("afc_12, `config/afc_4_shed_air_weights.yaml` (the same, carried to 12 units)",
         ["--weights", "config/afc_4_shed_air_weights.yaml", "--pairs", "12"] + noise),
        ("afc_12, `config/afc_12_shed_air_weights.yaml` (evolved on from it on afc_12)",
         ["--weights", "config/afc_12_shed_air_weights.yaml", "--pairs", "12"] + noise),
        ("hover_1, `config/hover_1_gains.yaml` (evolved with the products omitted)",
         ["--hover", "--gains", "config/hover_1_gains.yaml"]),
    ]
    bar_table("shed_air_bar", flyers, ["--added-mass-products", "shed"],
              ", in the air with the added mass's velocity products shed into the wake; "
              "ground-speed noise 0.05 m/s for the networks with a climb input")


def real_air_apart():
    """Real air with its two impulses taken away one at a time (--gust-torque 0, --gust-force
    0): which of them flips each creature."""
    flyers = [
        ("afc_1, `config/afc_1_real_air_weights.yaml`",
         ["--weights", "config/afc_1_real_air_weights.yaml"]),
        ("hover_1, `config/hover_1_gains.yaml`",
         ["--hover", "--urdf", "urdf/hover_1.urdf", "--gains", "config/hover_1_gains.yaml"]),
        ("`config/morph_116wkg`",
         ["--hover", "--urdf", "config/morph_116wkg/creature.urdf", "--gains",
          "config/morph_116wkg/gains.yaml"]),
    ]
    variants = [("all of it", []), ("without the push", ["--gust-force", "0"]),
                ("without the torque", ["--gust-torque", "0"]),
                ("without either", ["--gust-torque", "0", "--gust-force", "0"])]
    runs = [Run(key(label, name), real_air_argv(flags, extra))
            for label, flags in flyers for name, extra in variants]

    def rows(out):
        result = []
        for label, _ in flyers:
            for name, extra in variants:
                r = starts(out[key(label, name)])
                rms = [x["alt_rms"] for x in r if x["alt_rms"] is not None]
                result.append([label, name + (f" (`{' '.join(extra)}`)" if extra else ""),
                               str(flips(r)), f"{sum(meets_real_air_bar(x) for x in r)} of {len(r)}",
                               f"{max(rms):.2f} m" if rms else "-"])
        return result
    register(Table("real_air_apart", FLIGHT_DOC,
                   ["creature, controller", "real air", "flips", "meet the bar",
                    "largest alt. rms after 10 s"], runs, rows,
                   f"each row `{FLIGHT_CHECK} FLAGS --altitude 5 {' '.join(WIDE_STARTS)} "
                   "--real-air` with the row's sizes (FLAGS as in the table above), at 1 ms"))


def vertical_authority():
    """bench/vertical_authority.cpp: the altitude rms an ideal controller reaches in light
    turbulence at each climb-and-sink authority, and the flap unit's climb at its rates."""
    run = Run("vertical_authority", ["bin/vertical_authority"])

    def rows(out):
        text = out[run.key]
        bound = re.findall(r"^ *([0-9]+\.[0-9]+) +([0-9.]+) +([0-9.]+)$", text, re.M)
        climb = {int(d): float(v) for d, _, v in
                 re.findall(r"^ *([0-9]+) +([0-9]+) +(-?[0-9.]+) +[0-9.]+$", text, re.M)}
        if len(bound) < 4 or not climb:
            raise ValueError("vertical_authority output: no bound or no climb rows")

        def unit(a):  # the flap unit's rates that climb and sink at least a
            up = [d for d, v in sorted(climb.items()) if v >= a]
            down = [d for d, v in sorted(climb.items()) if v <= -a]
            return (f"{up[0]}" if up else f"over {max(climb)}") + " / " + (
                f"{down[-1]}" if down else f"under {min(climb)}")
        return [[f"{float(a):.2f}", f"{float(m):.3f} m", f"{float(w):.3f} m", unit(float(a))]
                for a, m, w in bound]
    register(Table("vertical_authority", FLIGHT_DOC,
                   ["climb and sink A (m/s)", "ideal altitude rms, mean of 40",
                    "ideal altitude rms, largest of 40",
                    "flap unit downstroke rate (rad/s, upstroke 10) that climbs / sinks at A"],
                   [run], rows,
                   "`bin/vertical_authority` (bench/vertical_authority.cpp): an ideal controller "
                   "that knows the vertical air speed w and moves against it at up to A m/s "
                   "(dz/dt = w - clamp(w + z / 0.5 s, -A, A)), light turbulence at 5 m in a 1 m/s "
                   "wind, 40 realisations of 60 s, the rms after 10 s; the flap unit open loop "
                   "from level, both wings alike, its mean vertical speed over its whole strokes "
                   "from 1 to 2.5 s (before it tips), at 10, 20, 30, 40, 60, 80 and 100 rad/s"))


held_out_starts()
steady_wind()
steady_wind_hover()
real_air()
real_air_bar()
shed_air_bar()
real_air_apart()
vertical_authority()
register_flight_table("afc_1_altitude_climbing", "config/afc_1_altitude_weights.yaml", 1, (1, 0.5),
                      CONDITIONS + HOLD_CONDITIONS)
register_flight_table("afc_1_altitude_hold", "config/afc_1_altitude_weights.yaml", 1, (1, 0.5),
                      CONDITIONS, hold=5)
# 1 ms only: the 0.5 ms rows double its 20 min of CPU.
register_flight_table("afc_12_altitude_hold", "config/afc_12_altitude_weights.yaml", 12, (1,),
                      CONDITIONS, hold=5)
register_flight_table("afc_12_climbing", "config/afc_12_weights.yaml", 12, (1,), CONDITIONS)
register_flight_table("afc_1_paper_climbing", "config/afc_1_weights.yaml", 1, (1,), CONDITIONS)


def chains_climbing():
    """afc_4 and afc_6 climbing under their controllers in the disturbance conditions."""
    runs4, labels4 = flight_table("", "config/afc_4_weights.yaml", 4, (1, 0.5), CONDITIONS,
                                  creature="afc_4")
    runs6, labels6 = flight_table("", "config/afc_6_weights.yaml", 6, (1, 0.5), CONDITIONS,
                                  creature="afc_6")
    register(Table("afc_4_6_climbing", FLIGHT_DOC, ["creature, condition"] + TABLE_HEADER[1:],
                   runs4 + runs6, flight_rows(labels4 + labels6),
                   f"each row `{FLIGHT_CHECK} --weights config/afc_N_weights.yaml --pairs N "
                   f"{' '.join(WIDE_STARTS)}` with the condition's flags and the step's "
                   "`--step-size`"))


chains_climbing()


# --- doc/validation.md, doc/physics.md --------------------------------------------------------

def markdown_rows(out, source):
    """The markdown table a tool prints: its header cells and its rows' cells."""
    lines = [line for line in out.split("\n") if line.startswith("|")]
    if len(lines) < 3:
        raise ValueError(f"{source}: no markdown table in its output")
    def cells(line):
        return [c.strip() for c in line.strip().strip("|").split("|")]
    return cells(lines[0]), [cells(line) for line in lines[2:]]


ENERGY = "bin/flapsim_bench"


def energy_tables():
    """The energy audit: every creature in vacuum, air and water at three steps, in the default
    air (the added mass's velocity products shed into the wake; every column), and the residual
    in a fluid in each of the three airs (the products omitted, Kirchhoff's, shed)."""
    on = Run("velocity products", [ENERGY, "--energy", "--added-mass-products", "kirchhoff"])
    off = Run("omitted", [ENERGY, "--energy", "--added-mass-products", "omitted"])
    shed = Run("shed products", [ENERGY, "--energy"])

    def audit(out):
        return markdown_rows(out[shed.key], "flapsim_bench --energy")[1]

    def residual(out):
        tables = [markdown_rows(out[run.key], "flapsim_bench --energy") for run in (off, on, shed)]
        columns = [header.index("residual") for header, _ in tables]
        rows = zip(*(table_rows for _, table_rows in tables))
        return [same[0][:3] + [r[c] for r, c in zip(same, columns)] for same in rows
                if same[0][1] != "vacuum"]
    register(Table("energy_audit", "doc/validation.md",
                   ["creature", "medium", "step", "motor work (positive)", "air work",
                    "damping work", "kinetic", "potential", "spring", "fluid kinetic", "residual"],
                   [shed], audit, f"`{ENERGY} --energy` (it prints these rows)"))
    register(Table("energy_residual", "doc/validation.md",
                   ["creature", "medium", "step", "products omitted", "Kirchhoff's products",
                    "products shed (default)"], [off, on, shed], residual,
                   f"`{ENERGY} --energy --added-mass-products omitted`, `--added-mass-products "
                   "kirchhoff` and `--energy` (the residual column of their rows in air and "
                   "water)"))


energy_tables()


def pressure_sweep():
    """sweep's average pressure on the plate at 0-90 deg for each model (paper Fig. 14-15)."""
    run = Run("sweep", ["bin/sweep", "--out", "out/sweep"])
    angles = [0, 15, 30, 45, 60, 75, 90]

    def rows(out):
        found = {}
        for line in out[run.key].split("\n"):
            cells = line.split()
            if len(cells) == 7 and cells[0] in ("pressure", "quasi_steady") and cells[2] == "4":
                found[(cells[0], cells[1], float(cells[3]))] = float(cells[4])
        result = []
        for model, cd, label in (("pressure", "2.00", "pressure model, Cd 2.0 (Pa)"),
                                 ("pressure", "1.15", "pressure model, Cd 1.15 (Pa)"),
                                 ("quasi_steady", "0.00", "quasi-steady (Pa)")):
            values = [found.get((model, cd, float(a))) for a in angles]
            if None in values:
                raise ValueError(f"sweep output: no {model} Cd {cd} pressure at every angle")
            result.append([label] + [f"{v:.1f}" if v else "0" for v in values])
        return result
    register(Table("pressure_sweep", "doc/physics.md",
                   ["inclination (deg)"] + [str(a) for a in angles], [run], rows,
                   "`bin/sweep --out out/sweep` (the defaults; it prints these pressures and "
                   "writes `sweep.csv` and `sweep.png` into `out/sweep`)"))


pressure_sweep()


# --- doc/hovering.md --------------------------------------------------------------------------

def paddle_power(out):
    """flight_check's mean over the starts: positive power (W), W/kg, mass (g), net power (W),
    figure of merit and the ideal power (W)."""
    import re
    m = re.search(r"mean over the starts: ([0-9.]+) W positive \(([0-9.]+) W/kg of its "
                  r"([0-9.]+) g\), ([0-9.]+) W net; figure of merit ([0-9.]+) \(ideal "
                  r"([0-9.]+) W", out)
    if not m:
        raise ValueError("flight_check output: no mean power and figure of merit line")
    return [float(x) for x in m.groups()]


def hover_energy():
    """What flight costs: the hover creature under its evolved and its hand-designed gains in
    still air and a 1 m/s side wind, against the paper's paddle flier climbing."""
    hovers = [("evolved gains", "config/hover_1_gains.yaml"),
              ("hand-designed gains", "config/hover_1_hand_gains.yaml")]
    runs = []
    for label, gains in hovers:
        for wind in ([], ["--wind", "1"]):
            runs.append(Run(key(label, " ".join(wind)),
                            [FLIGHT_CHECK, "--hover", "--gains", gains] + wind))
    paddle = Run("afc_1", [FLIGHT_CHECK, "--weights", "config/afc_1_weights.yaml", "--threads", "2"])
    runs.append(paddle)

    def rows(out):
        result = []
        for label, gains in hovers:
            for wind, flight in (([], "hover at 3 m, still air"),
                                 (["--wind", "1"], "the same in a 1 m/s side wind")):
                r = hover_report(out[key(label, " ".join(wind))])
                result.append([f"hover_1 ({r['mass_g']:.1f} g), {label}", flight,
                               f"{r['z_lo']:.3f}-{r['z_hi']:.3f} m (rms {r['rms'] * 1000:.1f} "
                               f"mm), up >= {r['up']:.4f}", f"{r['stroke_mm']:.1f} mm",
                               f"{r['p_pos']:.3f} W", f"{r['w_per_kg']:.1f} W/kg",
                               f"{r['p_net']:.3f} W",
                               f"{r['ideal']:.3f} / {r['p_pos']:.3f} = {r['merit']:.2f}"])
        s = starts(out[paddle.key])
        p_pos, per_kg, mass, p_net, merit, ideal = paddle_power(out[paddle.key])
        result.append([f"afc_1 ({mass:.1f} g, the paper's paddle)",
                       f"ends {height_range(s, '{:.1f}-{:.1f} m')} high after 60 s under its "
                       f"network ({passed(s)}/{len(s)} pass)", "-", "-", f"{p_pos:.2f} W",
                       f"{per_kg:.0f} W/kg", f"{p_net:.2f} W",
                       f"{ideal:.3f} / {p_pos:.2f} = {merit:.3f}"])
        return result
    register(Table("hover_energy", "doc/hovering.md",
                   ["creature", "flight", "height", "per stroke", "P+ (positive)", "P+ / mass",
                    "P net", "figure of merit"], runs, rows,
                   f"`{FLIGHT_CHECK} --hover --gains FILE [--wind 1]` (60 s at 1 ms, figures "
                   f"after 10 s) and `{FLIGHT_CHECK} --weights config/afc_1_weights.yaml "
                   "--threads 2` (20 starts within +-15 deg, 60 s)"))


hover_energy()


def robofly():
    """test_robofly's mean lift coefficients of a Robofly wing's cycle (symmetric, advanced and
    delayed flip) against Dickinson, Lehmann & Sane 1999."""
    import re
    run = Run("test_robofly", ["build/devel/lib/flapsim/test_robofly"])
    published = 1.4

    def rows(out):
        text = out[run.key]
        sym = re.search(r"symmetric flip: mean C_L ([-0-9.]+)", text)
        adv = re.search(r"advanced flip: mean C_L ([-0-9.]+) \(([-0-9.]+) without", text)
        dl = re.search(r"delayed flip: mean C_L ([-0-9.]+) \(([-0-9.]+) without", text)
        if not (sym and adv and dl) or "[  PASSED  ]" not in text:
            raise ValueError("test_robofly output: no passing run printing the three flips")
        s, a, a0, d, d0 = (float(x) for x in (sym.group(1), adv.group(1), adv.group(2),
                                               dl.group(1), dl.group(2)))
        return [["Robofly, symmetric flip: mean lift coefficient over the cycle",
                 f"Dickinson, Lehmann & Sane 1999: about {published:g} (the robot's force "
                 "record; the figure as issue 24's work quotes it, not re-read from the paper "
                 "here)", f"{s:.3f}", f"{(s / published - 1) * 100:+.0f} %",
                 "the model has no wake: the robot flaps into the downwash of its earlier "
                 "strokes, which lowers the angle of attack the wing meets (wing-wake "
                 "interaction; Birch & Dickinson 2003, J Exp Biol 206: 2257), while the fit's "
                 "coefficients come from a wing's first revolution in still fluid. "
                 "`Robofly.SymmetricFlipMeanLiftIsThePublishedWithinTheMeasuredError`"],
                ["Robofly, advanced and delayed flips (8 % of the cycle early or late)",
                 "the robot: advanced rotation gives the most lift, delayed the least",
                 f"advanced {a:.3f} (rotational lift {a - a0:+.3f} of it), delayed {d:.3f} "
                 f"({d - d0:+.3f})",
                 f"the order of advanced and delayed is {'right' if a > d else 'wrong'}; "
                 f"advanced is {abs(a / s - 1) * 100:.0f} % {'below' if a < s else 'above'} our "
                 f"own symmetric {s:.3f}, where the robot's is above its symmetric",
                 "a flip that leads the reversal turns the wing past 90 deg while it still "
                 "translates, where the model's translational lift points down; its rotational "
                 "term (Sane & Dickinson 2002) makes up only part of that, and the model has no "
                 "wake capture. `Robofly.RotationalLiftRaisesAnAdvancedFlipAndLowersADelayedOne`"]]
    register(Table("robofly", "doc/validation.md",
                   ["case", "source and number", "flapsim (quasi-steady)", "error",
                    "where it fails"], [run], rows,
                   "`build/devel/lib/flapsim/test_robofly` (the figures it prints)"))


robofly()


# --- doc/performance.md -----------------------------------------------------------------------

def step_profile():
    """Instructions per step by stage under callgrind (bench/step_profile.py), the flap unit and
    the 12-unit chain over their first 2 s."""
    run = Run("profile", ["bench/step_profile.py", "--units", "1,12", "--seconds", "2",
                          "--no-timing"])

    def profile(text, units):
        """{stage: (instr/step, share %, per body, per cell)} of the creature of `units`
        units, in the order printed; a sub-stage's name starts with two spaces."""
        block = text.split(f"\n{units} unit(s): ", 1)
        if len(block) < 2:
            raise ValueError(f"step_profile output: no profile of {units} unit(s)")
        stages = {}
        for line in block[1].split("\n")[2:]:
            if not line.strip():
                break
            cells = line.rsplit(None, 4)
            if len(cells) != 5:
                raise ValueError(f"step_profile output: not a stage line: {line!r}")
            stages[cells[0]] = (int(cells[1]), float(cells[2].rstrip("%")), int(cells[3]),
                                float(cells[4]))
        return stages

    def rows(out):
        one, chain = profile("\n" + out[run.key], 1), profile("\n" + out[run.key], 12)
        if list(one) != list(chain):
            raise ValueError("step_profile output: the two creatures' stages differ")
        result = []
        parent = ""
        for stage, (n1, s1, _, _) in one.items():
            n12, s12, body, cell = chain[stage]
            parent = parent if stage.startswith("  ") else stage
            name = "of which " + stage.strip() if stage.startswith("  ") else stage
            whole = stage.startswith("whole step")
            per_cell = f" ({cell:.1f} per air cell)" if parent.startswith("air model") else ""
            result.append([name, f"{n1:,}" if whole else f"{n1:,} ({s1:.1f}%)",
                           f"{n12:,}" if whole else f"{n12:,} ({s12:.1f}%)",
                           f"{body:,}{per_cell}"])
        return result
    register(Table("step_profile", "doc/performance.md",
                   ["stage", "flap unit, instructions/step", "12 units", "per body (12 units)"],
                   [run], rows, "`bench/step_profile.py --units 1,12 --seconds 2 --no-timing` "
                   "(callgrind, `World::step` only)"))


step_profile()


# --- doc/validation.md: the cases the gtests check ---------------------------------------------

def validation_tables():
    from doc_tables_validation import TABLES as VALIDATION
    for make in VALIDATION:
        register(make())


validation_tables()


# --- the bench programs' tables: times, memory, answers (doc/urdf.md, doc/reliability.md, ...) --

def bench_tables():
    from doc_tables_bench import TABLES as BENCH
    for make in BENCH:
        register(make())


bench_tables()


def episode_rate():
    """Episodes per core-second of a robust (and the hover) evolution's first generation
    (bench/episode_rate.sh), at the steps the preset chooses and at the earlier settings."""
    names = ["afc_1", "afc_4", "afc_12"]
    base = ["bench/episode_rate.sh", "--runs", "3", "--population", "16", "--episodes", "4"]
    now = Run("now", base + names + ["hover"])
    earlier = Run("earlier", base + names + ["--", "--step-sizes", "0.001,0.0005",
                                             "--turn-substep", "0.0005", "--crash-height", "off"])

    def parse(text):
        """{creature: (steps, check s, episodes/core-s)} of the bench's rows."""
        found = {}
        for line in text.split("\n"):
            cells = line.split()
            if cells and (cells[0].startswith("afc_") or cells[0] == "hover") and len(cells) >= 6:
                found[cells[0]] = (" ".join(cells[1:-4]), cells[-4], float(cells[-1]))
        return found

    def steps_text(steps):
        """'0.004,0.002, 0.004' (step sizes, turn substep; s) as '4 and 2 ms, 4 ms pieces'."""
        m = re.match(r"^([0-9.]+),([0-9.]+), ([0-9.]+)$", steps)
        if not m:
            return steps
        h, half, pieces = (float(x) * 1000 for x in m.groups())
        return f"{h:g} and {half:g} ms, {pieces:g} ms pieces"

    def rows(out):
        a, b = parse(out[now.key]), parse(out[earlier.key])
        result = []
        for name in names + ["hover"]:
            if name not in a:
                raise ValueError(f"episode_rate output: no row for {name}")
            steps, check, rate = a[name]
            before = f"{b[name][2]:.1f}" if name in b else "-"
            ratio = f"{rate / b[name][2]:.2f}x" if name in b else "-"
            steps = steps_text(steps)
            result.append([name, steps, check, f"{rate:.1f}", before, ratio])
        return result
    register(Table("episode_rate", "doc/performance.md",
                   ["creature", "steps (chosen)", "choice, CPU s once", "episodes/core-s",
                    "1 and 0.5 ms, 0.5 ms pieces, no crash end", "ratio"],
                   [now, earlier], rows,
                   "`bench/episode_rate.sh --runs 3 --population 16 --episodes 4 NAME...` (one "
                   "thread, medians of 3 runs; the earlier settings with `-- --step-sizes "
                   "0.001,0.0005 --turn-substep 0.0005 --crash-height off`)"))


episode_rate()


def mujoco_tables():
    from doc_tables_mujoco import TABLES as MUJOCO
    for make in MUJOCO:
        register(make())


mujoco_tables()


def morph_tables():
    from doc_tables_morph import TABLES as MORPH
    for make in MORPH:
        register(make())


morph_tables()


def real_air_tables():
    from doc_tables_real_air import TABLES as REAL_AIR
    for make in REAL_AIR:
        register(make())


real_air_tables()


# The air before 7 December 2026: the tables measured with the added mass's products omitted
# (then the default, now --added-mass-products omitted) say so in their commands, which measure
# the same again; their stored commands were given the flag when it was named (doc/history.md).
OMITTED = ["--added-mass-products", "omitted"]
OMITTED_SAID = (", in the air with the added mass's products omitted (`--added-mass-products "
                "omitted`, the default until 7 December 2026)")
OMITTED_AIR_TABLES = (
    "held_out_starts", "steady_wind", "steady_wind_hover", "real_air", "real_air_bar",
    "real_air_apart", "afc_1_altitude_climbing", "afc_1_altitude_hold", "afc_12_altitude_hold",
    "afc_12_climbing", "afc_1_paper_climbing", "afc_4_6_climbing", "hover_energy",
    "vertical_authority")


def omitted_air():
    for name in OMITTED_AIR_TABLES:
        table = TABLES[name]
        for run in table.runs:
            if run.argv[0] in (FLIGHT_CHECK, "bin/vertical_authority"):
                run.argv += OMITTED
        said = table.said
        table.said = (lambda out, s=said: (s(out) if callable(s) else s) + OMITTED_SAID)


omitted_air()
