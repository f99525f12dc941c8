// Joint motors (dynamics/motor.h), their mechanical power (World::power) and the parallel
// spring at a driven hinge.
#include <gtest/gtest.h>

#include <cmath>

#include "dynamics/motor.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::flapOnHinge;
using test::kFlapHingeInertia;
using test::vacuum;

MotorSpec dc(double stall, double no_load, double power = 0.0) {
  MotorSpec m;
  m.stall_torque = stall;
  m.no_load_speed = no_load;
  m.max_power = power;
  return m;
}

TEST(MotorModel, FlatBoundsAreTheEffortBothWays) {
  const TorqueBounds b = flatTorqueBounds(2.0);
  EXPECT_EQ(b.positive, 2.0);
  EXPECT_EQ(b.negative, 2.0);
}

// Driving along the velocity follows the line stall (1 - |v| / no_load); braking against it
// has the stall torque; past the no-load speed the motor cannot drive (it does not brake).
TEST(MotorModel, DrivingFollowsTheTorqueSpeedLineBrakingHasTheStallTorque) {
  const MotorSpec m = dc(0.1, 100.0);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 0.0).positive, 0.1);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 0.0).negative, 0.1);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 50.0).positive, 0.05);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 50.0).negative, 0.1);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, -75.0).positive, 0.1);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, -75.0).negative, 0.025);
  EXPECT_EQ(motorTorqueBounds(m, 150.0).positive, 0.0);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 150.0).negative, 0.1);
  // No speed line: the stall torque at any speed.
  EXPECT_DOUBLE_EQ(motorTorqueBounds(dc(0.1, 0.0), 1e4).positive, 0.1);
}

// A power limit caps the driving torque at P / |v| where that is below the line.
TEST(MotorModel, PowerLimitCapsTheDrivingTorque) {
  const MotorSpec m = dc(0.1, 100.0, 2.0);
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 10.0).positive, 0.09);  // the line: 0.09 < 2 / 10
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 40.0).positive, 0.05);  // 2 / 40 < 0.06
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, 40.0).negative, 0.1);   // braking: not capped
  EXPECT_DOUBLE_EQ(motorTorqueBounds(m, -40.0).negative, 0.05);
}

TEST(MotorModel, WorkIsTorqueTimesDisplacementAndPositiveWorkCountsDrivingSteps) {
  EXPECT_DOUBLE_EQ(motorWork(0.002, 0.001, 0.01), 0.02);  // 2 N m over 0.01 rad
  EXPECT_DOUBLE_EQ(motorWork(-0.002, 0.001, 0.01), -0.02);
  JointEnergy e;
  e.add(0.3);
  e.add(-0.5);
  e.add(0.1);
  EXPECT_DOUBLE_EQ(e.work, -0.1);
  EXPECT_DOUBLE_EQ(e.positive_work, 0.4);
}

// The flap on a hinge about z (gravity does no work) with a motor of 0.05 N m stall torque
// and 50 rad/s no-load speed, asked for 100 rad/s.
CreatureModelPtr motorFlap(const std::string& motor) {
  return flapOnHinge("continuous", "0 0 1", R"(<limit effort="0.05" velocity="50"/>)", motor);
}

// Driven towards a speed beyond its no-load speed, a DC motor spins the flap up along
// w0 (1 - exp(-t / tau)), tau = I w0 / stall = 0.134 s, and never past w0; without the
// <motor> the flat limit takes it to the target.
TEST(Motor, SpinsUpAlongItsTorqueSpeedLineToTheNoLoadSpeed) {
  World w(vacuum());
  w.spawn("dc", motorFlap(R"(<motor joint="hinge"/>)"), at(0, 0, 1));
  w.spawn("flat", motorFlap(""), at(1, 0, 1));
  w.setJointVelocityTarget("dc", "hinge", 100.0);
  w.setJointVelocityTarget("flat", "hinge", 100.0);
  const double tau = kFlapHingeInertia * 50.0 / 0.05;
  w.step(static_cast<int>(std::lround(tau / 0.001)));
  const double at_tau = w.state("dc").joint_velocities[0];
  EXPECT_NEAR(at_tau, 50.0 * (1.0 - std::exp(-1.0)), 0.005 * 50.0);
  w.step(2000);
  const double late = w.state("dc").joint_velocities[0];
  EXPECT_LT(late, 50.0);
  EXPECT_GT(late, 49.9);
  EXPECT_NEAR(w.state("flat").joint_velocities[0], 100.0, 1e-9);
}

