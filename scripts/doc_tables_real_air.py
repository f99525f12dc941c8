"""Real air taken apart: afc_1's default-air controllers from three held-out seeds
(doc/flight_and_evolution.md), hover_1 under one of real air's impulses at a time, and the
lift fliers with an oracle that knows it (doc/hovering.md), the README's flight table: each creature's default-air controller against
the real-air bar (the same commands as shed_air_bar's rows; measured together, they run once),
and how fast the flap unit and the chains climb and sink open loop."""
import re

from doc_tables import Run, Table
from doc_tables_flight import (FLIGHT_CHECK, WIDE_STARTS, flips, lowest, meets_real_air_bar,
                               real_air_argv, starts)

SEEDS = (2024, 7, 99)
STEPS = (1, 0.5)
AFC_1 = [("`config/afc_1_shed_air_weights.yaml`", "config/afc_1_shed_air_weights.yaml"),
         ("`config/afc_1_shed_floor_weights.yaml` (24 episodes, an upright floor)",
          "config/afc_1_shed_floor_weights.yaml"),
         ("`config/afc_1_mixer_seed_weights.yaml` (the floor's, given the mixer at 0.1)",
          "config/afc_1_mixer_seed_weights.yaml"),
         ("`config/afc_1_mixer_weights.yaml` (that seed evolved)",
          "config/afc_1_mixer_weights.yaml")]


def seeds_table(name, seeds):
    """afc_1's controllers evolved in the default air, against the real-air bar from the
    held-out `seeds` at 1 and 0.5 ms: the table `name`."""
    def run_key(weights, seed, step):
        return f"{weights} | {seed} | {step}"
    runs = [Run(run_key(w, seed, step),
                real_air_argv(["--weights", w, "--velocity-noise", "0.05"], ["--seed", str(seed)],
                              step))
            for _, w in AFC_1 for seed in seeds for step in STEPS]

    def rows(out):
        result = []
        for label, w in AFC_1:
            met, every = [], []
            for seed in seeds:
                r = [starts(out[run_key(w, seed, step)]) for step in STEPS]
                met.append(" / ".join(str(sum(meets_real_air_bar(x) for x in s)) for s in r))
                every += r[0] + r[1]
            rms = [x["alt_rms"] for x in every if x["alt_rms"] is not None]
            result.append([label, "; ".join(met),
                           f"**{sum(meets_real_air_bar(x) for x in every)} of {len(every)}**",
                           str(flips(every)), f"{lowest(every, 'up_set'):.3f}",
                           f"{max(rms):.2f} m"])
        return result
    first, rest = seeds[0], "; ".join(str(x) for x in seeds[1:])
    return Table(name, "doc/flight_and_evolution.md",
                 ["controller", f"meet the bar (seed {first}: 1 / 0.5 ms; {rest})", "in all",
                  "flips", "lowest up after 10 s", "largest alt. rms after 10 s"], runs, rows,
                 f"each cell `{FLIGHT_CHECK} --weights FILE --velocity-noise 0.05 --altitude 5 "
                 f"{' '.join(WIDE_STARTS)} --real-air --seed N` with the step's `--step-size`; "
                 "the bar: no flip, lowest up-component above 0.5 after 10 s, altitude rms under "
                 "0.3 m, mean bank under 5 deg")


def afc_1_seeds():
    """afc_1's default-air controllers from the held-out seeds 2024, 7 and 99."""
    return seeds_table("afc_1_seeds", SEEDS)


def afc_1_more_seeds():
    """The same controllers from three more held-out seeds, 11, 12 and 13."""
    return seeds_table("afc_1_more_seeds", (11, 12, 13))


HOVER_GAINS = [("its gains (`config/hover_1_gains.yaml`)", "config/hover_1_gains.yaml"),
               ("the roll loop saturated (`config/hover_1_saturated_roll_gains.yaml`)",
                "config/hover_1_saturated_roll_gains.yaml")]
IMPULSES = [("roll torque for 0.5 s (real air's: 0.0119 N m)", "--gust-torque", "--gust-force",
             ("0.003", "0.006", "0.009"), "N m"),
            ("push on a wing for 0.2 s (real air's: 0.706 N)", "--gust-force", "--gust-torque",
             ("0.1", "0.2", "0.4"), "N")]
HOVER_STARTS = ["--altitude", "5", "--roll", "0.1", "--pitch", "0.1", "--starts", "10",
                "--duration", "30", "--threads", "2", "--real-air"]


