// The pressure law on a creature's faces at once (fluid/pressure_batch.h) against the law body
// by body (pressureLaw): to the bit, on the scalar and on the AVX2 path, in flight-like and in
// edge-on states, with and without wind; and a world stepped on either path.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "flapsim/make_creature.h"
#include "fluid/pressure.h"
#include "fluid/pressure_batch.h"
#include "fluid/surface.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::loadUrdf;

bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 24) == 0; }

struct Bodies {
  std::vector<AeroSurface> surfaces;
  std::vector<const AeroSurface*> pointers;
};

// The aero surfaces of every link with boxes, as the world builds them.
Bodies surfacesOf(const CreatureModel& m, const AirParams& air) {
  Bodies b;
  for (size_t k = 0; k < m.links.size(); ++k) {
    if (m.links[k].boxes.empty()) continue;
    b.surfaces.push_back(linkAeroSurface(m, static_cast<int>(k), air));
  }
  for (const AeroSurface& s : b.surfaces) b.pointers.push_back(&s);
  return b;
}

// A random state of every body: flight-like speeds (|v| ~ 3 m/s, |w| ~ 30 rad/s), or with
// `edge_on`, a body moving in the plane of its first face (u.n = 0 there up to rounding).
std::vector<BodyKinematics> randomStates(const Bodies& b, std::mt19937& rng, bool edge_on) {
  std::normal_distribution<double> nd(0.0, 1.0);
  std::vector<BodyKinematics> kin(b.surfaces.size());
  for (size_t i = 0; i < kin.size(); ++i) {
    BodyKinematics& k = kin[i];
    const Vec3 axis = Vec3(nd(rng), nd(rng), nd(rng)).normalized();
    k.orientation = Quat(Eigen::AngleAxisd(nd(rng), axis));
    k.rotation = k.orientation.toRotationMatrix();
    k.has_body_frame = true;
    k.body_linear_velocity = 3.0 * Vec3(nd(rng), nd(rng), nd(rng));
    k.body_angular_velocity = 30.0 * Vec3(nd(rng), nd(rng), nd(rng));
    if (edge_on) {
      const Vec3& n = b.surfaces[i].faces[0].normal;
      k.body_linear_velocity -= k.body_linear_velocity.dot(n) * n;
      k.body_angular_velocity.setZero();
    }
    k.linear_velocity = k.rotation * k.body_linear_velocity;
    k.angular_velocity = k.rotation * k.body_angular_velocity;
  }
  return kin;
}

// Over `states` random states: every body the batch holds gets pressureLaw's wrench to the
// bit from `kernel`; returns how many bodies were compared.
int compareWithLaw(const CreatureModel& m, AirParams air, PressureBatch::Kernel kernel,
                   int states) {
  const Bodies b = surfacesOf(m, air);
  PressureBatch batch;
  batch.build(b.pointers);
  std::mt19937 rng(11);
  std::vector<Wrench> out;
  int compared = 0;
  for (int s = 0; s < states; ++s) {
    air.wind = s % 3 == 0 ? Vec3(1.5, -0.5, 0.25) : Vec3::Zero();
    const std::vector<BodyKinematics> kin = randomStates(b, rng, s % 4 == 1);
    batch.run(kin, air, out, kernel);
    for (size_t i = 0; i < kin.size(); ++i) {
      if (!batch.holds(i)) continue;
      const Wrench law = pressureLaw(FluidInput{kin[i], b.surfaces[i], air}, nullptr);
      EXPECT_TRUE(sameBits(out[i].force, law.force) && sameBits(out[i].torque, law.torque))
          << "state " << s << " body " << i << ": force " << out[i].force.transpose() << " vs "
          << law.force.transpose() << ", torque " << out[i].torque.transpose() << " vs "
          << law.torque.transpose();
      ++compared;
    }
  }
  return compared;
}

std::vector<CreatureModelPtr> creatures() {
  return {parseCreatureModel(makeCreatureUrdf(1, "unit")),
          parseCreatureModel(makeCreatureUrdf(12, "chain")), loadUrdf("afc_1.urdf"),
          loadUrdf("feather_unit.urdf"), loadUrdf("bamboo_copter.urdf")};
}

TEST(PressureBatch, ScalarPathGivesTheLawsBits) {
  for (const CreatureModelPtr& m : creatures()) {
    EXPECT_GT(compareWithLaw(*m, AirParams(), PressureBatch::Kernel::kScalar, 64), 0) << m->name;
  }
}

bool cpuHasAvx2() { return __builtin_cpu_supports("avx2") != 0; }

TEST(PressureBatch, Avx2PathGivesTheLawsBits) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  for (const CreatureModelPtr& m : creatures()) {
    EXPECT_GT(compareWithLaw(*m, AirParams(), PressureBatch::Kernel::kAvx2, 64), 0) << m->name;
  }
}

// The world's step on either path: a 12-unit chain and a flap unit in a side wind, 300 steps.
TEST(PressureBatch, WorldsOnTheScalarAndTheAvx2PathAgreeToTheBit) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  const CreatureModelPtr chain = parseCreatureModel(makeCreatureUrdf(12, "chain"));
  const CreatureModelPtr unit = loadUrdf("flap_unit.urdf");
  auto fly = [&](bool simd) {
    PressureBatch::allowSimd(simd);
    WorldParams p;
    p.air.wind = Vec3(0.0, 1.0, 0.2);
    World w(p);
    w.spawn("chain", chain, test::at(0, 0, 50));
    w.spawn("unit", unit, test::at(5, 0, 50));
    w.setWingCommands("chain", {},
                      std::vector<StrokeCommand>(chain->wing_joints.size(), {30, 10, 0.8}));
    w.setWingCommands("unit", {},
                      std::vector<StrokeCommand>(unit->wing_joints.size(), {40, 10, 0.8}));
    w.step(300);
    return std::vector<CreatureState>{w.state("chain"), w.state("unit")};
  };
  const std::vector<CreatureState> scalar = fly(false), simd = fly(true);
  PressureBatch::allowSimd(true);
  for (size_t i = 0; i < scalar.size(); ++i) {
    EXPECT_TRUE(test::bitIdentical(scalar[i], simd[i])) << "creature " << i;
  }
  // The flight moved: the comparison is of something.
  EXPECT_GT((scalar[0].link_poses[0].position - Vec3(0, 0, 50)).norm(), 1e-3);
}
}  // namespace
}  // namespace flapsim
