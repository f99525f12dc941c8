"""The docs' tables measured against MuJoCo: bench/vs_mujoco.sh's speed comparison
(doc/performance.md) and bench/mujoco_wing.sh's plate (doc/validation.md). Both run against the
MuJoCo the environment names (FLAPSIM_MUJOCO_INCLUDE, FLAPSIM_MUJOCO_LIB: one built from source)
or else Debian's; their output names its version, which the tables quote."""
import math
import re
import statistics

from doc_tables import Run, Table

# --- doc/performance.md: flapsim against MuJoCo, in alternating pairs ---------------------------

VS_MUJOCO = "bench/vs_mujoco.sh"
CREATURES = {"flap_unit": "flap unit (3)", "chain_12": "12 units (36)"}
# (creature, what the row compares, simulated s a run, MuJoCo's integrator and step (s),
#  flapsim's step and turn substep (s; None: its default 0.5 ms)).
COMPARISONS = [
    ("flap_unit", "same 1 ms step", 10, "implicitfast", 0.001, 0.001, None),
    ("flap_unit", "fastest that pass", 10, "implicit", 0.0046, 0.012, 0.002),
    ("chain_12", "same 1 ms step", 2, "implicitfast", 0.001, 0.001, None),
    ("chain_12", "fastest that pass", 2, "implicitfast", 0.0014, 0.012, 0.004),
]
PAIRS = 9


def ms(seconds):
    return f"{seconds * 1000:g} ms"


def comparison_run(name, what, seconds, integrator, step, fstep, substep):
    argv = [VS_MUJOCO, "--pairs", str(PAIRS), "--seconds", str(seconds), "--integrator",
            integrator, "--step", str(step), "--flapsim-step", str(fstep)]
    if substep is not None:
        argv += ["--flapsim-turn-substep", str(substep)]
    return Run(f"{name}, {what}", argv + [name])


def check_cell(text, prefix):
    """'stable, height at 3 s 8.9 % off the reference's' from a --check probe's lines (those of
    flapsim prefixed `flapsim   `)."""
    heights = {}
    verdict = None
    for line in text.split("\n"):
        m = re.match(r"^  " + prefix + r"(setting|reference) .*height change ([-0-9.]+) m after "
                     r"([0-9.]+) s", line)
        if m:
            heights[m.group(1)] = (float(m.group(2)), float(m.group(3)))
        m = re.match(r"^  " + prefix + r"verdict: (.*)$", line)
        if m:
            verdict = m.group(1)
    if verdict is None or len(heights) != 2:
        raise ValueError(f"vs_mujoco.sh output: no {prefix.strip() or 'MuJoCo'} check")
    (dz, at), (ref, _) = heights["setting"], heights["reference"]
    return (f"{verdict}: height at {at:g} s {abs(dz - ref) / abs(ref) * 100:.1f} % off the "
            f"reference's ({dz:.2f} m against {ref:.2f} m)")


def rate(x):
    return f"{x / 1000:.0f} k" if x >= 1e5 else f"{x / 1000:.1f} k" if x >= 1e4 else \
        f"{x / 1000:.2f} k"


def mujoco_version(text):
    m = re.search(r"^MuJoCo: MuJoCo ([^,]+), ", text, re.M)
    if not m:
        raise ValueError("vs_mujoco.sh output: no 'MuJoCo:' line naming its version")
    return m.group(1)


def comparison_row(run, comparison, text):
    name, what, seconds, integrator, step, fstep, substep = comparison
    pairs = [line.split() for line in text.split("\n")
             if re.match(rf"^{name} +\d+ +(fm|mf) ", line)]
    median = re.search(rf"^{name} +median +([0-9.]+) +([0-9.]+) +([0-9.]+)$", text, re.M)
    fsetting = ms(fstep) + (f", {ms(substep)} turn substeps" if substep else "")
    setting = f"{mujoco_version(text)} {integrator}, {ms(step)}; flapsim {fsetting}"
    mj_check = check_cell(text, "")
    f_check = check_cell(text, "flapsim   ")
    if f"{name}: not counted" in text or not median:
        return [CREATURES[name] + ", " + what, setting, "-", "-", "not timed", mj_check, f_check]
    if len(pairs) != PAIRS:
        raise ValueError(f"vs_mujoco.sh output: {len(pairs)} pairs of {name}, not {PAIRS}")
    ours = statistics.median(float(p[3]) for p in pairs)
    theirs = statistics.median(float(p[4]) for p in pairs)
    ratio = float(median.group(3))
    return [CREATURES[name] + ", " + what, setting, rate(ours), rate(theirs), f"**{ratio:.3g}**",
            mj_check, f_check]