def hover_impulses():
    """hover_1 in real air with one of its impulses at a time, at three sizes."""
    def run_key(gains, flag, size):
        return f"{gains} | {flag} | {size}"
    runs = [Run(run_key(g, flag, size),
                [FLIGHT_CHECK, "--hover", "--gains", g] + HOVER_STARTS + [flag, size, other, "0"])
            for _, g in HOVER_GAINS for _, flag, other, sizes, _ in IMPULSES for size in sizes]

    def rows(out):
        result = []
        for label, g in HOVER_GAINS:
            for name, flag, _, sizes, unit in IMPULSES:
                cells = []
                for size in sizes:
                    r = starts(out[run_key(g, flag, size)])
                    cells.append(f"{size} {unit}: {flips(r)} of {len(r)}")
                result.append([label, name] + cells)
        return result
    return Table("hover_impulses", "doc/hovering.md",
                 ["gains", "impulse", "the starts that flip", "", ""], runs, rows,
                 f"each cell `{FLIGHT_CHECK} --hover --gains FILE {' '.join(HOVER_STARTS)} "
                 "--gust-torque T --gust-force F`, the other impulse 0 (the rest of real air as "
                 "it is: wind, light turbulence, sensor noise and bias)")


ORACLE = "bin/hover_oracle"
ORACLE_CREATURES = [
    ("hover_1 (`config/hover_1_gains.yaml`)", ["--gains", "config/hover_1_gains.yaml"]),
    ("`config/morph_shed` (co-evolved; its gains)",
     ["--urdf", "config/morph_shed/creature.urdf", "--gains", "config/morph_shed/gains.yaml"])]
ORACLE_FRACTIONS = ("0.25", "0.5", "1")


def hover_oracle():
    """The lift fliers under one of real air's impulses, alone and with an oracle that knows when
    it comes (bench/hover_oracle.cpp), at three fractions of its size."""
    def run_key(label, impulse, fraction):
        return f"{label} | {impulse} | {fraction}"
    runs = [Run(run_key(label, impulse, f),
                [ORACLE] + args + ["--impulse", impulse, "--fraction", f])
            for label, args in ORACLE_CREATURES for impulse in ("torque", "push")
            for f in ORACLE_FRACTIONS]
    summary = re.compile(r"\(([\d.]+) of real air's\): the controller alone turns over in "
                         r"(\d+) of (\d+) starts .* some oracle pattern keeps (\d+) upright")

    def rows(out):
        result = []
        for label, _ in ORACLE_CREATURES:
            for impulse in ("torque", "push"):
                cells = []
                for f in ORACLE_FRACTIONS:
                    m = summary.search(out[run_key(label, impulse, f)])
                    cells.append(f"{m.group(2)} / **{m.group(4)}** of {m.group(3)}")
                result.append([label, impulse] + cells)
        return result
    return Table("hover_oracle", "doc/hovering.md",
                 ["creature", "impulse", "a quarter of real air's", "half", "real air's"], runs,
                 rows,
                 f"each cell `{ORACLE} [--urdf URDF] --gains FILE --impulse I --fraction F` "
                 "(bench/hover_oracle.cpp): 10 held-out starts within 0.1 rad holding 5 m, the "
                 "rest of real air as it is (wind, light turbulence, sensor noise and bias), each "
                 "flown until 3 s after the impulse; the starts in which the controller alone "
                 "turns over / **those that some one of 80 oracle patterns keeps upright**: the "
                 "controller with a feed-forward that knows when the impulse comes, one wing's "
                 "amplitude times 1 + r and the other's times 1 - r (r 0.1-0.6, within the "
                 "stroke's limit), the frequency as commanded or 1.3 times it, from 0 or 0.05 s "
                 "before the impulse to 0 or 0.1 s after its end, either wing the stronger")


NOISE = ["--velocity-noise", "0.05"]
README_FLYERS = [
    ("afc_1", "`config/afc_1_shed_floor_weights.yaml`",
     ["--weights", "config/afc_1_shed_floor_weights.yaml"] + NOISE),
    ("afc_4", "`config/afc_4_ceiling_weights.yaml`",
     ["--weights", "config/afc_4_ceiling_weights.yaml", "--pairs", "4"] + NOISE),
    ("afc_6", "`config/afc_4_ceiling_weights.yaml`",
     ["--weights", "config/afc_4_ceiling_weights.yaml", "--pairs", "6"] + NOISE),
    ("afc_12", "`config/afc_12_shed_air_weights.yaml`",
     ["--weights", "config/afc_12_shed_air_weights.yaml", "--pairs", "12"] + NOISE),
    ("hover_1", "`config/hover_1_gains.yaml` (hover.launch's)",
     ["--hover", "--gains", "config/hover_1_gains.yaml"]),
]


