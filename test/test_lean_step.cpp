// Lean steps (WorldParams::lean_steps): a step in which nothing can touch the ground skips
// Bullet's collision, island and solver stages and updates the velocities with TreeDynamics
// instead of Bullet's articulated-body pass. Its trajectories must be Bullet's full step's up
// to rounding, in flight, near the ground and at a joint's stop.
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "doc_figure.h"
#include "dynamics/tree_dynamics.h"
#include "flapsim/make_creature.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;

// The largest difference between two states' link positions (m), orientations (quaternion
// coefficients), velocities (m/s, rad/s) and joint positions and velocities.
double largestDifference(const CreatureState& a, const CreatureState& b) {
  double most = 0.0;
  auto take = [&most](double d) { most = std::max(most, std::abs(d)); };
  for (size_t i = 0; i < a.link_poses.size(); ++i) {
    take((a.link_poses[i].position - b.link_poses[i].position).cwiseAbs().maxCoeff());
    take((a.link_poses[i].orientation.coeffs() - b.link_poses[i].orientation.coeffs())
             .cwiseAbs()
             .maxCoeff());
    take((a.link_twists[i].linear - b.link_twists[i].linear).cwiseAbs().maxCoeff());
    take((a.link_twists[i].angular - b.link_twists[i].angular).cwiseAbs().maxCoeff());
  }
  for (size_t j = 0; j < a.joint_positions.size(); ++j) {
    take(a.joint_positions[j] - b.joint_positions[j]);
    take(a.joint_velocities[j] - b.joint_velocities[j]);
  }
  return most;
}

// Rounding apart, the lean and the full step are the same step: over the runs below their
// trajectories stay within 1e-12 of each other (SI units); this leaves a margin.
constexpr double kTolerance = 1e-10;

// Two worlds, lean and full steps, set up alike; `steps` steps in `chunk`s, the states
// compared after each chunk (and `check` run on the lean one).
void expectSameTrajectory(WorldParams p, const std::function<void(World&)>& setup, int steps,
                          int chunk, const std::function<void(const CreatureState&)>& check,
                          double tolerance = kTolerance) {
  p.lean_steps = true;
  World lean(p);
  p.lean_steps = false;
  World full(p);
  setup(lean);
  setup(full);
  double most = 0.0;
  for (int done = 0; done < steps; done += chunk) {
    lean.step(chunk);
    full.step(chunk);
    const CreatureState a = lean.state("c"), b = full.state("c");
    most = std::max(most, largestDifference(a, b));
    ASSERT_LT(largestDifference(a, b), tolerance) << "after " << done + chunk << " steps";
    if (check) check(a);
  }
  test::printFigure("largest_difference", most);
}

void flapper(World& w, int units, double height) {
  const CreatureModelPtr m = parseCreatureModel(makeCreatureUrdf(units, "c"));
  w.spawn("c", m, at(0, 0, height));
  w.setWingCommands("c", {}, std::vector<StrokeCommand>(m->wing_joints.size(), {30, 10, 0.8}));
}

TEST(LeanStep, FlappingFlightFollowsFullSteps) {
  expectSameTrajectory(
      WorldParams(), [](World& w) { flapper(w, 1, 50); }, 600, 20, nullptr);
}

TEST(LeanStep, ChainWithAddedMassFollowsFullSteps) {
  WorldParams p;
  p.air.added_mass = true;
  expectSameTrajectory(
      p, [](World& w) { flapper(w, 3, 50); }, 300, 20, nullptr);
}

// The feathering unit (a second servo on each wing) and the flap unit under the
// quasi-steady model in a side wind, which rolls it (the implicit drag's loads in the servo
// solve, on a root that turns).
TEST(LeanStep, FeatheringAndImplicitDragFollowFullSteps) {
  const CreatureModelPtr feather = test::loadUrdf("feather_unit.urdf");
  expectSameTrajectory(
      WorldParams(),
      [&feather](World& w) {
        w.spawn("c", feather, at(0, 0, 50));
        w.setWingCommands(
            "c", {}, std::vector<StrokeCommand>(feather->wing_joints.size(), {30, 10, 0.8, 1.2}));
      },
      300, 20, nullptr);
  // The quasi-steady law's implicit part is central differences of its kernel, which turn
  // the two steps' rounding (1e-16) into 1e-11 of the damping: 1.7e-10 after 200 steps.
  WorldParams p;
  p.air.model = "quasi_steady";
  p.air.wind = Vec3(0.0, 1.0, 0.0);
  const CreatureModelPtr fu = test::loadUrdf("flap_unit.urdf");
  expectSameTrajectory(
      p,
      [&fu](World& w) {
        w.spawn("c", fu, at(0, 0, 50));
        w.setWingCommands("c", {},
                          std::vector<StrokeCommand>(fu->wing_joints.size(), {40, 10, 0.8}));
      },
      300, 20, nullptr, 1e-9);
}

// A flap unit released 0.3 m above the ground falls onto it and keeps flapping there: the
// steps near the ground are Bullet's (contacts hold it up) and the trajectory is the same.
// Without added mass: with it the unit (30/10) comes down onto a wing at step 676, where the
// lean and the full step, 6e-15 apart before, part by 9e-4 in that one step; a contact that
// starts at Bullet's threshold turns a rounding difference into whether it acts at all.
TEST(LeanStep, FallsBackToFullStepsNearTheGround) {
  WorldParams p;
  p.air.added_mass = false;
  expectSameTrajectory(
      p, [](World& w) { flapper(w, 1, 0.3); }, 1500, 50,
      [](const CreatureState& s) {
        for (const Pose& link : s.link_poses) EXPECT_GT(link.position.z(), -0.01);
      });
}

