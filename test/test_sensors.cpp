// The sensors a controller of flap units reads (flapsim/sensors.h) and the extended network's
// inputs (flapsim/ann.h): forward kinematics from the IMU and the encoders against the
// world's own link poses, the mirror network's symmetry, the altitude input.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "flapsim/ann.h"
#include "flapsim/make_creature.h"
#include "flapsim/sensors.h"
#include "flapsim/world.h"

namespace flapsim {
namespace {

// A four-unit chain flown open loop for 1 s, its units' wings pulling apart, from a tilted start,
// so that its joints are bent and turning: the units sensed from an exact IMU and the encoders are
// the world's.
TEST(UnitSensing, ImuAndEncodersGiveEveryUnitsAttitudeAndRate) {
  const CreatureModelPtr m = parseCreatureModel(makeCreatureUrdf(4, "afc"), "afc_4");
  World world;
  world.spawn("c", m, poseFromXyzRpy(Vec3(0, 0, 1), Vec3(0.3, -0.2, 0.5)));
  const FlapUnitLayout layout = flapUnitLayout(*m);
  std::vector<StrokeCommand> strokes;  // left, right per unit: the wings of each pull apart
  for (int u = 0; u < 4; ++u) {
    strokes.push_back(StrokeCommand{u % 2 ? 60.0 : 20.0, 10, 1.2});
    strokes.push_back(StrokeCommand{u % 2 ? 20.0 : 60.0, 10, 1.2});
  }
  world.setWingCommands("c", layout.wing_joints, strokes);
  world.step(1000);
  const CreatureState s = world.state("c");
  std::vector<int> bodies;
  for (const auto& name : layout.body_links) bodies.push_back(m->findLink(name));
  const ImuReading imu =
      imuReading(s, world.rootAcceleration("c"), world.params().gravity, ImuNoise(), nullptr);
  const FlapSensing sensed =
      unitSensing(*m, bodies, imu, s.joint_positions, s.joint_velocities, 1.5);
  ASSERT_EQ(sensed.orientations.size(), 4u);
  double bend = 0.0;
  for (size_t u = 0; u < bodies.size(); ++u) {
    const Quat truth = s.link_poses[bodies[u]].orientation;
    const Vec3 rate = truth.conjugate() * s.link_twists[bodies[u]].angular;
    EXPECT_LT(sensed.orientations[u].angularDistance(truth), 1e-9) << "unit " << u;
    EXPECT_LT((sensed.rates[u] - rate).norm(), 1e-9) << "unit " << u;
    bend = std::max(bend, truth.angularDistance(s.link_poses[bodies[0]].orientation));
  }
  EXPECT_GT(bend, 1e-3);  // the units do not all share the root's attitude
  EXPECT_EQ(sensed.altitude, 1.5);
  std::vector<double> short_list(2, 0.0);
  EXPECT_THROW(unitSensing(*m, bodies, imu, short_list, s.joint_velocities, 0.0), InputError);
}

// The orientation noise turns the reading by a rotation vector of sigma x three standard
// normals, in the body's axes.
TEST(ImuReading, OrientationNoiseIsARotationVectorInTheBodysAxes) {
  const CreatureModelPtr m = parseCreatureModel(makeCreatureUrdf(1, "afc"), "afc_1");
  World world;
  world.spawn("c", m, poseFromXyzRpy(Vec3(0, 0, 1), Vec3(0.2, 0.1, 0.0)));
  const CreatureState s = world.state("c");
  ImuNoise noise;
  noise.orientation = 0.05;
  const double samples[] = {1.0, -2.0, 0.5};
  int k = 0;
  const ImuReading r =
      imuReading(s, Vec3::Zero(), world.params().gravity, noise, [&] { return samples[k++]; });
  EXPECT_EQ(k, 3);
  const Vec3 v = 0.05 * Vec3(1.0, -2.0, 0.5);
  const Quat expected =
      s.link_poses[0].orientation * Quat(Eigen::AngleAxisd(v.norm(), v / v.norm()));
  EXPECT_LT(r.orientation.angularDistance(expected), 1e-12);
  EXPECT_NEAR(r.orientation.angularDistance(s.link_poses[0].orientation), v.norm(), 1e-12);
}

// A steady turn at 0.5 rad/s read exactly: the filter's gyro carries its estimate along, so it
// stays on the reading; blind to the gyro (angular velocity zero) it is a low-pass of the angle,
// which trails a ramp by rate x time constant (0.1 rad).
// The ground-speed sensor adds noise x the standard normals drawn for x, y, z in that order,
// and draws none when exact (so an exact sensor leaves a seeded run's other draws alone).
TEST(GroundSpeedReading, AddsDeviationTimesNormalsInAxisOrderAndDrawsNoneWhenExact) {
  const std::vector<double> normals = {1.0, -2.0, 0.5};
  int drawn = 0;
  const std::function<double()> normal = [&] { return normals.at(drawn++); };
  const Vec3 v(0.3, -0.1, 0.05);
  EXPECT_EQ(groundSpeedReading(v, 0.0, normal), v);
  EXPECT_EQ(drawn, 0);
  const Vec3 noisy = groundSpeedReading(v, 0.1, normal);
  EXPECT_EQ(drawn, 3);
  EXPECT_DOUBLE_EQ(noisy.x(), 0.3 + 0.1);
  EXPECT_DOUBLE_EQ(noisy.y(), -0.1 - 0.2);
  EXPECT_DOUBLE_EQ(noisy.z(), 0.05 + 0.05);
}

TEST(AttitudeFilter, FollowsASteadyTurnWhereALowPassTrailsByRateTimesTimeConstant) {
  const double rate = 0.5, tau = 0.2, dt = 0.02;
  const Vec3 axis = Vec3(0.3, -0.4, 0.866).normalized();
  AttitudeFilter with_gyro(tau), blind(tau);
  double lag_with = 0.0, lag_blind = 0.0;
  for (int k = 0; k <= 200; ++k) {  // 4 s, 20 time constants
    ImuReading r;
    r.orientation = Quat(Eigen::AngleAxisd(rate * k * dt, axis));
    r.angular_velocity = rate * axis;  // the body's axes: the axis is fixed in both
    lag_with = with_gyro.update(r, dt).orientation.angularDistance(r.orientation);
    r.angular_velocity = Vec3::Zero();
    lag_blind = blind.update(r, dt).orientation.angularDistance(r.orientation);
  }
  EXPECT_LT(lag_with, 1e-9);
  EXPECT_NEAR(lag_blind, rate * tau, 1e-6);
}

// A still body read with white orientation noise (0.1 rad per axis, a fresh draw each 0.02 s):
// through a 0.2 s filter the estimate's error is the noise's times sqrt(a / (2 - a)), a = dt /
// (tau + dt) (an exponential average of independent draws): 0.173 rad rms -> 0.038 rad.
TEST(AttitudeFilter, CutsWhiteOrientationNoiseBySqrtAOver2MinusA) {
  const double sigma = 0.1, tau = 0.2, dt = 0.02, a = dt / (tau + dt);
  std::mt19937_64 gen(7);
  std::normal_distribution<double> normal;
  AttitudeFilter filter(tau);
  const Quat truth(Eigen::AngleAxisd(0.4, Vec3(1, 2, 0).normalized()));
  double raw_sq = 0.0, est_sq = 0.0;
  int n = 0;
  for (int k = 0; k < 100000; ++k) {
    const Vec3 v(sigma * normal(gen), sigma * normal(gen), sigma * normal(gen));
    ImuReading r;
    r.orientation = truth * Quat(Eigen::AngleAxisd(v.norm(), v / v.norm()));
    const double e = filter.update(r, dt).orientation.angularDistance(truth);
    if (k < 100) continue;  // the first reading is taken as it is
    raw_sq += v.squaredNorm();
    est_sq += e * e;
    ++n;
  }
  const double raw = std::sqrt(raw_sq / n), est = std::sqrt(est_sq / n);
  EXPECT_NEAR(raw, sigma * std::sqrt(3.0), 0.002);
  EXPECT_NEAR(est / raw, std::sqrt(a / (2.0 - a)), 0.03 * std::sqrt(a / (2.0 - a)));
}

// Time constant 0 passes the reading bit for bit; reset() makes the next reading the estimate
// again; a bad time constant is named.
TEST(AttitudeFilter, OffPassesTheReadingAndResetRestartsIt) {
  ImuReading first, second;
  first.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX()));
  second.orientation = Quat(Eigen::AngleAxisd(-0.2, Vec3::UnitY()));
  second.angular_velocity = Vec3(0.1, 0.2, 0.3);
  AttitudeFilter off(0.0);
  off.update(first, 0.02);
  EXPECT_EQ(off.update(second, 0.02).orientation.coeffs(), second.orientation.coeffs());
  AttitudeFilter on(0.2);
  EXPECT_LT(on.update(first, 0.02).orientation.angularDistance(first.orientation), 1e-12);
  const double moved = on.update(second, 0.02).orientation.angularDistance(first.orientation);
  EXPECT_GT(moved, 0.0);
  EXPECT_LT(moved, 0.2 * first.orientation.angularDistance(second.orientation));
  on.reset();
  EXPECT_LT(on.update(second, 0.02).orientation.angularDistance(second.orientation), 1e-12);
  for (double bad : {-0.1, std::nan(""), 2e3}) {
    try {
      AttitudeFilter f(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("time constant"), std::string::npos) << e.what();
    }
  }
}

