// Momentum of a free tree and the rigid correction that keeps it true; then the world:
// internal forces neither move the centre of mass nor change the angular momentum of a
// flapping creature, at any step size, and its trajectories converge as the step shrinks.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "doc_figure.h"
#include "dynamics/momentum.h"
#include "fluid/added_mass.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

std::vector<BodyMotion> twoBodies() {
  BodyMotion a, b;
  a.mass = 2.0;
  a.com = Vec3(1, 0, 0);
  a.inertia = Vec3(0.1, 0.2, 0.3).asDiagonal();
  a.velocity = Vec3(0, 1, 0);
  a.angular_velocity = Vec3(0, 0, 2);
  b.mass = 1.0;
  b.com = Vec3(-2, 0, 0);
  b.inertia = Mat3::Identity() * 0.05;
  b.velocity = Vec3(0, 0, 3);
  return {a, b};
}

// Hand sums: com (0,0,0); P = (0,2,3); L = I_a w_a + sum m r x v.
TEST(Momentum, TwoBodiesByHand) {
  const SystemMomentum s = systemMomentum(twoBodies());
  EXPECT_DOUBLE_EQ(s.mass, 3.0);
  EXPECT_LT(s.com.norm(), 1e-15);
  EXPECT_LT((s.linear - Vec3(0, 2, 3)).norm(), 1e-15);
  // 0.3*2 about z; 2*(1,0,0)x(0,1,0) = (0,0,2); 1*(-2,0,0)x(0,0,3) = (0,6,0).
  EXPECT_LT((s.angular - Vec3(0, 6, 2.6)).norm(), 1e-14);
  // About y: 0.2 + 0.05 + 2*1 + 1*4.
  EXPECT_NEAR(s.inertia(1, 1), 6.25, 1e-14);
}

// The correction, applied as a rigid motion, gives exactly the target momentum and centre.
TEST(Momentum, CorrectionReachesTheTarget) {
  std::vector<BodyMotion> bodies = twoBodies();
  const SystemMomentum before = systemMomentum(bodies);
  const Vec3 linear(0.5, -1, 2), angular(1, -2, 0.25), com(0.1, 0.2, -0.3);
  const RigidCorrection c = momentumCorrection(before, linear, angular);
  for (BodyMotion& b : bodies) {
    b.velocity += c.velocity + c.angular_velocity.cross(b.com - before.com);
    b.angular_velocity += c.angular_velocity;
    b.com += com - before.com;
  }
  const SystemMomentum after = systemMomentum(bodies);
  test::printFigure("error",
                    std::max((after.linear - linear).norm(), (after.angular - angular).norm()));
  EXPECT_LT((after.linear - linear).norm(), 1e-13);
  EXPECT_LT((after.angular - angular).norm(), 1e-13);
  EXPECT_LT((after.com - com).norm(), 1e-15);
}

// With a fluid carried along (an added mass along one body's normal), the correction
// reaches the target of bodies and fluid together.
TEST(Momentum, CorrectionReachesTheTargetWithFluid) {
  std::vector<BodyMotion> bodies = twoBodies();
  Vec6 f;
  f << Vec3(0.1, 0, 0).cross(Vec3::UnitZ()), Vec3::UnitZ();  // along z, 0.1 m off the COM
  const SpatialFactor added = factorSpatial(3.0 * f * f.transpose());
  auto measure = [&](const std::vector<BodyMotion>& b) {
    SystemMomentum s = systemMomentum(b);
    Vec6 v;
    v << b[0].angular_velocity, b[0].velocity;
    addFluidMomentum(s, added, b[0].com, v);
    return s;
  };
  bodies[0].velocity.z() = 0.5;  // the body's normal speed at the fluid's point: f . v = 0.5
  const SystemMomentum before = measure(bodies);
  EXPECT_LT((before.linear - before.body_linear - Vec3(0, 0, 3.0 * 0.5)).norm(), 1e-15);
  const Vec3 linear(0.5, -1, 2), angular(1, -2, 0.25);
  const RigidCorrection c = momentumCorrection(before, linear, angular);
  for (BodyMotion& b : bodies) {
    b.velocity += c.velocity + c.angular_velocity.cross(b.com - before.com);
    b.angular_velocity += c.angular_velocity;
  }
  const SystemMomentum after = measure(bodies);
  test::printFigure("error",
                    std::max((after.linear - linear).norm(), (after.angular - angular).norm()));
  EXPECT_LT((after.linear - linear).norm(), 1e-13);
  EXPECT_LT((after.angular - angular).norm(), 1e-13);
}