def load_range(outputs):
    loads = [float(x) for text in outputs for x in
             re.findall(r"^load average at the (?:start|end): ([0-9.]+)", text, re.M)]
    if not loads:
        raise ValueError("vs_mujoco.sh output: no load average")
    return f"{min(loads):.1f}-{max(loads):.1f}"


def mujoco_comparison():
    runs = [comparison_run(*c) for c in COMPARISONS]

    def rows(out):
        return [comparison_row(r, c, out[r.key]) for r, c in zip(runs, COMPARISONS)]

    def said(out):
        texts = [out[r.key] for r in runs]
        sources = {re.search(r"^MuJoCo: .*\(from (.*)\)$", t, re.M).group(1) for t in texts}
        return (f"`{VS_MUJOCO} --pairs {PAIRS} --seconds T --integrator I --step S "
                "--flapsim-step S [--flapsim-turn-substep S] NAME` (T = 10 simulated s a run for "
                "the flap unit, 2 for the chain; medians of 9 alternating pairs of 3 runs each, "
                f"CPU time; MuJoCo from {' and '.join(sorted(sources))}; the 1-minute load "
                f"average {load_range(texts)} over the runs on 2 cores shared with other work)")
    return Table("mujoco_comparison", "doc/performance.md",
                 ["creature (bodies), setting", "MuJoCo; flapsim", "flapsim steps/s",
                  "MuJoCo steps/s", "flapsim / MuJoCo per simulated s",
                  "MuJoCo's check (10 s, against RK4 at 1/16 ms)",
                  "flapsim's check (10 s, against itself at 1/16 ms)"], runs, rows, said)


# --- doc/validation.md: the hover wing's plate in MuJoCo and in flapsim -------------------------

WING = Run("mujoco_wing", ["bash", "bench/mujoco_wing.sh"])
ROBOFLY_CL = (0.225, 1.58, 2.13, 7.20)  # C_L = a + b sin(c alpha - d), degrees
ROBOFLY_CD = (1.92, 1.55, 2.04, 9.82)  # C_D = a - b cos(c alpha - d)
SUN_TANG = 1.27  # mean drag over mean lift at 37 deg


def robofly(fit, deg, sign):
    a, b, c, d = fit
    f = math.sin if sign > 0 else math.cos
    return a + sign * b * f(math.radians(c * deg - d))


def wing_output(text):
    """MuJoCo's version, {alpha: (qs C_L, qs C_D, mj C_L, mj C_D, pr C_L, pr C_D)} and the
    water start's figures."""
    version = re.search(r"^MuJoCo ([0-9][^ ]*)$", text, re.M)
    plate = re.search(r"^plate ([0-9.]+) x ([0-9.]+) x ([0-9.]+) m", text, re.M)
    water = re.search(r"C_A = ([0-9.]+) \(m_a = [0-9.e+-]+ kg, ([0-9]+) times the plate\): "
                      r"([-0-9.]+) m/s\^2; flapsim ([-0-9.]+) m/s\^2 \(([-+0-9.]+) %\); MuJoCo "
                      r"([-0-9.]+) m/s\^2 \(([-+0-9.]+) %\)", text)
    rows = {}
    for line in text.split("\n"):
        m = re.match(r"^ *([0-9]+) \|" + r" +([-0-9.]+)" * 2 + r" \|" + r" +([-0-9.]+)" * 2 +
                     r" \|" + r" +([-0-9.]+)" * 2 + "$", line)
        if m:
            rows[int(m.group(1))] = tuple(float(x) for x in m.groups()[1:])
    if not (version and plate and water) or not {0, 37, 45, 90} <= set(rows):
        raise ValueError("mujoco_wing output: no version, plate, water start or angles "
                         "0, 37, 45 and 90")
    return version.group(1), [float(x) for x in plate.groups()], rows, water.groups()


def pct(ours, theirs):
    return f"{(ours / theirs - 1) * 100:+.0f} %".replace("+0 %", "0 %").replace("-0 %", "0 %")


