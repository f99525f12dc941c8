// The paper's experiments on whole creatures: gliding plates (Fig. 2, eq. 7), the
// bamboo-copter (Fig. 3-4) and the flapping unit (Fig. 5, eq. 19).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "doc_figure.h"
#include "flapsim/make_creature.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;
using test::openSky;

// A plate pitched by phi about +y has its lower face's normal tilted towards -x, so eq. 7's
// moving force F_d cos(phi) sin(phi) pushes it towards +x while it falls.
double glideDrift(double deg, double seconds) {
  World w(openSky());
  const double phi = deg * M_PI / 180.0;
  w.spawn("plate", loadUrdf("plate.urdf"),
          at(0, 0, 50, Quat(Eigen::AngleAxisd(phi, Vec3::UnitY()))));
  w.step(static_cast<int>(seconds / w.params().step_size));
  const Pose p = w.rootPose("plate");
  EXPECT_NEAR(p.position.y(), 0.0, 1e-9) << deg;
  EXPECT_LT(p.position.z(), 50.0) << deg;
  return p.position.x();
}

// Eq. 7's moving force grows with cos(phi) sin(phi) = sin(2 phi) / 2 up to 45 deg: so does
// the drift over 0.4 s of fall; a mirror tilt drifts the mirror way.
TEST(Glide, MoreTiltDriftsFurtherUpTo45DegAndMirrorTiltTheOtherWay) {
  double last = 0.0;
  for (double deg : {10.0, 20.0, 30.0, 45.0}) {
    const double x = glideDrift(deg, 0.4);
    EXPECT_GT(x, last) << deg << " deg: more tilt (up to 45) drifts further";
    last = x;
  }
  EXPECT_LT(glideDrift(-20.0, 0.4), 0.0);  // mirror tilt, mirror drift
}

// Eq. 6 and 7 on the plate falling at u (no spin), tilted phi: its lower face (area A)
// feels F_d cos(phi) along its normal, F_d = 1/2 rho Cd A u^2, so the horizontal moving force
// F_d cos(phi) sin(phi) (eq. 7) and the lift F_d cos^2(phi). The plate's 2 mm rim (area a)
// that advances adds -1/2 rho Cd a u^2 sin(phi) cos(phi) and +... sin^2(phi): 1% of the face.
// Upward, buoyancy rho V g adds to the lift.
TEST(Glide, TiltedPlateFeelsEquation7sMovingForce) {
  const double rho = AirParams().density, cd = AirParams().drag_coefficient;
  const double face = 0.2 * 0.2, rim = 0.2 * 0.002, u = 2.0;
  for (double deg : {10.0, 20.0, 30.0, 45.0, 60.0}) {
    const double phi = deg * M_PI / 180.0;
    World w(openSky());
    Twist falling;
    falling.linear = Vec3(0, 0, -u);
    w.spawn("plate", loadUrdf("plate.urdf"),
            at(0, 0, 50, Quat(Eigen::AngleAxisd(phi, Vec3::UnitY()))), falling);
    w.step(1);  // the wrench of the first step, from the spawned state
    const Vec3 f = w.aeroForces("plate").at(0).wrench.force;
    const double q = 0.5 * rho * cd * u * u;
    const double moving = q * std::cos(phi) * std::sin(phi);  // eq. 7, per unit area
    EXPECT_NEAR(f.x(), moving * (face - rim), 1e-12) << deg;
    const double lift =
        q * (face * std::cos(phi) * std::cos(phi) + rim * std::sin(phi) * std::sin(phi));
    const double buoyancy = rho * face * 0.002 * 9.81;
    EXPECT_NEAR(f.z(), lift + buoyancy, 1e-12) << deg;
    EXPECT_NEAR(f.y(), 0.0, 1e-15) << deg;
  }
}