// The unrolled 6x6 solve (L D L^T without pivoting) against Eigen's LDLT, on symmetric
// positive definite matrices of condition 1 to 1e12: a spatial inertia with a plate's added
// mass, random ones with spread eigenvalues, and a near-singular one. Its backward error is
// rounding's, |a x - b| <= 1e-15 |a| |x| (measured below 7e-17), and it agrees with Eigen's
// solution to the condition number times 1e-15 (measured below 2e-16).
TEST(SpatialSolve, SymmetricSolveMatchesEigensLdlt) {
  std::vector<Mat6> matrices;
  {
    Vec6 f;
    f << Vec3(0.1, -0.05, 0).cross(Vec3(0, 0.6, 0.8)), Vec3(0, 0.6, 0.8);
    matrices.push_back(
        spatialInertia(0.02, Vec3(0.03, -0.01, 0.02), Vec3(2e-6, 5e-6, 6e-6).asDiagonal()) +
        0.3 * f * f.transpose());
  }
  std::srand(7);
  for (double condition : {1.0, 1e3, 1e6, 1e9, 1e12}) {
    // q diag(spread) q^T with q orthogonal (from a random matrix's QR).
    const Eigen::HouseholderQR<Mat6> qr(Mat6::Random());
    const Mat6 q = qr.householderQ();
    Vec6 spread;
    for (int i = 0; i < 6; ++i) spread[i] = std::pow(condition, -i / 5.0);
    matrices.push_back(q * spread.asDiagonal() * q.transpose());
  }
  {
    const Vec6 g = Vec6::Random();
    matrices.push_back(g * g.transpose() + 1e-10 * Mat6::Identity());  // condition ~1e10
  }
  for (size_t m = 0; m < matrices.size(); ++m) {
    const Mat6 a = 0.5 * (matrices[m] + matrices[m].transpose());
    const Eigen::SelfAdjointEigenSolver<Mat6> eigen(a);
    const double condition = eigen.eigenvalues()[5] / eigen.eigenvalues()[0];
    ASSERT_GT(eigen.eigenvalues()[0], 0.0) << m;
    for (int k = 0; k < 4; ++k) {
      const Vec6 b = Vec6::Random();
      const Vec6 x = solveSymmetric(a, b);
      const Vec6 reference = a.ldlt().solve(b);
      EXPECT_LE((a * x - b).norm(), 1e-15 * a.norm() * x.norm()) << m;
      EXPECT_LE((x - reference).norm(), 1e-15 * condition * reference.norm()) << m;
    }
  }
}

// ---- in the world --------------------------------------------------------------------

WorldParams vacuum(double step_size) {
  WorldParams p = test::openSky();
  p.air.enabled = false;
  p.gravity = Vec3::Zero();
  p.step_size = step_size;
  return p;
}

struct VacuumRun {
  double com_drift = 0.0;          // largest distance of the COM from its start
  double angular_change = 0.0;     // largest change of the total angular momentum
  double wing_angular_peak = 0.0;  // largest angular momentum of one wing about the COM
  double linear_momentum = 0.0;    // largest |P|
};

