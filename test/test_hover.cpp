// The hover creature (make_creature --layout hover), its hand-designed controller and issue
// 24's target: 50 s within 0.3 m of 3 m after 10 s of settling, upright, at most 100 W/kg of
// positive mechanical power, under 5 cm of vertical oscillation per stroke; also in a 1 m/s
// side wind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "flapsim/flight_check.h"
#include "flapsim/hover_flight.h"
#include "flapsim/make_creature.h"
#include "flapsim/text_file.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::sourcePath;

TEST(HoverCreature, CommittedUrdfIsTheGeneratorsOutput) {
  EXPECT_EQ(readTextFile(sourcePath("urdf/hover_1.urdf"), 1 << 20), makeHoverUrdf("hover"))
      << "regenerate with make_creature --layout hover --output urdf/hover_1.urdf";
}

// Two stroke hinges about the body's vertical axis, mirror images, each with a DC motor (its
// line from the <limit>), a parallel spring and a pitch joint along the span; the membranes
// fly the quasi-steady model, the spars feel no air.
TEST(HoverCreature, WingsStrokeAboutTheVerticalAndPitchAboutTheirSpans) {
  const HoverParams p;
  auto m = parseCreatureModel(makeHoverUrdf("hover", p));
  ASSERT_EQ(m->wing_joints.size(), 2u);
  for (int side = 0; side < 2; ++side) {
    const JointModel& hinge = m->joints[m->findJoint(kHoverWingJoints[side])];
    EXPECT_TRUE(hinge.axis.isApprox(Vec3(0, 0, side == 0 ? 1 : -1)));
    ASSERT_TRUE(hinge.motor.has_value());
    EXPECT_EQ(hinge.motor->stall_torque, p.stall_torque);
    EXPECT_EQ(hinge.motor->no_load_speed, p.no_load_speed);
    EXPECT_EQ(hinge.motor->max_power, p.max_power);
    EXPECT_EQ(hinge.stiffness, p.hinge_stiffness);
    ASSERT_GE(hinge.feather_joint, 0);
    const JointModel& pitch = m->joints[hinge.feather_joint];
    const LinkModel& membrane = m->links[pitch.child_link];
    EXPECT_EQ(membrane.aero.model, "quasi_steady");
    EXPECT_FALSE(m->links[hinge.child_link].aero.enabled);
    const std::optional<Vec3> span = spanAxis(*m, pitch.child_link);
    ASSERT_TRUE(span.has_value());
    EXPECT_NEAR(std::abs(span->y()), 1.0, 1e-12);
  }
  EXPECT_NEAR(m->totalMass(), p.body_mass + 2 * (p.wing_mass + p.spar_mass), 1e-15);
}

// The controller's signs: below its height it beats faster; rolled about +x (left side up) the
// right wing beats wider; nose down (the up axis leaning forward) the strokes move forward
// (negative offset), the lift ahead of the centre of mass pitching the nose up; a wing
// pitches +feather forward and -feather back.
TEST(HoverController, CorrectsHeightRollAndPitchTheRightWay) {
  HoverControllerParams p;
  auto command = [&](const Quat& q, double z) {
    HoverController c(p);
    HoverSensors s;
    s.orientation = q;
    s.position = Vec3(0, 0, z);
    return c.update(s, 0.01);
  };
  const auto level = command(Quat::Identity(), p.altitude);
  // (The first command is the start's: its amplitude start_amplitude of the whole.)
  EXPECT_NEAR(level[0].downstroke_rate / (4 * level[0].amplitude),
              p.trim_frequency / p.start_amplitude, 1e-12);
  EXPECT_EQ(level[0].shape, StrokeShape::kSine);
  EXPECT_EQ(level[0].downstroke_feather, p.feather);
  EXPECT_EQ(level[0].feather, -p.feather);
  const auto low = command(Quat::Identity(), p.altitude - 0.5);
  EXPECT_GT(low[0].downstroke_rate, level[0].downstroke_rate);
  const auto rolled = command(Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())), p.altitude);
  EXPECT_GT(rolled[1].amplitude, rolled[0].amplitude);  // +x roll: left side up
  const auto nose_down = command(Quat(Eigen::AngleAxisd(0.2, Vec3::UnitY())), p.altitude);
  EXPECT_LT(nose_down[0].offset, 0.0);  // strokes forward: lift ahead pitches the nose up
  EXPECT_EQ(nose_down[0].offset, nose_down[1].offset);
  HoverControllerParams bad;
  bad.trim_frequency = -1.0;
  EXPECT_THROW(HoverController{bad}, InputError);
}