// The motor's work is the kinetic energy it gives the flap (vacuum, no gravity torque about
// z): spun up by a power-limited motor (1 W), its energy grows at 1 W once the torque would
// exceed 1 W / v.
TEST(Power, MotorWorkIsTheKineticEnergyItGives) {
  WorldParams p = vacuum();
  p.step_size = 0.0005;
  World w(p);
  w.spawn("h", motorFlap(R"(<motor joint="hinge" no_load_speed="0" max_power="0.1"/>)"),
          at(0, 0, 1));
  w.setJointVelocityTarget("h", "hinge", 30.0);
  w.step(200);  // 0.1 s: 0.05 N m up to 2 rad/s (2.7 ms), then 0.1 W
  const double v = w.state("h").joint_velocities[0];
  const double energy = 0.5 * kFlapHingeInertia * v * v;
  const CreaturePower power = w.power("h");
  EXPECT_NEAR(power.time, 0.1, 1e-12);
  EXPECT_NEAR(power.totalWork(), energy, 3e-3 * energy);
  EXPECT_NEAR(power.totalPositiveWork(), energy, 3e-3 * energy);
  EXPECT_NEAR(power.totalPower(), 0.1, 0.002);  // at the power limit
  EXPECT_NEAR(energy, 0.1 * 0.1, 0.05 * 0.01);  // nearly all of the 0.1 s at 0.1 W
  w.reset();
  EXPECT_EQ(w.power("h").time, 0.0);
  EXPECT_EQ(w.power("h").totalWork(), 0.0);
}

// Braking the spinning flap to rest is negative work: the net work comes back to zero while
// the positive work keeps the spin-up's.
TEST(Power, BrakingIsNegativeWork) {
  World w(vacuum());
  w.spawn("h", motorFlap(""), at(0, 0, 1));
  w.setJointVelocityTarget("h", "hinge", 10.0);
  w.step(500);
  const double spun = w.power("h").totalWork();
  EXPECT_NEAR(spun, 0.5 * kFlapHingeInertia * 100.0, 3e-3 * spun);
  w.setJointVelocityTarget("h", "hinge", 0.0);
  w.step(500);
  const CreaturePower p = w.power("h");
  EXPECT_NEAR(w.state("h").joint_velocities[0], 0.0, 1e-12);
  EXPECT_NEAR(p.totalWork(), 0.0, 3e-3 * spun);
  EXPECT_NEAR(p.totalPositiveWork(), spun, 3e-3 * spun);
  EXPECT_EQ(p.work.size(), 1u);
}

// A sine stroke of amplitude A at w = 2 pi f on the bare flap (vacuum) needs the torque
// I q'' of its inertia: mean positive power I A^2 w^3 / (2 pi). A parallel spring of
// k = I w^2 gives it that torque: the motor's positive power falls to a rounding's worth.
TEST(Spring, ParallelSpringAtResonanceCarriesTheStroke) {
  const double f = 5.0, a = 0.5, omega = 2.0 * M_PI * f;
  const double k = kFlapHingeInertia * omega * omega;
  const std::string limit = R"(<limit lower="-1" upper="1" effort="1" velocity="100"/>)";
  WorldParams p = vacuum();
  p.step_size = 0.00025;
  World w(p);
  w.spawn("bare", flapOnHinge("revolute", "0 0 1", limit, R"(<wing joint="hinge"/>)"), at(0, 0, 1));
  w.spawn("sprung",
          flapOnHinge("revolute", "0 0 1", limit,
                      R"(<wing joint="hinge"/><spring joint="hinge" stiffness=")" +
                          std::to_string(k) + R"("/>)"),
          at(1, 0, 1));
  StrokeCommand c;
  c.amplitude = a;
  c.downstroke_rate = c.upstroke_rate = 4.0 * a * f;
  c.shape = StrokeShape::kSine;
  for (const char* name : {"bare", "sprung"}) w.setWingCommands(name, {}, {c});
  w.step(1200);  // 1.5 cycles: from rest to a steady stroke
  const CreaturePower bare0 = w.power("bare"), sprung0 = w.power("sprung");
  w.step(8000);  // 10 cycles
  const double bare = (w.power("bare").totalPositiveWork() - bare0.totalPositiveWork()) / 2.0;
  const double sprung = (w.power("sprung").totalPositiveWork() - sprung0.totalPositiveWork()) / 2.0;
  const double expected = kFlapHingeInertia * a * a * omega * omega * omega / (2.0 * M_PI);
  EXPECT_NEAR(bare, expected, 0.02 * expected);
  EXPECT_LT(sprung, 0.01 * expected);
}

}  // namespace
}  // namespace flapsim
