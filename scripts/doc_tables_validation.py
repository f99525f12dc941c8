"""doc/validation.md's tables of cases checked by gtests: each row's figures are those its test
printed (test/doc_figure.h) at the commit the table was written; the words around them, the
references (analytic or published) and the tests' bounds are the rows' text. A figure said to
be from "before" a fix is history, kept in the row's text (the caption says so)."""
import math

from doc_tables import Run, Table
from doc_tables_gtest import Figures, gtest_run, pct, sci, span

DOC = "doc/validation.md"
HEADER = ["case", "reference", "flapsim", "error", "test"]
BEFORE = ("; figures said to be from before a fix are history, kept in the rows' text")


def said(runs, history):
    return ("the figures the tests of the test column print (test/doc_figure.h), run as "
            + ", ".join(f"`{r.command()}`" for r in runs) + (BEFORE if history else ""))


def gtest_table(name, header, binaries, rows, history=False):
    """A table whose runs are `binaries` ({binary: [Suite.Test...]}) and whose rows are
    rows(Figures); `history`: some rows quote figures from before a fix."""
    runs = [gtest_run(b, tests) for b, tests in binaries.items()]
    return Table(name, DOC, header, runs,
                 lambda out: rows(Figures(out, f"table {name}")), said(runs, history))


def t(name):
    return f"`{name}`"


# --- Dynamics ---------------------------------------------------------------------------------

MOMENTUM = "MomentumInWorld.FlappingInVacuumKeepsCentreAndAngularMomentum"
CLIMB = "StepConvergence.FlapUnitClimbAgreesWithTheFineStep"
FIRST_ORDER = "StepConvergence.ClimbErrorIsFirstOrderInTheStepWithFineTurnSubsteps"
STROKES = ["40/10/0.8", "60/10/0.8", "50/12/0.6"]
LEAN = ["LeanStep.FlappingFlightFollowsFullSteps", "LeanStep.ChainWithAddedMassFollowsFullSteps",
        "LeanStep.FallsBackToFullStepsNearTheGround", "LeanStep.FallsBackToTheSolverNearAJointStop"]
FEATHER = "LeanStep.FeatheringAndImplicitDragFollowFullSteps"


def heights(f, test, stroke, step):
    return [f.one(test, f"height_{stroke}_{step}ms_{s}s") for s in (1, 2, 3)]


def climb_row(f, stroke, first):
    fine = heights(f, CLIMB, stroke, "0.125")
    at = {step: heights(f, CLIMB, stroke, step) for step in ("1", "0.5", "2")}
    error = "; ".join(f"{step} ms " + " / ".join(f"{(h - r) / r * 100:+.2f}" for h, r in
                                                 zip(at[step], fine)) + " %" for step in at)
    if first:
        error += (" (before, history: with strip theory's added mass 1 ms was within 0.14 %; "
                  "without added mass at 2 N m, 40/10/0.8 before the turn substeps, 3 s: -5.6 % "
                  "at 1 ms, -21 % at 2 ms)")
    bounds = {"60/10/0.8": "(1.5 %, 1.5 %, 1 %)", "50/12/0.6": "(3 %, 3 %, 5 %)",
              "40/10/0.8": "(1.5 %, 1.5 %, 11 %)"}[stroke]
    case = ("flap unit climb with the finite plates' added mass (C_A = 0.704; 8 N m motors), "
            f"{stroke}, air, no ground, heights at 1 / 2 / 3 s" if first else f"the same, {stroke}")
    return [case, "the climb at 0.125 ms: " + " / ".join(f"{h:.4f}" for h in fine) + " m",
            "; ".join(f"{step} ms: " + " / ".join(f"{h:.4f}" for h in at[step]) + " m"
                      for step in at), error,
            (t(CLIMB) if first else "same test") + " " + bounds]