def readme_flight():
    """Each creature's default-air controller in real air, holding 5 m, against the bar."""
    def argv(flags, step):  # shed_air_bar's commands (bar_table in doc_tables_registry.py)
        return real_air_argv(flags, ["--added-mass-products", "shed"], step)
    runs = [Run(f"{c} | {step}", argv(flags, step)) for c, _, flags in README_FLYERS
            for step in STEPS]

    def rows(out):
        result = []
        for creature, label, flags in README_FLYERS:
            r = [starts(out[f"{creature} | {step}"]) for step in STEPS]
            every = r[0] + r[1]
            rms = [x["alt_rms"] for x in every if x["alt_rms"] is not None]
            met = " / ".join(f"{sum(meets_real_air_bar(x) for x in s)} of {len(s)}" for s in r)
            command = " ".join(argv(flags, STEPS[0]))
            result.append([creature, label, f"**{met}**", str(flips(every)),
                           f"{max(rms):.2f} m" if rms else "-", f"`{command}`"])
        return result
    return Table("readme_flight", "README.md",
                 ["creature", "controller", "meet the bar at 1 / 0.5 ms", "flips of 40",
                  "largest alt. rms after 10 s", "command (at 1 ms; `--step-size 0.0005` for "
                  "0.5 ms)"], runs, rows,
                 "real air, holding 5 m from 20 held-out starts within +-30 deg for 60 s; the "
                 "bar: no flip, lowest up-component above 0.5 after 10 s, altitude rms under "
                 "0.3 m, mean bank under 5 deg ([flight_and_evolution.md](doc/flight_and_evolution.md#the-air-with-the-products-shed) "
                 "has the rest)")


CHAIN_PAIRS = (1, 4, 12)


def chain_authority():
    """bench/vertical_authority.cpp --pairs N: the open-loop climb of the flap unit and of the
    chains of 4 and 12 units at each downstroke rate, in the default air, each with its own
    wing motors, and the chain of 4 with the unit's."""
    # (run key, flags, the wing motors make_creature gives it (N m), column header)
    columns = [(f"pairs {n}", ["--pairs", str(n)], 8 if n == 1 else 2, f"afc_{n}")
               for n in CHAIN_PAIRS]
    columns.append(("pairs 4 at 8 N m", ["--pairs", "4", "--wing-effort", "8"], 8, "afc_4 `--wing-effort 8`"))
    runs = [Run(key, ["bin/vertical_authority", "--flights", "1"] + flags)
            for key, flags, _, _ in columns]

    def rows(out):
        climbs = []
        for key, _, motors, _ in columns:
            text = out[key]
            found = re.findall(r"^ *([0-9]+) +([0-9]+) +(-?[0-9.]+) +[0-9.]+$", text, re.M)
            effort = re.search(r"([0-9.]+) N m wing motors", text)
            if not found or not effort:
                raise ValueError(f"vertical_authority ({key}): no climb rows or no motors")
            if float(effort.group(1)) != motors:
                raise ValueError(f"vertical_authority ({key}): {effort.group(1)} N m wing "
                                 f"motors, not the {motors} N m its column names")
            climbs.append(found)
        if len({tuple(r[:2] for r in c) for c in climbs}) != 1:
            raise ValueError("vertical_authority: the chains' rates differ from the unit's")
        return [[f"{down} / {up}"] + [f"{float(c[i][2]):.2f} m/s" for c in climbs]
                for i, (down, up, _) in enumerate(climbs[0])]
    return Table("chain_authority", "doc/flight_and_evolution.md",
                 ["downstroke / upstroke (rad/s)"] +
                 [f"{name} ({motors} N m motors) climbs at" for _, _, motors, name in columns],
                 runs, rows,
                 "`bin/vertical_authority --flights 1 --pairs N [--wing-effort 8]` "
                 "(bench/vertical_authority.cpp): the creature open loop from level at rest, "
                 "every wing at the row's rates, amplitude 1.2 rad, its root's mean vertical "
                 "speed over its whole strokes from 1 to 2.5 s (before it tips), in the default "
                 "air (the added mass's products shed; negative: it sinks); make_creature gives "
                 "one unit 8 N m wing motors and a chain 2 N m")