// A flap unit started at rest, tilted, flapping (left and right strokes as given) for
// `seconds` in vacuum without gravity, sampled every step through World::state().
VacuumRun flapInVacuum(double step_size, const StrokeCommand& left, const StrokeCommand& right,
                       double seconds, const std::string& urdf = "flap_unit.urdf") {
  World w(vacuum(step_size));
  auto model = loadUrdf(urdf);
  w.spawn("u", model, at(0, 0, 10, Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()))));
  std::vector<StrokeCommand> strokes;  // every unit: left wing, then right
  for (size_t i = 0; i < model->wing_joints.size(); i += 2) {
    strokes.push_back(left);
    strokes.push_back(right);
  }
  w.setWingCommands("u", {}, strokes);
  auto momentum = [&model](const CreatureState& s) { return test::bodyMotions(*model, s); };
  const std::vector<BodyMotion> first = momentum(w.state("u"));
  const SystemMomentum start = systemMomentum(first);
  VacuumRun run;
  const int steps = static_cast<int>(std::lround(seconds / step_size));
  for (int i = 0; i < steps; ++i) {
    w.step(1);
    const std::vector<BodyMotion> bodies = momentum(w.state("u"));
    const SystemMomentum s = systemMomentum(bodies);
    run.com_drift = std::max(run.com_drift, (s.com - start.com).norm());
    run.angular_change = std::max(run.angular_change, (s.angular - start.angular).norm());
    run.linear_momentum = std::max(run.linear_momentum, s.linear.norm());
    const BodyMotion& wing = bodies[1];
    const Vec3 own =
        wing.inertia * wing.angular_velocity + wing.mass * (wing.com - s.com).cross(wing.velocity);
    run.wing_angular_peak = std::max(run.wing_angular_peak, own.norm());
  }
  return run;
}

// The case (40/10/0.8 on both wings, 3 s) and an asymmetric one whose wings do not
// cancel each other's angular momentum: the centre of mass stays within 1e-12 m (rounding:
// measured 1.8e-15 to 3.6e-15 m at z = 10 m) and the total angular momentum within 1e-12 of
// a wing's peak (measured 1e-14), at 2, 1, 0.5 and 0.25 ms. (Without the correction the
// centre drifts 1.4 m at 1 ms, halving with the step.)
TEST(MomentumInWorld, FlappingInVacuumKeepsCentreAndAngularMomentum) {
  const StrokeCommand sym{40, 10, 0.8};
  const StrokeCommand slow{30, 12, 0.7};
  for (double dt : {0.002, 0.001, 0.0005, 0.00025}) {
    for (bool symmetric : {true, false}) {
      SCOPED_TRACE(std::to_string(dt) + (symmetric ? " symmetric" : " asymmetric"));
      const VacuumRun r = flapInVacuum(dt, sym, symmetric ? sym : slow, 3.0);
      const char* stroke = symmetric ? "symmetric" : "asymmetric";
      test::printFigure(test::figureName("com_drift_%gms_%s", dt * 1000, stroke), r.com_drift);
      test::printFigure(test::figureName("angular_change_%gms_%s", dt * 1000, stroke),
                        r.angular_change);
      test::printFigure(test::figureName("wing_peak_%gms_%s", dt * 1000, stroke),
                        r.wing_angular_peak);
      ASSERT_GT(r.wing_angular_peak, 1e-4);  // kg m^2/s: the wings do move
      EXPECT_LT(r.com_drift, 1e-12);
      EXPECT_LT(r.angular_change, 1e-12 * r.wing_angular_peak);
      EXPECT_LT(r.linear_momentum, 1e-12);
    }
  }
}

// A second creature: the 4-unit chain, whose passive joints between units swing freely
// (and meet their limits, whose impulses are internal too), over 2 s at 1 and 0.25 ms.
TEST(MomentumInWorld, ChainFlappingInVacuumKeepsCentreAndAngularMomentum) {
  for (double dt : {0.001, 0.00025}) {
    SCOPED_TRACE(dt);
    const VacuumRun r = flapInVacuum(dt, {40, 10, 0.8}, {30, 12, 0.7}, 2.0, "afc_4.urdf");
    ASSERT_GT(r.wing_angular_peak, 1e-4);
    EXPECT_LT(r.com_drift, 1e-12);  // measured 3.6e-15 m
    EXPECT_LT(r.angular_change, 1e-12 * r.wing_angular_peak);
    EXPECT_LT(r.linear_momentum, 1e-12);
  }
}