def first_order_row(f):
    steps = ["1", "0.5", "0.25", "0.125", "0.0625"]
    ratios, fine_off, default_off, worst_fine = [], [], [], None

    def limit(stroke, second):
        h = {s: f.one(FIRST_ORDER, f"height_{stroke}_{s}ms_{second}s") for s in steps}
        return 2 * h["0.0625"] - h["0.125"], h["1"]

    for stroke in STROKES:
        at3 = [f.one(FIRST_ORDER, f"height_{stroke}_{s}ms_3s") for s in steps]
        ratios.append([(at3[k + 1] - at3[k]) / (at3[k + 2] - at3[k + 1]) for k in range(3)])
        lim, fine1 = limit(stroke, 3)
        fine_off.append((fine1 - lim) / lim)
        default_off.append((heights(f, CLIMB, stroke, "1")[2] - lim) / lim)
        for second in (1, 2, 3):
            lim_s, _ = limit(stroke, second)
            off = (heights(f, CLIMB, stroke, "0.125")[second - 1] - lim_s) / lim_s
            if worst_fine is None or abs(off) > abs(worst_fine[0]):
                worst_fine = (off, stroke, second)
    lim1, fine1 = limit("60/10/0.8", 1)
    lim2, fine2 = limit("50/12/0.6", 2)
    d1 = (heights(f, CLIMB, "60/10/0.8", "1")[0] - lim1) / lim1
    d2 = (heights(f, CLIMB, "50/12/0.6", "1")[1] - lim2) / lim2

    def p(x):
        v = x * 100
        return f"{v:+.{1 if abs(v) >= 0.095 else 2 if abs(v) >= 0.0095 else 3}f} %"

    measured = ", ".join(" / ".join(f"{r:.2f}" for r in rs) + f" ({s.split('/0')[0]})"
                         for rs, s in zip(ratios, STROKES))
    measured = ("ratios " + measured + "; 1 ms against the extrapolation `2 h(0.0625) - "
                "h(0.125)` at 3 s: " + " / ".join(p(x) for x in fine_off) +
                " (default substep: " + " / ".join(p(x) for x in default_off) +
                f"; at 1 s at 60/10 {p(d1)} against {p((fine1 - lim1) / lim1)}, at 2 s at "
                f"50/12 {p(d2)} against {p((fine2 - lim2) / lim2)})")
    error = ("the error is first order in the step (the added mass's implicit update), and at "
             "steps of 0.5 ms and more the default 0.5 ms turn substep integrates the reversals, "
             "where that error is largest, alike: so 1 and 0.5 ms agree with each other and both "
             "miss the 0.125 ms climb, which is itself up to "
             f"{p(worst_fine[0])} off the extrapolation ({worst_fine[1].split('/0')[0]} at "
             f"{worst_fine[2]} s). A finer default substep would bring 1 ms to "
             f"{min(abs(x) for x in fine_off) * 100:.1f}-{max(abs(x) for x in fine_off) * 100:.1f}"
             " % at the cost of more substeps per turn (not changed: it alters every trajectory)")
    return ["why 0.5 ms is no closer to 0.125 ms than 1 ms: the same three climbs with the steps "
            "in which a stroke turns taken in 0.0625 ms substeps (default 0.5 ms) at steps of 1, "
            "0.5, 0.25, 0.125 and 0.0625 ms",
            "first-order convergence: each halving of the step changes the 3 s height by half the "
            "change of the halving before (ratio 2; 4 for a second-order scheme)", measured, error,
            t(FIRST_ORDER) + " (ratios within 1.8-2.4; before, history: turns without substeps "
            "gave -3.1 to 601 and failed it)"]