// updateAt (ann_controller's, on the IMU's stamps): stamps k x 20 ms step as update() by the
// control period 0.02 does, bit for bit (the episodes'); the same stamp again changes nothing;
// an earlier stamp (the simulator was reset) restarts the filter on that reading.
TEST(AttitudeFilter, UpdateAtStepsByTheStampsAndRestartsWhenTheyGoBack) {
  AttitudeFilter by_stamp(0.1), by_period(0.1);
  std::vector<ImuReading> readings(50);
  for (size_t k = 0; k < readings.size(); ++k) {
    readings[k].orientation =
        Quat(Eigen::AngleAxisd(0.3 * std::sin(0.7 * k), Vec3(1, 1, 0).normalized()));
    readings[k].angular_velocity = Vec3(0.5 * std::cos(0.3 * k), -0.2, 0.1 * k);
  }
  ImuReading a, b;
  for (size_t k = 0; k < readings.size(); ++k) {
    const std::int64_t stamp = static_cast<std::int64_t>(k) * 20000000 + 1000000000;
    a = by_stamp.updateAt(readings[k], stamp);
    b = by_period.update(readings[k], 0.02);
    ASSERT_EQ(a.orientation.coeffs(), b.orientation.coeffs()) << "reading " << k;
    ASSERT_EQ(by_stamp.updateAt(readings[(k + 7) % readings.size()], stamp).orientation.coeffs(),
              a.orientation.coeffs());
  }
  const ImuReading again = by_stamp.updateAt(readings[3], 0);
  EXPECT_LT(again.orientation.angularDistance(readings[3].orientation), 1e-12);
  EXPECT_GT(a.orientation.angularDistance(readings[3].orientation), 1e-3);
}