def wing_rows(out):
    version, (chord, span, _), c, water = wing_output(out[WING.key])
    cl45, cd90 = robofly(ROBOFLY_CL, 45, 1), robofly(ROBOFLY_CD, 90, -1)
    qs_ratio, pr_ratio = c[37][1] / c[37][0], c[37][5] / c[37][4]
    lift = [["translational lift of a wing at 45 deg (steady, after the start)",
             "Robofly, Dickinson, Lehmann & Sane 1999 (Science 284: 1954), measured C_L = 0.225 + "
             f"1.58 sin(2.13 a - 7.20): {cl45:.2f} at 45 deg; C_D = 1.92 - 1.55 cos(2.04 a - "
             f"9.82): {cd90:.2f} at 90 deg",
             f"quasi-steady: C_L {c[45][0]:.3f}, C_D {c[90][1]:.3f}; pressure (the paper's law): "
             f"C_L {c[45][4]:.3f}, C_D {c[90][5]:.3f}",
             f"quasi-steady {pct(c[45][0], cl45)} and {pct(c[90][1], cd90)} (it is built on this "
             "fit: this shows the plate's cells sum to it, not an independent check); pressure "
             f"{pct(c[45][4], cl45)} and {pct(c[90][5], cd90)}",
             "the pressure law has no leading-edge vortex: a third of a flapping wing's lift"],
            ["mid-stroke angle of attack 37 deg of a hovering fruit fly: mean drag over mean lift",
             "Sun & Tang 2002 (J Exp Biol 205: 2413, CFD of Drosophila virilis, symmetric "
             f"rotation): drag {SUN_TANG} x lift at the 37 deg that carries the weight",
             f"quasi-steady at 37 deg: C_D / C_L = {c[37][1]:.3f} / {c[37][0]:.3f} = "
             f"{qs_ratio:.2f}; pressure: {c[37][5]:.3f} / {c[37][4]:.3f} = {pr_ratio:.2f}",
             f"{pct(qs_ratio, SUN_TANG)} and {pct(pr_ratio, SUN_TANG)}",
             "the quasi-steady model is translational: no drag peaks of the wing's rotation and "
             "wake capture at the reversals, which carry much of a hovering insect's drag (Sun & "
             "Tang's figure includes them); its power is an underestimate by as much"]]
    return lift + [mujoco_plate_row(version, c), water_row(chord, span, water)]


def mujoco_plate_row(version, c):
    k = c[45][2]
    kutta = all(abs(v[2] - k * math.sin(2 * math.radians(a))) < 0.002 for a, v in c.items())
    drags = [v[3] for a, v in c.items() if a >= 5]
    flat = max(drags) - min(drags) < 0.005
    cl37 = robofly(ROBOFLY_CL, 37, 1)
    drag = (f"C_D {drags[-1]:.3f} at every angle from 5 to 90 deg" if min(drags) == max(drags)
            else f"C_D {min(drags):.3f}-{max(drags):.3f} from 5 to 90 deg") + f", {c[0][3]:.3f} at 0"
    why = ("MuJoCo's model is a fit for blunt bodies: no leading-edge-vortex lift. " +
           ("Its drag here does not grow with the angle from 5 deg up, where its documented "
            "blunt/slender split of the projected area would make it grow from 0.39 to 0.785: "
            "not understood (the harness or the model)" if flat else
            "Its drag grows with the angle") +
           ("; the lift follows its Kutta term" if kutta else ""))
    return [f"the same plate in MuJoCo {version}'s ellipsoid fluid model (default coefficients, "
            "viscosity 0)",
            f"MuJoCo: C_L {c[37][2]:.3f} at 37 deg" +
            (f" ({k:.3f} sin 2a at every angle)" if kutta else "") + f", {drag}",
            f"quasi-steady C_L {c[37][0]:.3f}, C_D {c[37][1]:.3f} at 37 deg",
            f"MuJoCo's C_L is {c[37][2] / c[37][0] * 100:.0f} % of ours and "
            f"{c[37][2] / cl37 * 100:.0f} % of the Robofly's {cl37:.2f} at 37 deg", why]


def water_row(chord, span, water):
    ca, times, expected, ours, our_error, theirs, their_error = water
    ours_said = ("< 0.01 %" if abs(float(our_error)) < 0.005 else
                 f"{float(our_error):+.2f} %")
    free_fall = abs(float(theirs) + 9.81) < 0.01
    return [f"the same plate released at rest in water (its added mass, b / c = {span / chord:.2f}: "
            f"DNV C_A = {ca}, {times} times the plate)",
            f"momentum theory `(m - rho V) g / (m + C_A rho pi c^2 b / 4)` = {expected} m/s^2 up",
            f"{ours} m/s^2 ({our_error} %); MuJoCo {float(theirs):.2f} m/s^2" +
            (" (free fall: its ellipsoid model's added mass and buoyancy act through "
             "velocity-dependent forces, not at rest)" if free_fall else ""),
            f"flapsim {ours_said}; MuJoCo {float(their_error):+.0f} %" +
            (" (falls where the plate rises)" if float(theirs) < 0 < float(expected) else ""),
            "-"]