def dynamics_rows(f):
    sym = ["symmetric", "asymmetric"]
    cases = [(dt, s) for dt in ("2", "1", "0.5", "0.25") for s in sym]
    drift = [f.one(MOMENTUM, f"com_drift_{dt}ms_{s}") for dt, s in cases]
    peaks = [f.one(MOMENTUM, f"wing_peak_{dt}ms_{s}") for dt, s in cases]
    turn = [f.one(MOMENTUM, f"angular_change_{dt}ms_{s}") / p for (dt, s), p in zip(cases, peaks)]
    lean = [v for test in LEAN for v in f.all(test, "largest_difference")]
    feather = f.all(FEATHER, "largest_difference")
    correction = max(f.one("Momentum.CorrectionReachesTheTarget", "error"),
                     f.one("Momentum.CorrectionReachesTheTargetWithFluid", "error"))
    spring = "World.SpringJointSwingsAtItsNaturalPeriod"
    period, expected = f.one(spring, "period"), f.one(spring, "expected")
    rows = [
        ["flap unit flapping 40/10 (left) and 30/12 (right) rad/s in vacuum, no gravity, tilted "
         "start, 3 s", "internal forces: centre of mass fixed, angular momentum constant",
         f"COM drift {span(drift)} m at 2, 1, 0.5 and 0.25 ms (at z = 10 m; before the "
         "correction, history: 1.40 m at 1 ms, 0.70 m at 0.5 ms); angular-momentum change "
         f"{span(turn, lambda x: f'{x:.0e}')} of a wing's peak ({max(peaks):.1e} kg m^2/s)",
         "rounding", t(MOMENTUM) + " (also the symmetric 40/10 stroke)"],
        ["lean steps (no collision detection, islands or solver while no link can reach the "
         "ground; flapsim's own articulated-body pass, which the servo solve takes in when a "
         "servo acts or the fluid has an implicit part) against Bullet's full step: flapping "
         "unit, 3-unit chain with added mass, feathering unit, flap unit under the quasi-steady "
         "model in a side wind (implicit drag on a rolling root), a unit near the ground, a hinge "
         "thrown into its stop", "Bullet's full step from the same state", "the same trajectories",
         f"at most {sci(max(lean))} (SI units); the feathering and quasi-steady cases "
         f"{span(feather)} (300 steps)", "`LeanStep.*` (1e-10; the quasi-steady case 1e-9)"],
        ["flapsim's articulated-body pass (TreeDynamics) on a floating base with revolute, "
         "prismatic and fixed joints, random states and forces",
         "Bullet's computeAccelerationsArticulatedBodyAlgorithmMultiDof", "the same accelerations",
         f"{sci(f.one('LeanStep.TreeDynamicsAcceleratesAsBullet', 'largest_relative_difference'))}"
         " relative", "`LeanStep.TreeDynamicsAcceleratesAsBullet` (1e-10 relative)"],
        ["rigid correction of a tree's momentum, with and without a fluid's added mass",
         "target momentum", "reached", sci(correction), "`Momentum.CorrectionReachesTheTarget*` "
         "(1e-13)"],
    ]
    rows += [climb_row(f, s, i == 0) for i, s in enumerate(["60/10/0.8", "50/12/0.6",
                                                             "40/10/0.8"])]
    rows.append(first_order_row(f))
    rows += [
        ["hinged flap (I = 1.34e-4 kg m^2) on a `<spring>` of 0.01 N m/rad, released 0.1 rad off "
         "its reference, vacuum, 0.1 ms", f"torsion pendulum: period `2 pi sqrt(I / k)` = "
         f"{expected:.4f} s", f"{period:.4f} s (10 periods between upward zero crossings)",
         f"{period / expected - 1:+.1e} relative", t(spring) + " (0.5 %)"],
        ["stroke targets integrated at 2, 1, 0.7, 0.25 ms", "ideal triangle wave (turns on "
         "+-theta0, period 2 theta0 (1/w1 + 1/w2))", "on the wave at every sample",
         sci(f.one("Stroke.TurnsExactlyWithinAStep", "largest_error")) + " rad",
         "`Stroke.TurnsExactlyWithinAStep` (1e-12)"],
        ["servo solve with extra inertias and known impulses on a random 7-link tree",
         "dense joint-space solve (J^T A J, J^T p, KKT for the servos)", "same",
         sci(f.one("JointServo.ExtraInertiaAndImpulsesMatchDenseSolve", "largest_difference")),
         "`JointServo.ExtraInertiaAndImpulsesMatchDenseSolve` (1e-9)"],
    ]
    return rows


def dynamics():
    return gtest_table("validation_dynamics", HEADER, {
        "test_momentum": [MOMENTUM, "Momentum.CorrectionReachesTheTarget*", CLIMB, FIRST_ORDER],
        "test_lean_step": ["LeanStep.*"],
        "test_world": ["World.SpringJointSwingsAtItsNaturalPeriod"],
        "test_stroke": ["Stroke.TurnsExactlyWithinAStep"],
        "test_joint_servo": ["JointServo.ExtraInertiaAndImpulsesMatchDenseSolve"],
    }, dynamics_rows, history=True)


# --- Water ------------------------------------------------------------------------------------

LEVEL = "WaterWorld.LevelPlateStartsAtItsAspectRatiosAddedMassAcceleration"
STIFF = "StiffDrag.LightSheetThrownFaceOnSlowsWithoutReversing"


