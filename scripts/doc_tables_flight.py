"""flight_check's output, read: the per-start lines and the summary of a flight of held-out
starts, and the hover flight's report; the cells the flight tables of the docs are made of."""
import re

FLIGHT_CHECK = "bin/flight_check"
# The disturbance conditions of the flight tables (scripts/flight_table.sh's): name, flags.
CONDITIONS = [
    ("still air", []),
    ("wind 1 m/s", ["--wind", "1"]),
    ("wind 2 m/s", ["--wind", "2"]),
    ("roll torque 0.05 N m, 0.5 s", ["--gust-torque", "0.05", "--gust-time", "0.5"]),
    ("1 N up on one wing, 0.2 s", ["--gust-force", "1", "--gust-time", "0.2"]),
    ("attitude noise 0.1 rad", ["--noise", "0.1"]),
]
HOLD_CONDITIONS = [("hold 5 m", ["--altitude", "5"]),
                   ("hold 5 m, wind 1 m/s", ["--altitude", "5", "--wind", "1"])]
# 20 held-out starts within +-30 deg, 60 s, on both cores (results do not depend on threads).
WIDE_STARTS = ["--roll", "0.52", "--pitch", "0.52", "--starts", "20", "--duration", "60",
               "--threads", "2"]
NUMBER = re.compile(r"^[-+]?[0-9.]+(e[-+]?[0-9]+)?")


def number(cell):
    """The number a cell starts with ('56.87m' -> 56.87, '-4.89°' -> -4.89), None for '-'."""
    if cell == "-":
        return None
    match = NUMBER.match(cell)
    if not match:
        raise ValueError(f"flight_check output: not a number: {cell!r}")
    return float(match.group(0))


def step_argv(step):
    """--step-size for a step in ms (none for flight_check's default 1 ms)."""
    return [] if step == 1 else ["--step-size", f"{step / 1000:g}"]


def real_air_argv(flags, extra=(), step=1):
    """flight_check in real air holding 5 m from the wide starts: `flags` the creature's and its
    controller's, `extra` after --real-air (the air, a seed, an impulse's size), then the step.
    The real-air tables build their commands here, so that the same flight is the same command
    (doc_tables.py runs a command once per invocation)."""
    return ([FLIGHT_CHECK] + list(flags) + ["--altitude", "5"] + WIDE_STARTS + ["--real-air"]
            + list(extra) + step_argv(step))


def step_cell(step):
    return f"{step:g} ms"


def starts(out):
    """The per-start rows of a flight of held-out starts: one dict per start, keyed by the
    header's names (numbers without their units; 'flipped' and 'result' as words)."""
    lines = out.split("\n")
    header = None
    rows = []
    for line in lines:
        cells = line.split()
        if cells[:2] == ["start", "roll"]:
            header = cells
        elif header and cells and cells[0].isdigit() and cells[1] != "of":
            if len(cells) != len(header):
                raise ValueError(f"flight_check output: {len(cells)} cells for {len(header)} "
                                 f"columns: {line!r}")
            row = dict(zip(header, cells))
            for k in header:
                if k not in ("flipped", "result", "wind"):
                    row[k] = number(row[k])
            rows.append(row)
    if not rows:
        raise ValueError("flight_check output: no per-start lines")
    return rows


def meets_real_air_bar(row):
    """Issue 40's bar for one start: no flip, up-component above 0.5 after settling, altitude
    rms under 0.3 m, mean bank under 5 deg."""
    return (row["flipped"] == "no" and row["up_set"] > 0.5 and row["alt_rms"] is not None
            and row["alt_rms"] < 0.3 and abs(row["bank"]) < 5.0)


def power_per_mass(out):
    """The mean positive motor power per mass over the starts, W/kg."""
    match = re.search(r"mechanical power of the motors.*?\(([0-9.]+) W/kg", out)
    if not match:
        raise ValueError("flight_check output: no 'mechanical power of the motors' line")
    return float(match.group(1))


def passed(rows):
    return sum(r["result"] == "pass" for r in rows)


def flips(rows):
    return sum(r["flipped"] == "yes" for r in rows)


def lowest(rows, key):
    return min(r[key] for r in rows)


def height_range(rows, fmt="{:.1f} to {:.1f} m"):
    return fmt.format(min(r["final_z"] for r in rows), max(r["final_z"] for r in rows))


def mean_abs_bank(rows):
    return sum(abs(r["bank"]) for r in rows) / len(rows)


def max_abs_bank(rows):
    return max(abs(r["bank"]) for r in rows)


def table_cells(out, with_up_set=True):
    """scripts/flight_table.sh's cells after condition and step: passed, flips, lowest up,
    [lowest up after 10 s,] final height, mean abs bank, max drift, alt. rms after 10 s."""
    rows = starts(out)
    rms = [r["alt_rms"] for r in rows if r["alt_rms"] is not None]
    cells = [f"{passed(rows)}/{len(rows)}", str(flips(rows)), f"{lowest(rows, 'min_up'):.3f}"]
    if with_up_set:
        cells.append(f"{lowest(rows, 'up_set'):.3f}")
    cells += [height_range(rows), f"{mean_abs_bank(rows):.2f} deg",
              f"{max(r['drift'] for r in rows):.1f} m", f"max {max(rms):.2f} m" if rms else "-"]
    return cells


TABLE_HEADER = ["condition", "step", "passed", "flips", "lowest up", "lowest up after 10 s",
                "final height", "mean abs bank", "max drift", "alt. rms after 10 s"]


def hover_report(out):
    """flight_check --hover's report: height range and rms (m), lowest up-component, largest
    height range in a stroke (mm), drift (m), positive and net power (W), W/kg, the ideal
    power (W), the figure of merit, and whether it passed."""
    pattern = (r"height ([0-9.]+) to ([0-9.]+) m \(rms ([0-9.]+) m\), lowest up-component "
               r"([0-9.]+), largest height range in a stroke ([0-9.]+) mm, drift ([0-9.]+) m")
    m = re.search(pattern, out)
    p = re.search(r"motors: ([0-9.]+) W positive \(([0-9.]+) W/kg of its ([0-9.]+) g\), "
                  r"([0-9.]+) W net", out)
    f = re.search(r"figure of merit: ideal ([0-9.]+) W .* = ([0-9.]+)", out)
    if not (m and p and f):
        raise ValueError("flight_check --hover output: no height, power or figure-of-merit line")
    return {"z_lo": float(m.group(1)), "z_hi": float(m.group(2)), "rms": float(m.group(3)),
            "up": float(m.group(4)), "stroke_mm": float(m.group(5)), "drift": float(m.group(6)),
            "p_pos": float(p.group(1)), "w_per_kg": float(p.group(2)), "mass_g": float(p.group(3)),
            "p_net": float(p.group(4)), "ideal": float(f.group(1)), "merit": float(f.group(2)),
            "pass": out.rstrip().split("\n")[-1].strip() == "pass"}
