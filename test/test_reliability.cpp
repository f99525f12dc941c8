// Reliability: joint limits that hold, the divergence watchdog, and bad or extreme input
// refused with a named error instead of a blow-up, a NaN or a hang.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

// The largest excursion of any limited joint beyond its limits, and the fastest link COM,
// over a run.
struct RunExtremes {
  double limit_excess = 0.0;  // rad (or m)
  double max_speed = 0.0;     // m/s
  bool finite = true;
};

void record(const CreatureModel& m, const CreatureState& s, RunExtremes& out) {
  for (size_t j = 0; j < m.joints.size(); ++j) {
    const JointModel& jm = m.joints[j];
    const double q = s.joint_positions[j];
    if (!std::isfinite(q)) out.finite = false;
    if (jm.limited) out.limit_excess = std::max({out.limit_excess, q - jm.upper, jm.lower - q});
  }
  for (const Twist& t : s.link_twists) {
    if (!t.linear.allFinite() || !t.angular.allFinite()) out.finite = false;
    out.max_speed = std::max(out.max_speed, t.linear.norm());
  }
}

RunExtremes run(const std::string& urdf, int steps, double rate, double amplitude,
                double z = 50.0) {
  World w;
  CreatureModelPtr m = loadUrdf(urdf);
  w.spawn("c", m, at(0, 0, z));
  if (rate > 0.0) {
    std::vector<StrokeCommand> c(m->wing_joints.size(), StrokeCommand{rate, rate, amplitude});
    w.setWingCommands("c", {}, c);
  }
  RunExtremes out;
  for (int s = 0; s < steps; ++s) {
    w.step(1);
    record(*m, w.state("c"), out);
  }
  return out;
}

// Without a command the wings of a falling chain fold up onto their upper limits (about
// 0.44 s): Bullet's own limit rows over-corrected there, and the error grew until the
// creature went non-finite (afc_4: NaN at step 475).
TEST(JointLimits, FoldedWingsOfFallingChainsRestOnTheirStops) {
  for (const char* urdf : {"afc_4.urdf", "afc_6.urdf", "afc_12.urdf"}) {
    const RunExtremes r = run(urdf, 600, 0.0, 0.0);
    EXPECT_TRUE(r.finite) << urdf;
    EXPECT_LT(r.limit_excess, 1e-9) << urdf;
    // Falling from rest for 0.6 s under drag: slower than free fall's 5.9 m/s.
    EXPECT_LT(r.max_speed, 9.81 * 0.6) << urdf;
  }
}

// Strokes that turn just inside the +-1.4 rad wing limits at 200 rad/s: joints went 0.11 rad
// (flap unit) and 0.20 rad (afc_4) past their stops.
TEST(JointLimits, HoldAgainstFastStrokesThatTurnAtTheStops) {
  const RunExtremes unit = run("flap_unit.urdf", 1000, 200.0, 1.39);
  EXPECT_TRUE(unit.finite);
  EXPECT_LT(unit.limit_excess, 1e-9);
  const RunExtremes chain = run("afc_4.urdf", 1000, 200.0, 1.39);
  EXPECT_TRUE(chain.finite);
  EXPECT_LT(chain.limit_excess, 1e-9);
  // The wing tips move at about 200 rad/s x 0.35 m = 70 m/s at most; the COMs slower.
  EXPECT_LT(std::max(unit.max_speed, chain.max_speed), 70.0);
}

// A valid 250 rad/s stroke: the flap unit's wings went 0.05 rad past their stops.
TEST(JointLimits, FlapUnitAt250RadPerSecondStaysBounded) {
  const RunExtremes r = run("flap_unit.urdf", 2000, 250.0, 1.0);
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.limit_excess, 1e-9);
  EXPECT_LT(r.max_speed, 250.0 * 0.35);
}

}  // namespace
}  // namespace flapsim