def water_rows(f):
    plates = {"0.2x0.2": None, "0.1x0.2": None}
    error = 0.0
    for plate in plates:
        got = []
        for model in ("pressure", "quasi_steady"):
            for dt in ("1", "0.25"):
                a = f.one(LEVEL, f"a_{plate}_{model}_{dt}ms")
                e = f.one(LEVEL, f"expected_{plate}_{model}_{dt}ms")
                got.append(a)
                error = max(error, abs(a / e - 1))
        plates[plate] = (e, got)
    sheet = {dt: (f.one(STIFF, f"speed_{dt}ms"), f.one(STIFF, f"expected_{dt}ms"),
                  f.one(STIFF, f"monotonic_{dt}ms")) for dt in ("2", "0.25")}
    mono = all(m == 1 for _, _, m in sheet.values())
    pn = "AddedMass.PlateGetsItAlongItsNormalOnly"
    swim = "WaterWorld.SwimmerStaysBoundedAtHardStrokes"
    sink = "World.DensePlateSinksAtTerminalSpeedInWater"
    cube = "WaterWorld.BottomHeavyCubeRightsItself"
    wrench = "BuoyancyWrench.BottomHeavyCubeIsTurnedBackUpright"
    aligned = "UnionOfBoxes.AlignedOverlapIsCountedOnceExactly"
    turned = "UnionOfBoxes.TurnedOverlapMatchesTheOctagonWithinSamplingError"
    vol, vol_ref = f.one(turned, "volume"), f.one(turned, "expected")
    speed, terminal = f.one(sink, "speed"), f.one(sink, "expected")

    def both(plate):
        e, got = plates[plate]
        return span(got, lambda x: f"{x:.6f}")
    return [
        ["level plates released at rest in water, 10 g, 2 mm thick: 0.2 x 0.2 m (square) and "
         "0.1 x 0.2 m (2:1), pressure and quasi-steady models, 1 and 0.25 ms",
         "`(m - rho V) g / (m + C_A rho pi c^2 b / 4)`, C_A from DNV-RP-C205 table A-2 "
         "(rectangular plates: 0.579 square, 0.757 at 2:1): "
         f"{plates['0.2x0.2'][0]:.6f} and {plates['0.1x0.2'][0]:.6f} m/s^2 up",
         f"{both('0.2x0.2')} and {both('0.1x0.2')} m/s^2 in both models at both steps",
         f"{sci(error)} relative (test allows 2 %; strip theory's C_A = 1 would be 42 % and "
         "24 % slower)", t(LEVEL)],
        ["added-mass coefficient of a rectangular plate", "DNV-RP-C205 (Det Norske Veritas, "
         "2010) appendix A table A-2: b/c = 1, 1.25, 1.5, 1.59, 2, 2.5, 3, 4, 5, 6.25, 8, 10, "
         "inf: C_A = 0.579, 0.642, 0.690, 0.704, 0.757, 0.801, 0.830, 0.871, 0.897, 0.917, "
         "0.934, 0.947, 1; linear in c/b between rows", "the table at its rows",
         sci(f.one("AddedMass.CoefficientFollowsTheDnvTableOfRectangularPlates",
                   "largest_difference")),
         "`AddedMass.CoefficientFollowsTheDnvTableOfRectangularPlates` (1e-12 between rows)"],
        ["plate added mass spread over its cells, tilted plate", "`C_A rho pi c^2 b / 4` along "
         "the normal, 0 in the plane", "same",
         f"{sci(f.one(pn, 'normal_relative_error'))} along the normal, "
         f"{sci(f.one(pn, 'in_plane_relative'))} in the plane (relative)", t(pn) + " (1e-12)"],
        ["1 g sheet, 0.2 x 0.2 m, thrown face-on at 100 m/s, no gravity, 0.2 s, without added "
         "mass (stiff: step x rho Cd A v / m = 5.5 at 2 ms, explicit would reverse it)",
         f"`v0 / (1 + k A v0 t / m)` = {sheet['2'][1]:.6f} m/s",
         f"{sheet['2'][0]:.6f} (2 ms), {sheet['0.25'][0]:.6f} (0.25 ms), "
         + ("monotonic, never reversed" if mono else "NOT monotonic"),
         f"{pct(sheet['2'][0] / sheet['2'][1] - 1, 1)} / {pct(sheet['0.25'][0] / sheet['0.25'][1] - 1, 1)}"
         " (the slow part is explicit, first order)", t(STIFF) + " (5 %, 1 %)"],
        ["linearised drag of a face-on plate at 2 m/s", "d/du of `1/2 rho Cd S u^2` = "
         "`rho Cd S u`; numerical derivative of the pressure model", "same",
         sci(f.one("DragDamping.FaceOnPlateIsTheForceDerivative", "relative_difference")) +
         " relative (finite difference)", "`DragDamping.FaceOnPlateIsTheForceDerivative` (1e-4)"],
        ["swimmer at 40/40 and 30/10 rad/s for 10 s", "finite, root speed below the wing-tip "
         "speed (15 m/s)", f"fastest {f.one(swim, 'fastest_40/40'):.2f} and "
         f"{f.one(swim, 'fastest_30/10'):.2f} m/s (before, history: \\|z\\| > 1 km within "
         "0.01 s)", "-", t(swim)],
        ["swimmer, equal strokes, 10 cycles, weightless", "no net motion",
         f"\\|z\\| = {sci(abs(f.one('Water.EqualStrokesGoNowhereUnequalOnesMove', 'equal_z')))} m",
         "-", "`Water.EqualStrokesGoNowhereUnequalOnesMove` (0.01 m)"],
        ["dense plate sinking flat", "`sqrt(2 (m - rho V) g / (rho Cd A))` = "
         f"{terminal:.4f} m/s", f"{speed:.4f} m/s after 5 s", f"{sci(speed / terminal - 1)} relative",
         t(sink) + " (0.1 %)"],
        ["bottom-heavy neutral cube (COM 2 cm below centre) tilted 30 deg", "buoyancy at the "
         "centroid rights it", f"{f.one(cube, 'tilt_deg_1ms'):.2f} deg (1 ms), "
         f"{f.one(cube, 'tilt_deg_0.5ms'):.2f} deg (0.5 ms) after 10 s (before, history: "
         "30.00 deg)", "-", t(cube) + " (5 deg)"],
        ["same cube tilted 0.1 rad, buoyancy torque", "`-rho V g h sin(theta)` = "
         f"{-1000 * 0.001 * 9.81 * 0.02 * math.sin(0.1):.6e} N m",
         f"{f.one(wrench, 'torque_0.1rad'):.6e} N m", sci(f.one(wrench, "largest_difference")) +
         " N m (four angles)", t(wrench) + " (1e-12)"],
        ["two 0.1 m cubes overlapping by half", "V = 1.5e-3 m^3, centroid x = 0.025 m", "same",
         f"{sci(f.one(aligned, 'volume_error'))} m^3, {sci(f.one(aligned, 'centroid_error'))} m",
         t(aligned) + " (1e-15)"],
        ["cube and the same cube turned 45 deg", f"`(4 - 2 sqrt 2) a^3` = {vol_ref:.6e} m^3",
         f"{vol:.6e} m^3", f"{vol / vol_ref - 1:+.1e} relative", t(turned) + " (1e-4)"],
    ]