def unit_upstroke_authority():
    """bench/vertical_authority.cpp --max-upstroke-rate 65: the flap unit's open-loop climb over
    the range afc_1's network commands (downstrokes 20-60 rad/s, upstrokes 10-65), its fastest
    climb and sink, and the ideal controller's altitude rms with that authority."""
    run = Run("upstroke authority", ["bin/vertical_authority", "--max-upstroke-rate", "65"])
    row = re.compile(r"^  ([0-9]+) / ([0-9]+) rad/s: (-?[0-9.]+) m/s", re.M)
    bound = re.compile(r"^fastest climb ([0-9.]+) m/s at ([0-9]+) / ([0-9]+) rad/s, fastest sink "
                       r"([0-9.]+) m/s at ([0-9]+) / ([0-9]+) rad/s; .*mean ([0-9.]+) m, largest "
                       r"([0-9.]+) m of ([0-9]+) flights$", re.M)

    def rows(out):
        climb = {(int(d), int(u)): float(v) for d, u, v in row.findall(out[run.key])}
        ups = sorted({u for _, u in climb})
        if not ups or any((d, u) not in climb for d in (20, 60) for u in ups):
            raise ValueError("vertical_authority --max-upstroke-rate: not every row")
        return [[str(u), f"{climb[(20, u)]:.2f} m/s", f"{climb[(60, u)]:.2f} m/s"] for u in ups]

    def said(out):
        b = bound.search(out[run.key])
        if not b:
            raise ValueError("vertical_authority --max-upstroke-rate: no bound line")
        return ("`bin/vertical_authority --max-upstroke-rate 65` (bench/vertical_authority.cpp): "
                "the flap unit open loop from level at rest, both wings at the row's upstroke and "
                "the column's downstroke rate, its root's mean vertical speed over its whole "
                "strokes from 1 to 2.5 s, in the default air (negative: it sinks); its fastest "
                f"climb {b.group(1)} m/s (at {b.group(2)} / {b.group(3)} rad/s) and sink "
                f"{b.group(4)} m/s (at {b.group(5)} / {b.group(6)} rad/s); an ideal controller "
                "that knows the air's vertical speed w and climbs or sinks against it at up to "
                "those speeds (the `vertical_authority` table's, dz/dt = w - clamp(w + z / 0.5 s, "
                f"-climb, sink)): altitude rms after 10 s {b.group(7)} m on average and "
                f"{b.group(8)} m at worst over {b.group(9)} realisations of 60 s of light "
                "turbulence at 5 m in a 1 m/s wind")
    return Table("unit_upstroke_authority", "doc/flight_and_evolution.md",
                 ["upstroke (rad/s)", "downstroke 20 rad/s: climbs at",
                  "downstroke 60 rad/s: climbs at"], [run], rows, said)


CEILING = [("the previous default (`config/afc_4_shed_air_weights.yaml`)", "config/afc_4_shed_air_weights.yaml"),
           ("50 generations on 16 episodes (`config/afc_4_ceiling_16_weights.yaml`)",
            "config/afc_4_ceiling_16_weights.yaml"),
           ("then 18 on 24 episodes (`config/afc_4_ceiling_24_weights.yaml`)",
            "config/afc_4_ceiling_24_weights.yaml"),
           ("then 10 on 32 episodes (`config/afc_4_ceiling_weights.yaml`, the default)",
            "config/afc_4_ceiling_weights.yaml"),
           ("then 10 more on 32 (`config/afc_4_ceiling_more_weights.yaml`)",
            "config/afc_4_ceiling_more_weights.yaml")]
CEILING_CHAINS = (4, 6)
CEILING_12 = [("the default (`config/afc_12_shed_air_weights.yaml`)",
               "config/afc_12_shed_air_weights.yaml"),
              ("afc_4's carried (`config/afc_4_ceiling_weights.yaml`)",
               "config/afc_4_ceiling_weights.yaml"),
              ("that evolved on, on afc_12, 10 generations on 24 episodes "
               "(`config/afc_12_ceiling_24_weights.yaml`)",
               "config/afc_12_ceiling_24_weights.yaml")]


def ceiling_cell(r):
    """A ceiling table's cell for one flight of held-out starts: those that meet the bar; that
    flip; whose lowest up-component after 10 s is above 0.5; the mean altitude rms after 10 s."""
    rms = [x["alt_rms"] for x in r if x["alt_rms"] is not None]
    return (f"**{sum(meets_real_air_bar(x) for x in r)}**; {flips(r)}; "
            f"{sum(1 for x in r if x['up_set'] > 0.5)}; {sum(rms) / len(rms):.2f} m")


