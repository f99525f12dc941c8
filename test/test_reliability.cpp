// Reliability: joint limits that hold, the divergence watchdog, and bad or extreme input
// refused with a named error instead of a blow-up, a NaN or a hang.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/air_model.h"
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

// ---- the divergence watchdog ----------------------------------------------------------

// In vacuum a dropped plate's speed after step n is exactly g n dt; with max_speed 3 m/s the
// step that would pass it (n = 306) is refused and the plate keeps the state of step 305.
TEST(Watchdog, FreezesACreatureFasterThanMaxSpeedAtTheStepThatPassesIt) {
  WorldParams p = test::openSky();
  p.air.enabled = false;
  p.max_speed = 3.0;
  World w(p);
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 100));
  w.step(400);
  const std::optional<Divergence> d = w.divergence("plate");
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->creature, "plate");
  EXPECT_EQ(d->step, 306u);
  EXPECT_NE(d->quantity.find("link 'plate'"), std::string::npos) << d->quantity;
  EXPECT_NE(d->quantity.find("max_speed 3 m/s"), std::string::npos) << d->quantity;
  EXPECT_NEAR(w.rootTwist("plate").linear.z(), -9.81 * 305 * p.step_size, 1e-9);
  EXPECT_EQ(w.stepCount(), 400u);  // the world's time goes on
  // Reported once, then reset brings it back to life.
  EXPECT_EQ(w.takeDivergences().size(), 1u);
  EXPECT_TRUE(w.takeDivergences().empty());
  w.reset();
  EXPECT_FALSE(w.divergence("plate").has_value());
  w.step(10);
  EXPECT_NEAR(w.rootTwist("plate").linear.z(), -9.81 * 10 * p.step_size, 1e-9);
}

// The pressure model, but NaN for any body below z = 99.9 east of x = 5: a stand-in for a
// model (or a state) going non-finite.
class PoisonedAir : public AirModel {
 public:
  Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                    std::vector<Vec3>* cells) const override {
    if (body.com.x() > 5.0 && body.com.z() < 99.9) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return Wrench{Vec3(nan, nan, nan), Vec3::Zero()};
    }
    return pressure_.bodyWrench(body, surface, air, cells);
  }

 private:
  PressureAirModel pressure_;
};

TEST(Watchdog, ANonFiniteCreatureIsFrozenAndTheOthersGoOnUntouched) {
  World w(test::openSky());
  w.setAirModel(std::make_shared<PoisonedAir>());
  w.spawn("good", loadUrdf("plate.urdf"), at(0, 0, 100));
  w.spawn("bad", loadUrdf("plate.urdf"), at(10, 0, 100));
  World alone(test::openSky());
  alone.setAirModel(std::make_shared<PoisonedAir>());
  alone.spawn("good", loadUrdf("plate.urdf"), at(0, 0, 100));
  w.step(1000);
  alone.step(1000);

  const std::optional<Divergence> d = w.divergence("bad");
  ASSERT_TRUE(d.has_value());
  EXPECT_NE(d->quantity.find("non-finite"), std::string::npos) << d->quantity;
  // Frozen with the state of the step before, bit for bit, just below z = 99.9.
  World before(test::openSky());
  before.setAirModel(std::make_shared<PoisonedAir>());
  before.spawn("bad", loadUrdf("plate.urdf"), at(10, 0, 100));
  before.step(static_cast<int>(d->step) - 1);
  EXPECT_TRUE(test::bitIdentical(w.state("bad"), before.state("bad")));
  EXPECT_LT(w.rootPose("bad").position.z(), 99.9);
  // The good plate falls exactly as if it were alone.
  EXPECT_FALSE(w.divergence("good").has_value());
  EXPECT_TRUE(test::bitIdentical(w.state("good"), alone.state("good")));
}

}  // namespace
}  // namespace flapsim