// The start: the amplitudes grow linearly from start_amplitude of the whole to the whole over
// start_time of updates at the same stroke rate, and again after reset(); with start_time 0
// the first command has the whole amplitude. Bad start parameters are refused by name.
TEST(HoverController, StartGrowsTheAmplitudeAtTheSameStrokeRate) {
  HoverControllerParams p;
  p.start_time = 0.4;
  p.start_amplitude = 0.5;
  HoverController c(p);
  HoverSensors s;
  s.position = Vec3(0, 0, p.altitude);
  const double whole = p.amplitude;
  for (int k = 0; k <= 50; ++k) {
    const auto out = c.update(s, 0.01);
    const double share = std::min(1.0, 0.5 + 0.5 * (0.01 * k) / 0.4);
    ASSERT_NEAR(out[0].amplitude, share * whole, 1e-12) << k;
    ASSERT_NEAR(out[1].amplitude, share * whole, 1e-12) << k;
    // The height loop's integral grows only from the error (none here): the rate is trim's.
    ASSERT_NEAR(out[0].downstroke_rate, 4.0 * whole * p.trim_frequency, 1e-9) << k;
  }
  c.reset();
  EXPECT_NEAR(c.update(s, 0.01)[0].amplitude, 0.5 * whole, 1e-12);
  p.start_time = 0.0;
  EXPECT_NEAR(HoverController(p).update(s, 0.01)[0].amplitude, whole, 1e-12);
  auto refusal = [](HoverControllerParams bad) { return validateHoverControllerParams(bad); };
  HoverControllerParams bad = p;
  bad.start_time = -0.1;
  EXPECT_EQ(refusal(bad), "start_time must be >= 0");
  bad = p;
  bad.start_amplitude = 0.0;
  EXPECT_EQ(refusal(bad), "start_amplitude must be in (0, 1]");
  bad.start_amplitude = 1.5;
  EXPECT_EQ(refusal(bad), "start_amplitude must be in (0, 1]");
}

// Issue 24's target at 1 ms steps in still air and in a 1 m/s side wind (blowing towards +y),
// from a start tilted 0.1 rad in roll and pitch.
TEST(HoverFlight, HoldsThreeMetresUprightAtAnimalPower) {
  const CreatureModelPtr model = parseCreatureModel(makeHoverUrdf("hover"));
  for (double wind : {0.0, 1.0}) {
    SCOPED_TRACE(wind);
    HoverFlightParams p;
    p.world.air.wind = Vec3(0.0, wind, 0.0);
    p.start_roll = 0.1;
    p.start_pitch = -0.1;
    const HoverFlightResult r = flyHover(model, HoverControllerParams(), p);
    EXPECT_GT(r.min_height, 2.7);
    EXPECT_LT(r.max_height, 3.3);
    EXPECT_GT(r.min_upright, 0.9);  // never more than 26 deg from upright
    EXPECT_LT(r.max_stroke_oscillation, 0.05);
    EXPECT_LT(r.specificPower(), 100.0);
    EXPECT_GT(r.positive_power, r.net_power);  // the motors also brake
    EXPECT_LT(r.drift.norm(), 0.5);            // and it keeps its place
  }
}

// A spin given at the start carries on in vacuum, where nothing acts about the centre of mass
// but the wings' own sweep (rotated through 90 deg of bank within 1 s at 2 rad/s: the largest
// bank, asin(world_up . body_left), reaches about pi / 2), and the air takes it out: there the same
// spin, the roll loop off (max_roll_share 0), banks hover_1 less than 0.3 rad (measured: 0.085
// rad at 2 rad/s). Without the spin it does not bank (but for round-off: 1e-14 rad).
TEST(HoverFlight, AStartSpinCarriesOnInVacuumAndTheAirDampsIt) {
  const CreatureModelPtr model = parseCreatureModel(makeHoverUrdf("hover"));
  HoverControllerParams no_roll;
  no_roll.max_roll_share = 0.0;
  HoverFlightParams p;
  p.duration = 1.0;
  p.settle = 0.0;
  EXPECT_LT(flyHover(model, no_roll, p).largest_bank, 1e-9);  // symmetric to round-off
  p.start_rate = Vec3(2.0, 0.0, 0.0);
  const double in_air = flyHover(model, no_roll, p).largest_bank;
  EXPECT_GT(in_air, 0.02);
  EXPECT_LT(in_air, 0.3);
  p.world.air.density = 0.0;
  // Within 0.01 rad: the wings' sweep also turns it a little about its other axes (measured
  // 1.5647 rad).
  EXPECT_GT(flyHover(model, no_roll, p).largest_bank, M_PI / 2.0 - 0.01);
}