FlapControllerParams extended() {
  FlapControllerParams p;
  p.network = FlapNetwork::kMirror;
  p.rate_inputs = true;
  p.altitude_input = true;
  p.hidden = 4;
  return p;
}

std::vector<double> someWeights(int n) {
  std::vector<double> w(n);
  for (int i = 0; i < n; ++i) w[i] = std::sin(1.7 * i + 0.3) * 3.0;
  return w;
}

// The mirror network: the left wing's rate is the net on the mirrored inputs, so a unit
// mirrored (rolled the other way, turning the other way) swaps the wings' rates, and a level
// unit not turning about x or z commands the same rate on both.
TEST(MirrorNetwork, MirroredUnitsSwapTheirRatesAndALevelUnitFlapsEvenly) {
  const FlapControllerParams p = extended();
  EXPECT_EQ(FlapUnitController::weightCount(p), (6 + 1) * 4 + (4 + 1));
  const FlapUnitController unit(p, someWeights(FlapUnitController::weightCount(p)));
  const std::vector<double> x = {0.1, 0.3, 0.2, -0.1, 0.4, 0.7};
  const std::vector<double> a = unit.rates(x);
  const std::vector<double> b = unit.rates(mirroredInputs(p, x));
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0], b[1]);
  EXPECT_EQ(a[1], b[0]);
  EXPECT_NE(a[0], a[1]);
  const std::vector<double> level = unit.rates({0.1, 0.0, 0.0, 0.3, 0.0, -0.2});
  EXPECT_EQ(level[0], level[1]);
}

TEST(AltitudeInput, IsTheClampedErrorOrPlusOneWithoutASetpoint) {
  const FlapControllerParams p = extended();
  EXPECT_EQ(altitudeInput(p, 3.0, std::nullopt), 1.0);
  EXPECT_DOUBLE_EQ(altitudeInput(p, 4.75, 5.0), 0.25);
  EXPECT_EQ(altitudeInput(p, 9.0, 5.0), -1.0);
  EXPECT_EQ(altitudeInput(p, 1.0, 5.0), 1.0);
  const std::vector<double> in =
      flapNetworkInputs(p, Quat::Identity(), Vec3(10.0, -20.0, 5.0), 0.25);
  const std::vector<double> expected = {0.0, 0.0, 1.0, -2.0, 0.5, 0.25};
  EXPECT_EQ(in, expected);
  EXPECT_EQ(flapInputNames(p).size(), 6u);
}

}  // namespace
}  // namespace flapsim