def chain_ceiling():
    """afc_4's controllers evolved with the altitude-rms ceiling on afc_4 and afc_6 in real air,
    against the bar, at 1 and 0.5 ms."""
    def run_key(weights, pairs, step):
        return f"{weights} | {pairs} | {step}"
    runs = [Run(run_key(w, n, step),
                real_air_argv(["--weights", w, "--pairs", str(n)] + NOISE, [], step))
            for _, w in CEILING for n in CEILING_CHAINS for step in STEPS]

    def rows(out):
        result = []
        for label, w in CEILING:
            cells = []
            for n in CEILING_CHAINS:
                for step in STEPS:
                    cells.append(ceiling_cell(starts(out[run_key(w, n, step)])))
            result.append([label] + cells)
        return result
    return Table("chain_ceiling", "doc/flight_and_evolution.md",
                 ["weights", "afc_4, 1 ms", "afc_4, 0.5 ms", "afc_6, 1 ms", "afc_6, 0.5 ms"],
                 runs, rows,
                 f"each cell `{FLIGHT_CHECK} --weights FILE --pairs N --velocity-noise 0.05 "
                 f"--altitude 5 {' '.join(WIDE_STARTS)} --real-air` with the step's "
                 "`--step-size`, 20 starts: those that meet the bar; that flip; whose lowest "
                 "up-component after 10 s is above 0.5; the mean altitude rms after 10 s")


MODERATE = ["--wind", "2", "--turbulence", "moderate", "--added-mass-products", "shed"]


def moderate_air():
    """The README's controllers in real air with moderate turbulence and a 2 m/s wind (the
    issue's report beside its bar), at 1 ms."""
    runs = [Run(c, real_air_argv(flags, MODERATE)) for c, _, flags in README_FLYERS]

    def rows(out):
        result = []
        for creature, label, _ in README_FLYERS:
            r = starts(out[creature])
            rms = [x["alt_rms"] for x in r if x["alt_rms"] is not None]
            result.append([creature, label, f"**{sum(meets_real_air_bar(x) for x in r)} of "
                           f"{len(r)}**", str(flips(r)), f"{lowest(r, 'up_set'):.3f}",
                           f"{sum(rms) / len(rms):.2f} m" if rms else "-",
                           f"{max(rms):.2f} m" if rms else "-"])
        return result
    return Table("moderate_air", "doc/flight_and_evolution.md",
                 ["creature", "controller", "meet the bar", "flips", "lowest up after 10 s",
                  "mean alt. rms after 10 s", "largest"], runs, rows,
                 f"each row the README's command (`{FLIGHT_CHECK} FLAGS --altitude 5 "
                 f"{' '.join(WIDE_STARTS)} --real-air ...`) with `{' '.join(MODERATE[:4])}`: "
                 "real air's impulses, noises and gyro bias in moderate turbulence (W20 15.43 m/s: "
                 "sigma_w 1.5 m/s at 5 m) and a 2 m/s wind, 20 held-out starts, 60 s at 1 ms; "
                 "the bar as the README's")


def chain_12_ceiling():
    """afc_12's controllers, the ceiling's carried from afc_4 and evolved on, in real air against
    the bar at 1 and 0.5 ms."""
    runs = [Run(f"{w} | {step}", real_air_argv(["--weights", w, "--pairs", "12"] + NOISE, [], step))
            for _, w in CEILING_12 for step in STEPS]

    def rows(out):
        return [[label] + [ceiling_cell(starts(out[f"{w} | {step}"])) for step in STEPS]
                for label, w in CEILING_12]
    return Table("chain_12_ceiling", "doc/flight_and_evolution.md",
                 ["weights", "afc_12, 1 ms", "afc_12, 0.5 ms"], runs, rows,
                 f"each cell `{FLIGHT_CHECK} --weights FILE --pairs 12 --velocity-noise 0.05 "
                 f"--altitude 5 {' '.join(WIDE_STARTS)} --real-air` with the step's "
                 "`--step-size`, 20 starts: those that meet the bar; that flip; whose lowest "
                 "up-component after 10 s is above 0.5; the mean altitude rms after 10 s")


TABLES = [afc_1_seeds, afc_1_more_seeds, hover_impulses, hover_oracle, readme_flight, chain_authority, chain_ceiling,
          moderate_air, chain_12_ceiling, unit_upstroke_authority]