def water():
    return gtest_table("validation_water", HEADER, {
        "test_fluid": ["AddedMass.*", STIFF, "DragDamping.FaceOnPlateIsTheForceDerivative",
                       "WaterWorld.*"],
        "test_flight": ["Water.EqualStrokesGoNowhereUnequalOnesMove"],
        "test_world": ["World.DensePlateSinksAtTerminalSpeedInWater"],
        "test_air": ["BuoyancyWrench.BottomHeavyCubeIsTurnedBackUpright",
                     "UnionOfBoxes.AlignedOverlapIsCountedOnceExactly",
                     "UnionOfBoxes.TurnedOverlapMatchesTheOctagonWithinSamplingError"],
    }, water_rows, history=True)


# --- Air --------------------------------------------------------------------------------------

def air_rows(f):
    flush = "BuildSurface.FlushHalfPlatesFeelTheDragOfOneWholePlate"
    span_test = "QuasiSteadySpan.SquareAndNearlySquarePlatesAgreeGivenTheSpan"
    cop = "QuasiSteadyCentreOfPressure.GlidingPlatePitchesNoseUpByWhitneyWood"
    rot = "QuasiSteadyRotationalLift.FollowsSaneDickinsonAndIsOddInPitchRate"
    one, two = f.one(flush, "face_on_one"), f.one(flush, "face_on_two")
    e1, e2, unmasked = (f.one(flush, n) for n in ("edge_on_one", "edge_on_two", "edge_on_unmasked"))
    lo, hi = f.one(span_test, "lowest_ratio"), f.one(span_test, "highest_ratio")
    return [
        ["two flush 0.1 x 0.2 half-plates in one link vs one 0.2 x 0.2 plate, face-on 2 m/s",
         f"`1/2 rho Cd A u^2`: the one plate's {one:.6f} N", f"{two:.6f} N",
         sci(abs(two / one - 1)) + " relative", t(flush)],
        ["the same edge-on", f"one plate's edge: {e1:.5e} N (every face of both halves: "
         f"{unmasked:.5e}, twice)", f"{e2:.5e} N", sci(abs(e2 / e1 - 1)) + " relative", "same"],
        ["quasi-steady, 0.20 x 0.20 vs 0.20 x 0.202 plate, span given", "force ratio = area "
         "ratio 1.01", f"{lo:.4f} to {hi:.4f} in 4 flows (before, history: 0.0043 vs 0.0587 N)",
         f"{max(abs(lo - 1.01), abs(hi - 1.01)) / 1.01 * 100:.2f} % off the area ratio",
         t(span_test) + " (2 %)"],
        ["gliding plate, c = 0.2 m, U = 3 m/s, alpha = 10 deg, centre-of-pressure shift",
         "`d_cp / c = 0.82 \\|a\\| / pi + 0.05`", f"tau_y = {f.one(cop, 'torque_y_10deg'):.6e} "
         "N m (nose up)", sci(f.one(cop, "largest_relative_error")) + " relative (5 angles, both "
         "ways)", t(cop) + " (1e-6)"],
        ["rotational lift, alpha = 10 deg, U = 2 m/s, pitch axis at mid-chord, q = 1 rad/s",
         "`pi (0.75 - x0) rho U c^2 b q`; odd in q",
         f"{f.one(rot, 'lift_mid_chord_q1'):.6e} N",
         sci(f.one(rot, "largest_relative_error")) + " relative (both axes, q = +-1, +-2)",
         t(rot) + " (1e-9)"],
    ]