// A flap on a hinge limited to +-0.3 rad, thrown at 10 rad/s against its upper stop, in
// open sky (no contact ever possible): the limit's solve still runs when the joint nears
// the stop, which holds, and the trajectory is the full step's.
TEST(LeanStep, FallsBackToTheSolverNearAJointStop) {
  const CreatureModelPtr flap = parseCreatureModel(R"(<robot name="h"><link name="base">
    <inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
    <collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
    <link name="flap"><inertial><origin xyz="0 0.1 0"/><mass value="0.01"/>
      <inertia ixx="3.4e-5" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="3.4e-5"/></inertial>
      <collision><origin xyz="0 0.1 0"/><geometry><box size="0.05 0.2 0.002"/></geometry></collision></link>
    <joint name="hinge" type="revolute"><parent link="base"/><child link="flap"/>
      <axis xyz="1 0 0"/><limit lower="-0.3" upper="0.3" effort="1" velocity="100"/></joint></robot>)");
  WorldParams p = test::openSky();
  p.air.enabled = false;
  auto setup = [&flap](World& w) {
    w.spawn("c", flap, at(0, 0, 1));
    StateRequest r;
    r.joint_velocities = {10.0};
    w.setState("c", r);
  };
  expectSameTrajectory(p, setup, 200, 1,
                       [](const CreatureState& s) { EXPECT_LT(s.joint_positions[0], 0.3 + 1e-3); });
}

// A floating base with a revolute joint, a prismatic one on it, a fixed link and a second
// revolute branch, in random states under random forces and joint torques: TreeDynamics'
// accelerations are those of Bullet's articulated-body pass (which differ by 4e-13 at most
// here, for accelerations up to 190). One TreeDynamics throughout: the frames it keeps while
// the positions are the same must follow every change of them (a new pose of everything,
// one joint moved) and serve new velocities and forces at the same positions.
TEST(LeanStep, TreeDynamicsAcceleratesAsBullet) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  auto vec = [&] { return btVector3(uni(rng), uni(rng), uni(rng)); };
  auto rot = [&] { return btQuaternion(vec().normalized(), 3.0 * uni(rng)); };
  btMultiBody mb(4, 0.3, btVector3(2e-3, 3e-3, 4e-3), false, false);
  mb.setupRevolute(0, 0.05, btVector3(1e-4, 2e-4, 3e-4), -1, rot(), vec().normalized(), vec(),
                   vec(), true);
  mb.setupPrismatic(1, 0.02, btVector3(1e-5, 2e-5, 3e-5), 0, rot(), vec().normalized(), vec(),
                    vec(), true);
  mb.setupFixed(2, 0.01, btVector3(1e-5, 1e-5, 2e-5), 1, rot(), vec(), vec());
  mb.setupRevolute(3, 0.04, btVector3(3e-4, 1e-4, 2e-4), -1, rot(), vec().normalized(), vec(),
                   vec(), true);
  mb.finalizeMultiDof();
  mb.setLinearDamping(0);
  mb.setAngularDamping(0);
  mb.setUseGyroTerm(true);
  ASSERT_TRUE(TreeDynamics::handles(mb));
  auto velocitiesAndForces = [&] {
    mb.setBaseOmega(5.0 * vec());
    mb.setBaseVel(vec());
    for (int l : {0, 1, 3}) {
      mb.setJointVel(l, 10.0 * uni(rng));
      mb.addJointTorque(l, 0.01 * uni(rng));
    }
    mb.addBaseForce(vec());
    mb.addBaseTorque(0.01 * vec());
    for (int l = 0; l < 4; ++l) {
      mb.addLinkForce(l, vec());
      mb.addLinkTorque(l, 0.01 * vec());
    }
  };
  TreeDynamics tree;
  double most = 0.0;  // the largest difference relative to 1 + |Bullet's acceleration|
  auto expectAsBullet = [&](const std::string& what) {
    const std::vector<double> ours = tree.accelerations(mb);
    btAlignedObjectArray<btScalar> r;
    btAlignedObjectArray<btVector3> v;
    btAlignedObjectArray<btMatrix3x3> m;
    mb.computeAccelerationsArticulatedBodyAlgorithmMultiDof(0, r, v, m, false, false, false);
    const btScalar* bullet = &r[mb.getNumDofs()];
    ASSERT_EQ(ours.size(), 6u + mb.getNumDofs());
    for (size_t i = 0; i < ours.size(); ++i) {
      most = std::max(most, std::abs(ours[i] - bullet[i]) / (1.0 + std::abs(bullet[i])));
      EXPECT_NEAR(ours[i], bullet[i], 1e-10 * (1.0 + std::abs(bullet[i])))
          << what << ", acceleration " << i;
    }
    mb.clearForcesAndTorques();
  };
  for (int trial = 0; trial < 20; ++trial) {
    const std::string name = "trial " + std::to_string(trial);
    mb.setBaseWorldTransform(btTransform(rot(), vec()));
    for (int l : {0, 1, 3}) mb.setJointPos(l, uni(rng));
    velocitiesAndForces();
    expectAsBullet(name + ", new pose");
    velocitiesAndForces();
    expectAsBullet(name + ", same positions");
    mb.setJointPos(3, mb.getJointPos(3) + 0.5 * uni(rng));
    velocitiesAndForces();
    expectAsBullet(name + ", joint 3 moved");
  }
  test::printFigure("largest_relative_difference", most);
}

}  // namespace
}  // namespace flapsim