// Heights of a flap unit climbing from rest (open sky, default air) at 1, 2 and 3 s; the
// steps in which a stroke turns in substeps of `turn_substep` (s; default: the world's).
std::vector<double> climbHeights(double step_size, const StrokeCommand& stroke,
                                 std::optional<double> turn_substep = std::nullopt) {
  WorldParams p = test::openSky();
  p.step_size = step_size;
  if (turn_substep) p.turn_substep = *turn_substep;
  World w(p);
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 2));
  w.setWingCommands("u", {}, {stroke, stroke});
  std::vector<double> heights;
  for (int second = 1; second <= 3; ++second) {
    w.step(static_cast<int>(std::lround(1.0 / step_size)));
    heights.push_back(w.rootPose("u").position.z() - 2.0);
  }
  return heights;
}

// The climb converges in the step, at 1, 2 and 3 s, against 0.125 ms. In the default air (the
// added mass's products shed into the wake) the unit climbs 1.11 m in 3 s at 40/10/0.8, 3.06 m
// at 60/10/0.8 and 1.73 m at 50/12/0.6. Measured at most (7 December 2026): 40/10 0.73 %
// (1 ms), 0.46 % (0.5 ms), 1.66 % (2 ms, at 1 s); 60/10 1.14 %, 1.38 %, 1.30 %; 50/12 2.17 %,
// 1.84 %, 3.44 % (at 2 s). With the products omitted (the default until then; finite plates'
// added mass, C_A = 0.704 for the flap unit's 1.59:1 wings) it climbed 0.54 m, 2.16 m and 1.30
// m, within 40/10 1.1 %, 1.4 %, 10.3 %; 60/10 1.1 %, 1.3 %, 0.5 %; 50/12 2.7 %, 2.4 %, 4.2 %.
// With strip theory's added mass (C_A = 1, before issue
// 24) the 1 ms climb was within 0.5 % (60/10, 50/12) and 1.5 mm (40/10, which then nearly
// hovered): the lighter added mass made the step's error at the reversals larger, and 0.5 ms
// is not closer than 1 ms because both take the reversals in the same 0.5 ms turn substeps
// (the next test: the error is first order in the step once the turns are resolved). Before the
// turn substeps and the saturated joints' trapezoid, the flap unit climbed 5.6% (1 ms) and
// 21% (2 ms) less in 3 s, without added mass.
TEST(StepConvergence, FlapUnitClimbAgreesWithTheFineStep) {
  struct Case {
    StrokeCommand stroke;
    double tolerance_1ms, tolerance_05ms, tolerance_2ms;
    bool relative;  // tolerances as fractions of the fine climb, else in metres
  };
  for (const Case& c : {Case{{40, 10, 0.8}, 0.01, 0.006, 0.02, true},
                        Case{{60, 10, 0.8}, 0.015, 0.015, 0.015, true},
                        Case{{50, 12, 0.6}, 0.025, 0.025, 0.04, true}}) {
    const StrokeCommand& stroke = c.stroke;
    const std::vector<double> fine = climbHeights(0.000125, stroke);
    for (size_t i = 0; i < fine.size(); ++i) {
      test::printFigure(test::figureName("height_%g/%g/%g_0.125ms_%zus", stroke.downstroke_rate,
                                         stroke.upstroke_rate, stroke.amplitude, i + 1),
                        fine[i]);
    }
    ASSERT_GT(fine[2], 0.1);  // m: it does climb
    for (double dt : {0.002, 0.001, 0.0005}) {
      const std::vector<double> h = climbHeights(dt, stroke);
      const double tolerance = dt > 0.0015    ? c.tolerance_2ms
                               : dt > 0.00075 ? c.tolerance_1ms
                                              : c.tolerance_05ms;
      for (size_t i = 0; i < h.size(); ++i) {
        SCOPED_TRACE(std::to_string(stroke.downstroke_rate) + " rad/s, step " + std::to_string(dt) +
                     " s, at " + std::to_string(i + 1) + " s");
        const double error = h[i] - fine[i];
        test::printFigure(
            test::figureName("height_%g/%g/%g_%gms_%zus", stroke.downstroke_rate,
                             stroke.upstroke_rate, stroke.amplitude, dt * 1000, i + 1),
            h[i]);
        std::printf(
            "stroke %.0f/%.0f/%.1f step %g s at %zu s: %.6f m (0.125 ms: %.6f m, %+.2f%%)\n",
            stroke.downstroke_rate, stroke.upstroke_rate, stroke.amplitude, dt, i + 1, h[i],
            fine[i], 100.0 * error / fine[i]);
        EXPECT_LT(std::abs(c.relative ? error / fine[i] : error), tolerance);
      }
    }
  }
}