def mujoco_wing():
    def said(out):
        version = wing_output(out[WING.key])[0]
        source = re.search(r"^MuJoCo from (.*)$", out[WING.key], re.M)
        return (f"`bash bench/mujoco_wing.sh` (bench/mujoco_wing.cpp against MuJoCo {version}, "
                f"from {source.group(1) if source else 'the build'}; the figures it prints)")
    return Table("mujoco_wing", "doc/validation.md",
                 ["case", "source and number", "flapsim", "error", "where it fails"], [WING],
                 wing_rows, said)


# --- doc/performance.md: where each side's step stops passing the check ----------------------

BOUNDARY = "bench/step_boundary.sh"
# (creature, side, integrator (MuJoCo) or None, settings: MuJoCo's steps or flapsim's
# STEP/PIECES, in s), around each side's fastest setting in the comparison above.
BOUNDARIES = [
    ("flap_unit", "mujoco", "implicit", ["0.004", "0.0045", "0.0046", "0.0047", "0.005"]),
    ("flap_unit", "mujoco", "implicitfast", ["0.002", "0.004"]),
    ("flap_unit", "flapsim", None, ["0.004/0.002", "0.006/0.002", "0.008/0.002", "0.010/0.002",
                                    "0.012/0.0015", "0.012/0.002", "0.012/0.003", "0.014/0.002",
                                    "0.016/0.002"]),
    ("chain_12", "mujoco", "implicitfast", ["0.0013", "0.0014", "0.00145", "0.0015", "0.002"]),
    ("chain_12", "mujoco", "implicit", ["0.0011", "0.0012", "0.002"]),
    ("chain_12", "flapsim", None, ["0.004/0.004", "0.006/0.003", "0.008/0.004", "0.010/0.004",
                                   "0.010/0.005", "0.012/0.004", "0.016/0.004"]),
]


def boundary_run(name, side, integrator, settings):
    argv = ["bash", BOUNDARY, name, side] + ([integrator] if integrator else []) + settings
    return Run(f"{name}, {side}" + (f" {integrator}" if integrator else ""), argv)


def boundary_rows(text):
    """Rows from step_boundary.sh's lines: creature, setting, verdict, error, within 10%."""
    rows = []
    for line in text.split("\n"):
        m = re.match(r"^(mujoco|flapsim) (\S+) (.+?) \| (.+?) \| ([-0-9.]+) %$", line)
        if not m:
            continue
        side, name, setting, verdict, pct = m.groups()
        if side == "mujoco":
            integrator, step = setting.split()
            shown = f"MuJoCo {integrator}, {ms(float(step))}"
        else:
            step, pieces = setting.split("/")
            shown = f"flapsim {ms(float(step))}, {ms(float(pieces))} turn substeps"
        stable = verdict == "stable"
        within = stable and abs(float(pct)) <= 10.0
        rows.append([CREATURES[name], shown, "passes" if stable else verdict.replace("|", "/"),
                     f"{float(pct):+.1f} %", "yes" if within else "**no**"])
    if not rows:
        raise ValueError("step_boundary.sh output: no settings")
    return rows


def step_boundary():
    runs = [boundary_run(*b) for b in BOUNDARIES]

    def rows(out):
        return [row for r in runs for row in boundary_rows(out[r.key])]

    def said(out):
        versions = {m for r in runs for m in
                    re.findall(r"^MuJoCo: MuJoCo ([^,]+),", out[r.key], re.M)}
        return (f"`{BOUNDARY} NAME mujoco INTEGRATOR STEP...` and `{BOUNDARY} NAME flapsim "
                f"STEP/PIECES...` (MuJoCo {', '.join(sorted(versions))} from "
                "FLAPSIM_MUJOCO_INCLUDE and FLAPSIM_MUJOCO_LIB; each setting's 10 s check against "
                "its own simulator at 1/16 ms, as vs_mujoco.sh runs it; the error is the height "
                "change's at 3 s, as a share of the reference's)")
    return Table("step_boundary", "doc/performance.md",
                 ["creature (bodies)", "setting", "the check's verdict",
                  "height error at 3 s (of the reference's change)",
                  "within 10 % of its own change"], runs, rows, said)


TABLES = [mujoco_comparison, step_boundary, mujoco_wing]
