// Scratch experiment (replaced by the invariance tests).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

struct Medium {
  const char* name;
  bool air;
  double density;
};

struct End {
  Vec3 position;
  Quat orientation;
};

WorldParams base = test::openSky();
End fly(const std::string& urdf, const Medium& medium, double dt, const Vec3& moving,
        double seconds, double roll, const StrokeCommand& left, const StrokeCommand& right) {
  WorldParams p = base;
  p.step_size = dt;
  p.air.enabled = medium.air;
  p.air.density = medium.density;
  p.air.wind = moving;
  World w(p);
  const CreatureModelPtr m = loadUrdf(urdf);
  Twist t;
  t.linear = moving;
  w.spawn("c", m, at(0, 0, 20, Quat(Eigen::AngleAxisd(roll, Vec3::UnitX()))), t);
  std::vector<StrokeCommand> c;
  const size_t wings = m->wing_joints.size();
  for (size_t i = 0; i < wings; ++i) c.push_back(i % 2 ? right : left);
  w.setWingCommands("c", {}, c);
  const int steps = static_cast<int>(std::lround(seconds / dt));
  w.step(steps);
  End e{w.rootPose("c").position - moving * (steps * dt), w.rootPose("c").orientation};
  return e;
}

TEST(Scratch, Vacuum) {
  const Medium med{"vacuum", false, 0.0};
  for (int variant = 0; variant < 4; ++variant) {
    base = test::openSky();
    if (variant & 1) base.lean_steps = false;
    if (variant & 2) base.turn_substep = 0.0;
    for (double secs : {0.003, 0.01, 1.0}) {
      const StrokeCommand s{60, 10, 0.6};
      const double dt = 0.001;
      const Vec3 W(0.6, 0.8, 0);
      const End a = fly("flap_unit.urdf", med, dt, Vec3::Zero(), secs, 0.05, s, s);
      const End b = fly("flap_unit.urdf", med, dt, W, secs, 0.05, s, s);
      std::printf("variant lean_off=%d turn_off=%d %.3f s gal %.3e m %.3e rad\n", variant & 1,
                  variant >> 1, secs, (a.position - b.position).norm(),
                  a.orientation.angularDistance(b.orientation));
    }
  }
  base = test::openSky();
}

TEST(Scratch, VacuumSteps) {
  WorldParams p = test::openSky();
  p.air.enabled = false;
  const Vec3 W(0.6, 0.8, 0);
  World a(p), b(p);
  const CreatureModelPtr m = loadUrdf("flap_unit.urdf");
  Twist t;
  t.linear = W;
  a.spawn("c", m, at(0, 0, 20, Quat(Eigen::AngleAxisd(0.05, Vec3::UnitX()))));
  b.spawn("c", m, at(0, 0, 20, Quat(Eigen::AngleAxisd(0.05, Vec3::UnitX()))), t);
  const StrokeCommand s{60, 10, 0.6};
  a.setWingCommands("c", {}, {s, s});
  b.setWingCommands("c", {}, {s, s});
  for (int k = 1; k <= 6; ++k) {
    a.step();
    b.step();
    const CreatureState sa = a.state("c"), sb = b.state("c");
    double dq = 0, dqd = 0, dpos = 0, dvel = 0, dw = 0, dori = 0;
    for (size_t j = 0; j < sa.joint_positions.size(); ++j) {
      dq = std::max(dq, std::abs(sa.joint_positions[j] - sb.joint_positions[j]));
      dqd = std::max(dqd, std::abs(sa.joint_velocities[j] - sb.joint_velocities[j]));
    }
    for (size_t l = 0; l < sa.link_poses.size(); ++l) {
      dpos = std::max(dpos, (sa.link_poses[l].position + W * (k * 0.001) - sb.link_poses[l].position).norm());
      dori = std::max(dori, sa.link_poses[l].orientation.angularDistance(sb.link_poses[l].orientation));
      dvel = std::max(dvel, (sa.link_twists[l].linear + W - sb.link_twists[l].linear).norm());
      dw = std::max(dw, (sa.link_twists[l].angular - sb.link_twists[l].angular).norm());
    }
    std::printf("step %d: q %.2e qd %.2e pos %.2e ori %.2e vel %.2e w %.2e  q=%.6f qd=%.4f\n", k, dq, dqd, dpos,
                dori, dvel, dw, sa.joint_positions[0], sa.joint_velocities[0]);
  }
}

TEST(Scratch, Gaps) {
  const Medium media[] = {{"vacuum", false, 0.0}, {"air", true, 1.204}, {"water", true, 1000}};
  const char* creatures[] = {"flap_unit.urdf", "afc_4.urdf", "hover_1.urdf", "swimmer.urdf"};
  for (const char* urdf : creatures) {
    for (const Medium& med : media) {
      for (double dt : {0.001, 0.0005}) {
        const StrokeCommand s = med.density > 100 ? StrokeCommand{3, 1, 0.6}
                                                  : StrokeCommand{60, 10, 0.6};
        const Vec3 W = med.density > 100 ? Vec3(0.3, 0, 0.1) : Vec3(0.6, 0.8, 0);
        const double secs = 1.0;
        const End a = fly(urdf, med, dt, Vec3::Zero(), secs, 0.05, s, s);
        const End b = fly(urdf, med, dt, W, secs, 0.05, s, s);
        const End c = fly(urdf, med, dt, Vec3::Zero(), secs, 0.05 + 1e-9, s, s);
        std::printf("%-15s %-7s %.4f ms  gal %.3e m %.3e rad   chaos %.3e m %.3e rad\n", urdf,
                    med.name, dt * 1e3, (a.position - b.position).norm(),
                    a.orientation.angularDistance(b.orientation),
                    (a.position - c.position).norm(),
                    a.orientation.angularDistance(c.orientation));
      }
    }
  }
}

}  // namespace
}  // namespace flapsim