TEST(BambooCopter, RisesSlowsThenFallsSpinningTheOtherWay) {
  World w(openSky());
  Twist spin;
  spin.angular = Vec3(0, 0, 150.0);
  w.spawn("bc", loadUrdf("bamboo_copter.urdf"), at(0, 0, 10), spin);
  double max_z = 10.0, min_wz = 150.0;
  double wz_at_top = 0.0;
  for (int i = 0; i < 300; ++i) {
    w.step(10);
    const double z = w.rootPose("bc").position.z();
    const double wz = w.rootTwist("bc").angular.z();
    if (z > max_z) {
      max_z = z;
      wz_at_top = wz;
    }
    min_wz = std::min(min_wz, wz);
  }
  EXPECT_GT(max_z, 10.3);             // it rose
  EXPECT_LT(wz_at_top, 0.5 * 150.0);  // its spin decayed on the way up
  EXPECT_GT(wz_at_top, 0.0);
  EXPECT_LT(min_wz, -20.0);  // and reversed while falling
  EXPECT_LT(w.rootPose("bc").position.z(), max_z - 1.0);
  EXPECT_GT((w.rootPose("bc").orientation * Vec3::UnitZ()).z(), 0.99);  // stayed upright
}

double climb(double w1, double w2, double amplitude, double seconds) {
  World w(openSky());
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 20));
  w.setWingCommands("u", {}, {StrokeCommand{w1, w2, amplitude}, StrokeCommand{w1, w2, amplitude}});
  w.step(static_cast<int>(seconds / w.params().step_size));
  EXPECT_GT((w.rootPose("u").orientation * Vec3::UnitZ()).z(), 0.99) << w1 << "/" << w2;
  return w.rootPose("u").position.z() - 20.0;
}

// Over 3 s: a symmetric stroke from a level start keeps the unit level only as long as
// left and right stay mirror images; the unit is unstable in roll (the paper's reason for
// a controller), and rounding-level differences between the wings grow ~10x per second
// until it rolls over after 5-6 s.
TEST(FlapUnit, ClimbsOnlyWhenTheDownstrokeIsFaster) {
  EXPECT_LT(climb(10, 10, 0.8, 3), -1.0);
  EXPECT_LT(climb(10, 20, 0.8, 3), -1.0);
  // With the plates' added mass, 30/10 sinks (-0.9 m) and 40/10 just climbs (+0.12 m).
  double last = 0.0;
  for (double w1 : {40.0, 50.0, 60.0}) {  // w1^2 - w2^2 = 1500, 2400, 3500
    const double h = climb(w1, 10, 0.8, 3);
    EXPECT_GT(h, last) << "w1 = " << w1;
    last = h;
  }
}

// Eq. 17-19: with the body held still (anchored to "world"), the left side of eq. 17,
// the vertical air force integrated over the wing angle, int F_L d(theta) per stroke cycle,
// is proportional to (w1^2 - w2^2) sin(theta0).
// Weightless, and the unit's body held still by a "world" root link.
WorldParams weightless() {
  WorldParams p = openSky();
  p.gravity = Vec3::Zero();
  return p;
}

void spawnAnchored(World& w, const std::string& urdf) {
  w.spawn("u", parseCreatureModel(test::anchoredUrdf(urdf, "unit0_body")), at(0, 0, 0));
}

double liftWorkPerCycle(double w1, double w2, double amplitude) {
  const WorldParams p = weightless();
  World w(p);
  spawnAnchored(w, makeCreatureUrdf(1, "anchored"));
  w.setWingCommands("u", {}, {StrokeCommand{w1, w2, amplitude}, StrokeCommand{w1, w2, amplitude}});
  const int left = w.model("u")->findJoint("unit0_wing_left_joint");
  // Integrate over whole cycles: from one top reversal (velocity turns from up to down) to
  // the 20th after it; the first cycle is left out.
  const int cycles = 20;
  int tops = 0;
  double work = 0.0, last_velocity = 0.0;
  while (tops <= cycles + 1) {
    w.step(1);
    const double velocity = w.state("u").joint_velocities[left];
    if (last_velocity > 0.0 && velocity <= 0.0) ++tops;
    last_velocity = velocity;
    if (tops >= 2 && tops <= cycles + 1) {
      double fz = 0.0;
      for (const LinkAero& a : w.aeroForces("u")) fz += a.wrench.force.z();
      work += fz * std::abs(velocity) * p.step_size;
    }
  }
  EXPECT_EQ(w.rootPose("u").position, Vec3::Zero());  // anchored indeed
  return work / cycles;
}