def air():
    return gtest_table("validation_air", HEADER, {
        "test_air": ["BuildSurface.FlushHalfPlatesFeelTheDragOfOneWholePlate", "QuasiSteady*"],
    }, air_rows, history=True)


# --- Cylinders and spheres --------------------------------------------------------------------

def round_rows(f):
    areas = "RoundSurface.AreasSumToTheTrueSurfaceWithOutwardNormals"
    sphere = "RoundSurface.SphereDragIsTheLawsIntegralWithinTheFacetError"
    can = "RoundSurface.CylinderDragIsTheLawsIntegralWithinTheFacetError"
    rest = "RoundWorld.SphereAndCylindersRestOnTheGroundOnTheirLowestPoints"
    fall = "RoundWorld.FallingSphereReachesTheTerminalSpeedOfTheLaw"
    water = "RoundWorld.SphereInWaterIsBuoyedByRhoVg"
    dirs = ["down", "x", "oblique"]
    coarse = [f.one(sphere, "coarse_" + d) for d in dirs]
    fine = [f.one(sphere, "fine_" + d) for d in dirs]
    speed, terminal = f.one(fall, "speed"), f.one(fall, "expected")
    return [
        ["sphere, area of the cells", "`4 pi r^2`", "same", sci(f.one(areas, "sphere_area_error"))
         + " m^2", t(areas) + " (1e-14)"],
        ["cylinder, area of the cells", "`2 pi r L + 2 pi r^2`", "same",
         sci(f.one(areas, "cylinder_area_error")) + " m^2", "same"],
        ["sphere r = 0.1 at 3 m/s, straight down / along x / oblique",
         "`1/2 rho Cd v^2 2/3 pi r^2`", " / ".join(pct(x) for x in coarse) + " (48 x 24 cells: "
         + " / ".join(pct(x) for x in fine) + ")", "the facets' (second order in their size)",
         t(sphere) + " (1.4 %)"],
        ["cylinder r = 0.05, L = 0.4 at 3 m/s, cross-flow (two headings) / end-on",
         "`1/2 rho Cd v^2 pi/2 r L` / `1/2 rho Cd v^2 pi r^2`", "same",
         sci(f.one(can, "largest_relative_error")) + " relative", t(can) + " (1e-4)"],
        ["sphere r = 0.1, 50 g, falling in air", f"`sqrt(2 m g / (rho 2/3 Cd pi r^2))` = "
         f"{terminal:.3f} m/s", f"{speed:.3f} m/s", f"{pct(speed / terminal - 1)} (the facets' "
         f"{pct(coarse[0])})", t(fall) + " (0.7 %)"],
        ["sphere r = 0.05, 0.2 kg, at rest in water", "first step at `g (rho V / m - 1)`", "same",
         sci(f.one(water, "error")) + " m/s", t(water) + " (1e-9 m/s)"],
        ["sphere r = 0.05, a cylinder (r = 0.05, L = 0.3) on its side and on its cap, dropped on "
         "the ground", "centre at z = r = 0.05, 0.05, L/2 = 0.15",
         f"same, at rest (at most {sci(f.one(rest, 'largest_speed'))} m/s)",
         sci(f.one(rest, "largest_height_error")) + " m", t(rest) + " (1e-3)"],
    ]


def round_shapes():
    return gtest_table("validation_round", ["case", "reference (the law's integral)",
                                            "flapsim, default facets", "error", "test"],
                       {"test_round_shapes": ["Round*"]}, round_rows)


# --- Turbulence -------------------------------------------------------------------------------

SPECTRA = Run("turbulence_spectra", ["bash", "-c", "bin/turbulence_spectra light 2>&1"])


def bench_variances(text):
    """{axis: (variance, model sigma^2)} of bench/turbulence_spectra.cpp's report."""
    import re
    found = {m.group(1): (float(m.group(2)), float(m.group(3))) for m in re.finditer(
        r"^([uvw]): variance ([0-9.]+) \(m/s\)\^2, model sigma\^2 ([0-9.]+)", text, re.M)}
    if sorted(found) != ["u", "v", "w"]:
        raise ValueError("turbulence_spectra output: no variance of every component")
    return found


