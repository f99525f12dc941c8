// Lean steps (WorldParams::lean_steps): a step in which nothing can touch the ground skips
// Bullet's collision, island and solver stages. Its trajectories must be Bullet's full
// step's, bit for bit, in flight, near the ground and at a joint's stop.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "flapsim/make_creature.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::bitIdentical;

// Two worlds, lean and full steps, set up alike; `steps` steps in `chunk`s, the states
// compared after each chunk (and `check` run on the lean one).
void expectSameTrajectory(WorldParams p, const std::function<void(World&)>& setup, int steps,
                          int chunk, const std::function<void(const CreatureState&)>& check) {
  p.lean_steps = true;
  World lean(p);
  p.lean_steps = false;
  World full(p);
  setup(lean);
  setup(full);
  for (int done = 0; done < steps; done += chunk) {
    lean.step(chunk);
    full.step(chunk);
    const CreatureState a = lean.state("c"), b = full.state("c");
    ASSERT_TRUE(bitIdentical(a, b)) << "after " << done + chunk << " steps";
    if (check) check(a);
  }
}

void flapper(World& w, int units, double height) {
  const CreatureModelPtr m = parseCreatureModel(makeCreatureUrdf(units, "c"));
  w.spawn("c", m, at(0, 0, height));
  w.setWingCommands("c", {}, std::vector<StrokeCommand>(m->wing_joints.size(), {30, 10, 0.8}));
}

TEST(LeanStep, FlappingFlightIsBitIdenticalToFullSteps) {
  expectSameTrajectory(
      WorldParams(), [](World& w) { flapper(w, 1, 50); }, 600, 20, nullptr);
}

TEST(LeanStep, ChainWithAddedMassIsBitIdenticalToFullSteps) {
  WorldParams p;
  p.air.added_mass = true;
  expectSameTrajectory(
      p, [](World& w) { flapper(w, 3, 50); }, 300, 20, nullptr);
}

// A flap unit released 0.3 m above the ground falls onto it and keeps flapping there: the
// steps near the ground are Bullet's (contacts hold it up) and the trajectory is the same.
TEST(LeanStep, FallsBackToFullStepsNearTheGround) {
  expectSameTrajectory(
      WorldParams(), [](World& w) { flapper(w, 1, 0.3); }, 1500, 50,
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

}  // namespace
}  // namespace flapsim
