// The sensors a controller of flap units reads (flapsim/sensors.h) and the extended network's
// inputs (flapsim/ann.h): forward kinematics from the IMU and the encoders against the
// world's own link poses, the mirror network's symmetry, the altitude input.
#include <gtest/gtest.h>

#include <cmath>

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