def turbulence():
    spectra = "Turbulence.SpectraAndVariancesAreTheModels"
    drift = "Turbulence.InAFrozenFieldACreatureDriftingWithTheWindFeelsNoChange"
    living = "Turbulence.AirThatStaysInTheAirMassDecorrelatesOverTheLagrangianTime"
    felt = "Turbulence.TheFeltSpectrumIsTheTransformOfTheCorrelationInSpaceAndTime"
    gust = "Turbulence.AFreePlateIsCarriedByTheGust"
    test = gtest_run("test_turbulence", [spectra, drift, living, felt, gust])

    def rows(out):
        f = Figures({test.key: out[test.key]}, "table validation_turbulence")
        v = bench_variances(out[SPECTRA.key])
        axes = "uvw"
        err = [f.one(spectra, "variance_error_" + a) for a in axes]
        return [
            ["variance u, v, w ((m/s)^2; sigma " + ", ".join(f"{math.sqrt(v[a][1]):.2f}"
                                                             for a in axes) + " m/s)",
             ", ".join(f"{v[a][1]:.3f}" for a in axes),
             ", ".join(f"{v[a][0]:.3f}" for a in axes) + " (" +
             ", ".join(f"{(v[a][0] / v[a][1] - 1) * 100:+.1f}" for a in axes) + " %)",
             f"`{spectra}`: over 13 km of path, u, v within 10 %, w within 1.5 % (measured "
             f"{max(err[0], err[1]) * 100:.1f} %, {err[2] * 100:.1f} %)"],
            ["spectrum per octave, 1 / L to 8 rad/m, 2 seeds", "Dryden's `Phi_u`, `Phi_v`, "
             "`Phi_w`", f"within {f.one(spectra, 'lowest_three_octaves_error') * 100:.1f} % in "
             "the three lowest octaves (a few frequencies each), "
             f"{f.one(spectra, 'higher_octaves_error') * 100:.1f} % above",
             "same test, bounds 12 % and 4 %"],
            ["air carried by the wind, felt every 0.1 s for 20,000 s: variance u, v, w",
             "sigma^2", ", ".join(f"{(f.one(living, 'variance_ratio_' + a) - 1) * 100:+.1f} %"
                                  for a in axes), f"`{living}`: within 8 %"],
            ["the same air's w: correlation at T_L / 2, T_L, 2 T_L (T_L = 0.5 h / sigma_w, "
             "Hanna 1982: 3.24 s)",
             ", ".join(f"{f.one(living, 'model_at_' + t + '_s'):.3f}" for t in ("1.6", "3.2",
                                                                                 "6.5")),
             ", ".join(f"{f.one(living, 'correlation_at_' + t + '_s'):.3f}"
                       for t in ("1.6", "3.2", "6.5")), "same test, within 0.05"],
            ["the felt spectrum (space through time) at rest in a 1 m/s wind, integrated",
             "sigma^2", ", ".join(f"{(f.one(felt, 'felt_variance_ratio_' + a) - 1) * 100:+.2f} %"
                                  for a in axes), f"`{felt}`: within 0.5 %"],
            ["a creature carried by the wind in a frozen field (Taylor's hypothesis, "
             "`air/turbulence/frozen`)", "feels no change",
             f"changes {sci(f.one(drift, 'drifting_change'))} m/s over 20 s (at rest: "
             f"{f.one(drift, 'resting_change'):.2f} m/s)", f"`{drift}` (1e-9 m/s)"],
            ["a 10 g plate in a 2 m/s 1-cosine gust along its normal, 5 s after it holds",
             "relative speed < (m + m_a) / (1/2 rho Cd A t) = "
             f"{f.one(gust, 'bound'):.3f} m/s, never faster than the air",
             f"{f.one(gust, 'relative_speed'):.3f} m/s; fastest {f.one(gust, 'fastest'):.3f} "
             "m/s", f"`{gust}`"],
        ]
    return Table("validation_turbulence", DOC, ["quantity", "model", "measured", "test"],
                 [SPECTRA, test], rows,
                 "`bin/turbulence_spectra light` (the variances it reports of 2^18 samples 0.05 s "
                 "apart, 3.6 h of sim time; its spectra are the plot's) and the figures the tests "
                 f"of the test column print, `{test.command()}`")


# --- Observers and energy ---------------------------------------------------------------------