TEST(FlapUnit, Equation19SignAndProportionality) {
  EXPECT_GT(liftWorkPerCycle(30, 10, 0.8), 0.0);
  EXPECT_LT(liftWorkPerCycle(10, 30, 0.8), 0.0);
  EXPECT_NEAR(liftWorkPerCycle(20, 20, 0.8), 0.0, 1e-3 * liftWorkPerCycle(30, 10, 0.8));
  struct Setting {
    double w1, w2, amplitude;
  };
  std::vector<double> ratio;
  double last = 0.0;
  for (const Setting& s : {Setting{20, 10, 0.8}, Setting{30, 10, 0.8}, Setting{40, 10, 0.8}}) {
    const double work = liftWorkPerCycle(s.w1, s.w2, s.amplitude);
    EXPECT_GT(work, last) << "grows with w1^2 - w2^2, w1 = " << s.w1;
    last = work;
    ratio.push_back(work / ((s.w1 * s.w1 - s.w2 * s.w2) * std::sin(s.amplitude)));
  }
  last = 0.0;
  for (double amplitude : {0.3, 0.5, 0.8, 1.1}) {
    const double work = liftWorkPerCycle(30, 10, amplitude);
    EXPECT_GT(work, last) << "grows with theta0 = " << amplitude;
    last = work;
    ratio.push_back(work / (800.0 * std::sin(amplitude)));
  }
  // One constant K M r^4 / I^2 for every setting (eq. 19), up to the stroke reversals.
  for (double r : ratio) EXPECT_NEAR(r / ratio[0], 1.0, 0.1);
}

// Water (paper sec. VI): the swimmer (a flap unit as dense as water: 0.452 kg, 452 cm^3), with
// gravity and buoyancy off to isolate the stroke. Its wings carry ~13 kg of added mass each
// against a 0.3 kg body, so the body swings about wings that hardly move: over whole stroke
// cycles equal strokes leave it where it was, unequal ones move it (without the added mass
// it moved up when the downstroke was faster; with it, it drifts down a little).
double swim(double w1, double w2, int cycles) {
  WorldParams p = weightless();
  p.air = waterParams();
  p.air.buoyancy = false;
  World w(p);
  w.spawn("s", loadUrdf("swimmer.urdf"), at(0, 0, 0));
  w.setWingCommands("s", {}, {StrokeCommand{w1, w2, 0.8}, StrokeCommand{w1, w2, 0.8}});
  const double period = 2 * 0.8 * (1 / w1 + 1 / w2);
  w.step(static_cast<int>(std::round(cycles * period / p.step_size)));
  EXPECT_GT((w.rootPose("s").orientation * Vec3::UnitZ()).z(), 0.999);
  return w.rootPose("s").position.z();
}

TEST(Water, EqualStrokesGoNowhereUnequalOnesMove) {
  const double equal = swim(1, 1, 10), twice = swim(2, 1, 10), thrice = swim(3, 1, 10);
  test::printFigure("equal_z", equal);
  EXPECT_LT(std::abs(equal), 0.01);
  EXPECT_GT(std::abs(twice), 0.03);
  EXPECT_GT(std::abs(thrice), std::abs(twice));
}