// The parallel springs of the stroke hinges store the wings' kinetic energy at each turn:
// without them the motors brake the wings and drive them again, and the positive power grows.
TEST(HoverFlight, HingeSpringsSaveTheMotorsPower) {
  HoverParams sprung, bare;
  bare.hinge_stiffness = 0.0;
  HoverFlightParams p;
  p.duration = 20.0;
  const HoverFlightResult with =
      flyHover(parseCreatureModel(makeHoverUrdf("hover", sprung)), HoverControllerParams(), p);
  const HoverFlightResult without =
      flyHover(parseCreatureModel(makeHoverUrdf("hover", bare)), HoverControllerParams(), p);
  EXPECT_LT(with.positive_power, 0.8 * without.positive_power);
}

// The figure of merit's parts: momentum theory's sqrt(W^3 / (2 rho A)), and the disk of the
// afc_1 creature's 0.35 m wings over +-1.2 rad: 2 x 1.2 x 0.35^2 = 0.294 m^2.
TEST(FigureOfMerit, IdealPowerAndSweptDisk) {
  EXPECT_DOUBLE_EQ(idealHoverPower(2.0, 1.0, 1.0), 2.0);
  const double area = strokeDiskArea(*test::loadUrdf("afc_1.urdf"), 1.2);
  EXPECT_NEAR(area, 2 * 1.2 * (0.35 * 0.35 + 0.001 * 0.001), 1e-12);
}

// flight_check --hover --real-air: the hover creature's starts are flight_check's real-air
// draws (the push 4 x the whole creature's weight: it is its own unit; the torque 0.5 x weight
// x half-span), each disturbance acts on the flight, and the threads change nothing.
TEST(HoverRealAir, FliesRealAirsDrawsWithEveryDisturbanceActing) {
  const CreatureModelPtr model = parseCreatureModel(makeHoverUrdf("hover"));
  FlightCheckOptions o;
  o.hover = true;
  o.params.real_air = true;
  o.params.starts = 2;
  o.params.duration = 10.5;
  const FlightCheckParams real = realAirParams(o.params, *model);
  const double weight = model->totalMass() * 9.81;
  EXPECT_DOUBLE_EQ(real.gust_force, 4.0 * weight);
  EXPECT_DOUBLE_EQ(real.gust_torque, 0.25 * weight * creatureSpan(*model));
  const std::vector<HoverCheckRun> runs = hoverRealAirCheck(model, o);
  ASSERT_EQ(runs.size(), 2u);
  FlightCheckParams drawn = real;
  drawn.altitude = 3.0;
  const std::vector<EpisodeStart> starts = episodeStarts(flightCheckEpisodes(drawn), model.get());
  for (size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].start.wind, starts[i].wind);
    EXPECT_EQ(runs[i].start.force_link, starts[i].force_link);
    EXPECT_NEAR(runs[i].start.wind.norm(), 1.0, 1e-12);
    EXPECT_GT(runs[i].start.gyro_bias.norm(), 0.0);
  }
  o.params.threads = 2;
  const std::vector<HoverCheckRun> two = hoverRealAirCheck(model, o);
  EXPECT_EQ(two[1].flight.altitude_rms, runs[1].flight.altitude_rms);
  EXPECT_EQ(two[1].flight.drift, runs[1].flight.drift);
  // Each of the gusts, the gyro bias and the altimeter's noise moves the flight.
  HoverFlightParams f;
  f.duration = 10.5;
  f.gusts = flightCheckEpisodes(drawn);
  f.gust_start = starts[0];
  f.gust_start.torque_time = f.gust_start.force_time = 0.5;
  const auto drift = [&](const HoverFlightParams& q) {
    return flyHover(model, hoverCheckController(o), q).drift;
  };
  const Vec3 all = drift(f);
  HoverFlightParams calm = f;
  calm.gusts.reset();
  EXPECT_NE(drift(calm), all);
  HoverFlightParams no_torque = f, no_push = f, no_bias = f, no_altimeter = f;
  no_torque.gusts->gust_torque = 0.0;
  no_push.gusts->gust_force = 0.0;
  no_bias.gust_start.gyro_bias = Vec3::Zero();
  no_altimeter.gusts->altitude_noise = 0.0;
  for (const HoverFlightParams* q : {&no_torque, &no_push, &no_bias, &no_altimeter}) {
    EXPECT_NE(drift(*q), all);
  }
}

}  // namespace
}  // namespace flapsim