// Why 1 ms and 0.5 ms are about equally far from 0.125 ms above: the steps in which a stroke
// turns are taken in substeps of turn_substep, 0.5 ms by default, so at steps of 0.5 ms and
// more the reversals, where the wings' added mass makes the largest error, are integrated
// alike. With the turns in 0.0625 ms substeps at every step the climb converges at first order
// in the step: each halving of the step from 1 to 0.0625 ms changes the height at 3 s by half
// as much as the one before (measured in the default air, 7 December 2026: ratios 1.95 / 2.05 /
// 2.06 at 40/10/0.8, 2.14 / 2.11 / 2.15 at 60/10/0.8, 1.99 / 2.03 / 2.01 at 50/12/0.6); a
// second-order scheme would give 4, one that does not converge 1. Against the first-order
// extrapolation 2 h(0.0625 ms) - h(0.125 ms) the 1 ms climb at 3 s is then +0.65 %, +0.19 % and
// +0.66 % off (with the products omitted: ratios 2.16 / 2.21 / 2.06, 2.14 / 2.26 / 2.25, 1.97 /
// 2.06 / 2.05, and +1.1 %, +0.1 %, +0.8 %). Turns taken in one piece each side of the turn (no
// substeps: checked on a deliberately broken build) give ratios from -3.1 to 601.
TEST(StepConvergence, ClimbErrorIsFirstOrderInTheStepWithFineTurnSubsteps) {
  for (const StrokeCommand& stroke :
       {StrokeCommand{40, 10, 0.8}, StrokeCommand{60, 10, 0.8}, StrokeCommand{50, 12, 0.6}}) {
    std::vector<double> at3;  // heights at 3 s, steps 1, 0.5, ..., 0.0625 ms
    for (double dt = 0.001; dt > 0.00005; dt /= 2) {
      const std::vector<double> h = climbHeights(dt, stroke, 0.0000625);
      for (size_t i = 0; i < h.size(); ++i) {
        test::printFigure(
            test::figureName("height_%g/%g/%g_%gms_%zus", stroke.downstroke_rate,
                             stroke.upstroke_rate, stroke.amplitude, dt * 1000, i + 1),
            h[i]);
      }
      at3.push_back(h[2]);
    }
    for (size_t k = 0; k + 2 < at3.size(); ++k) {
      const double ratio = (at3[k + 1] - at3[k]) / (at3[k + 2] - at3[k + 1]);
      std::printf("stroke %.0f/%.0f/%.1f, steps %g ms: difference ratio %.3f\n",
                  stroke.downstroke_rate, stroke.upstroke_rate, stroke.amplitude,
                  1000 * 0.001 / std::pow(2.0, static_cast<double>(k)), ratio);
      EXPECT_GT(ratio, 1.8);
      EXPECT_LT(ratio, 2.4);
    }
    const double limit = 2 * at3.back() - at3[at3.size() - 2];
    std::printf("stroke %.0f/%.0f/%.1f: 1 ms %+.3f %% off the extrapolation at 3 s\n",
                stroke.downstroke_rate, stroke.upstroke_rate, stroke.amplitude,
                100 * (at3[0] - limit) / limit);
  }
}

}  // namespace
}  // namespace flapsim