// Feathering (paper sec. VI): pitching the wings edge-on for the upstroke loses less lift
// on the way up, so the anchored unit's net vertical air impulse (4 s at 30/10 rad/s, the
// air's wrench: the pressure and, where the plates shed them, the added mass's velocity
// products) grows with the angle. Measured, at 0, 0.4, 0.8, 1.0, 1.2 and 1.4 rad: in the
// default air (products shed) 2.304, 2.388, 2.436, 2.424, 2.411, 2.384 N s, a rise of 6 % to
// 0.8 rad and a slow fall beyond; with the products omitted 2.271, 2.483, 2.893, 3.066, 3.189,
// 3.243 N s, 40 % by 1.2 rad.
double anchoredImpulse(double feather,
                       AddedMassProducts products = AirParams().added_mass_products) {
  FlapUnitParams params;
  params.feathering = true;
  WorldParams p = weightless();
  p.air.added_mass_products = products;
  World w(p);
  spawnAnchored(w, makeCreatureUrdf(1, "feather", params));
  const StrokeCommand c{30, 10, 0.8, feather};
  w.setWingCommands("u", {}, {c, c});
  const int pitch = w.model("u")->findJoint("unit0_wing_left_pitch");
  double impulse = 0.0, max_pitch = 0.0;
  for (int i = 0; i < 4000; ++i) {
    w.step(1);
    for (const LinkAero& a : w.aeroForces("u")) impulse += a.wrench.force.z() * p.step_size;
    max_pitch = std::max(max_pitch, w.state("u").joint_positions[pitch]);
  }
  EXPECT_NEAR(max_pitch, feather, 0.01 + 1e-3 * feather);  // the servo reaches the angle
  return impulse;
}

TEST(Feathering, RaisesNetLiftSixPercentTo08RadAndFortyWithTheProductsOmitted) {
  const double level = anchoredImpulse(0.0);
  EXPECT_GT(level, 0.0);
  const double at_04 = anchoredImpulse(0.4), at_08 = anchoredImpulse(0.8);
  EXPECT_GT(at_04, level);
  EXPECT_GT(at_08, at_04);
  EXPECT_GT(at_08, 1.05 * level);
  EXPECT_LT(at_08, 1.07 * level);
  EXPECT_LT(anchoredImpulse(1.2), at_08);
  const AddedMassProducts omitted = AddedMassProducts::kOmitted;
  double last = anchoredImpulse(0.0, omitted);
  const double omitted_level = last;
  for (double feather : {0.4, 0.8, 1.2}) {
    const double impulse = anchoredImpulse(feather, omitted);
    EXPECT_GT(impulse, last) << "feather " << feather;
    last = impulse;
  }
  EXPECT_GT(last, 1.3 * omitted_level);
}

// Dihedral: the afc unit, weightless, stroking evenly about a raised or lowered mean angle in
// a 1 m/s wind from its right (air moving towards +y). The side wind pushes a raised
// windward wing up and the leeward one down, so raised strokes bank the unit away from the
// wind (left wing low: bank < 0); lowered strokes are an anhedral and bank it into the wind;
// a mirrored wind mirrors the bank. The bank: asin of the body's left axis' height (after 1 s:
// -0.19 rad raised by 0.4 rad, 0.36 level, 0.38 lowered by 0.4 rad).
double sideWindBank(double offset, double wind_y) {
  WorldParams p = weightless();
  p.air.wind = Vec3(0.0, wind_y, 0.0);
  World w(p);
  w.spawn("u", loadUrdf("afc_1.urdf"), at(0, 0, 0));
  const StrokeCommand stroke{33, 10, 0.9, 0.0, 0.0, offset};
  w.setWingCommands("u", {}, {stroke, stroke});
  w.step(static_cast<int>(1.0 / p.step_size));
  return std::asin((w.rootPose("u").orientation * Vec3::UnitY()).z());
}

TEST(SideWind, RaisedStrokesBankAwayFromItLoweredOnesInto) {
  const double raised = sideWindBank(0.4, 1.0), level = sideWindBank(0.0, 1.0),
               lowered = sideWindBank(-0.4, 1.0);
  EXPECT_LT(raised, 0.0);
  EXPECT_GT(lowered, 0.0);
  EXPECT_LT(raised, level);  // level strokes bank into it too (0.36 rad after 1 s)
  EXPECT_NEAR(sideWindBank(0.4, -1.0), -raised, 1e-6);
  EXPECT_NEAR(sideWindBank(-0.4, -1.0), -lowered, 1e-6);
}

}  // namespace
}  // namespace flapsim