GALILEAN = "GalileanInvariance.MovingWithAUniformFluidFliesAsAtRestShiftedByWt"
YAW = "RotationInvariance.AStartYawedAboutTheVerticalFliesTheYawedPath"
MIRROR = "MirrorSymmetry.MirroredStartAndCommandsFlyTheMirroredPath"
FLOW = "AcceleratingFlow.APlatePushedByTheWatersAccelerationGainsRhoVPlusAddedMassTimesU"
# The gtest's own lines of rostest's output (the rest names the machine's log files).
DRIVE = Run("drive", ["bash", "-c", "source build/devel/setup.bash && rostest --text flapsim "
                      "drive.test 2>&1 | grep -E '^\\[(figure|=|-| +(RUN|OK|PASSED|FAILED))'"])


def gaps(f, test):
    """(gap positions, gap angles, floor positions, floor angles, largest gap / floor)."""
    out = [list(f.matching(test, prefix).values()) for prefix in
           ("gap_position_", "gap_angle_", "floor_position_", "floor_angle_")]
    if not out[0] or len({len(x) for x in out}) != 1:
        raise ValueError(f"table validation_observers: {test} printed no gaps for every case")
    pos = f.matching(test, "gap_position_")
    floor = f.matching(test, "floor_position_")
    worst = max(pos[c] / floor[c] for c in pos)
    return out + [worst]


def observers():
    core = gtest_run("test_invariance", [GALILEAN, YAW, MIRROR, FLOW])

    def rows(out):
        f = Figures({core.key: out[core.key]}, "table validation_observers")
        drive = Figures({DRIVE.key: out[DRIVE.key]}, "table validation_observers (rostest)")
        g = gaps(f, GALILEAN)
        floors = [x for test in (GALILEAN, YAW, MIRROR) for x in gaps(f, test)[2]]

        def under(test):
            pos, ang, _, _, worst = gaps(f, test)
            return (f"at most {sci(max(pos))} m, {sci(max(ang))} rad: under the floor (the largest "
                    f"gap {worst:.0e} of its floor)")
        dv, dexp = (drive.one("Drive.ReconfiguredWindActsWithinOneStep", n)
                    for n in ("speed", "expected"))
        return [
            ["moving with a uniform wind or current (or moving in vacuum) vs at rest in still "
             "fluid", "the same flight shifted by W t",
             f"{span(g[0], lambda x: f'{x:.0e}')} m, {span(g[1], lambda x: f'{x:.0e}')} rad "
             f"(floors {span(floors, lambda x: f'{x:.0e}')} m)",
             "vacuum 1.4 cm / 0.41 rad (flap unit), air 0.12 to 0.35 m, water 8 mm to 8 cm, up to "
             "0.58 rad", t(GALILEAN)],
            ["the start yawed 0.7 rad about the vertical, the wind yawed alike", "the yawed path",
             under(YAW), "held", t(YAW)],
            ["the start mirrored (y -> -y), left and right strokes swapped, the wind mirrored",
             "the mirrored path", under(MIRROR), "held", t(MIRROR)],
            ["a 10 g plate (0.2 x 0.2 x 0.002 m) at rest in water, gravity and drag off, the "
             "water's velocity stepped by U between two steps", "Morison's inertia force (rho V "
             "+ m_a) dU/dt: along the normal `(rho V + m_a) U / (m + m_a)` = 1.0192 U (m_a = "
             "0.579 rho pi c^2 b / 4 = 3.638 kg), in the plane `rho V U / m` = 8 U",
             f"{f.one(FLOW, 'normal_per_u'):.4f} U and {f.one(FLOW, 'in_plane_per_u'):.4f} U "
             f"(error {sci(max(f.one(FLOW, 'normal_error'), f.one(FLOW, 'in_plane_error')))} "
             "m/s)", "-", t(FLOW) + " (1e-15 m/s)"],
            ["the same through the node: a hanging plate in air, the wind reconfigured from 0 to "
             "5 m/s", "`(F dt + rho V U) / m` (drag and the Froude-Krylov push): "
             f"{dexp:.6f} m/s", f"{dv:.6f} m/s (error {sci(abs(dv - dexp))} m/s)",
             "drag only: the push was missing", "`Drive.ReconfiguredWindActsWithinOneStep` "
             "(rostest, 1e-9)"],
        ]
    return Table("validation_observers", DOC, ["case", "reference", "flapsim",
                                               "before the fix (history)", "test"],
                 [core, DRIVE], rows,
                 f"the figures the tests of the test column print, `{core.command()}` and "
                 f"`{DRIVE.command()}`; the before column is history (issue 39's figures before "
                 "its fix), kept as text")


TABLES = [dynamics, water, air, round_shapes, turbulence, observers]
