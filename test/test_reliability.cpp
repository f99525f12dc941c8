// Reliability: joint limits that hold, the divergence watchdog, and bad or extreme input
// refused with a named error instead of a blow-up, a NaN or a hang.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"
#include "flapsim/world.h"
#include "fluid/pressure.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

// The largest excursion of any limited joint beyond its limits, and the fastest link COM,
// over a run, and the watchdog's verdict: a creature that went non-finite or too fast is
// frozen at the finite, in-limit state before that step, so the extremes alone would not
// show it.
struct RunExtremes {
  double limit_excess = 0.0;  // rad (or m)
  double max_speed = 0.0;     // m/s
  bool finite = true;
  std::optional<Divergence> divergence;
  // For messages: the watchdog's quantity, or "not frozen".
  std::string verdict() const { return divergence ? divergence->quantity : "not frozen"; }
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
  out.divergence = w.divergence("c");
  return out;
}

// Without a command the wings of a falling chain fold up onto their upper limits (about
// 0.44 s): Bullet's own limit rows over-corrected there, and the error grew until the
// creature went non-finite (afc_4: NaN at step 475).
TEST(JointLimits, FoldedWingsOfFallingChainsRestOnTheirStops) {
  for (const char* urdf : {"afc_4.urdf", "afc_6.urdf", "afc_12.urdf"}) {
    const RunExtremes r = run(urdf, 600, 0.0, 0.0);
    EXPECT_FALSE(r.divergence) << urdf << ": " << r.verdict();
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
  EXPECT_FALSE(unit.divergence) << unit.verdict();
  EXPECT_TRUE(unit.finite);
  EXPECT_LT(unit.limit_excess, 1e-9);
  const RunExtremes chain = run("afc_4.urdf", 1000, 200.0, 1.39);
  EXPECT_FALSE(chain.divergence) << chain.verdict();
  EXPECT_TRUE(chain.finite);
  EXPECT_LT(chain.limit_excess, 1e-9);
  // The wing tips move at about 200 rad/s x 0.35 m = 70 m/s at most; the COMs slower.
  EXPECT_LT(std::max(unit.max_speed, chain.max_speed), 70.0);
}

// A valid 250 rad/s stroke: the flap unit's wings went 0.05 rad past their stops.
TEST(JointLimits, FlapUnitAt250RadPerSecondStaysBounded) {
  const RunExtremes r = run("flap_unit.urdf", 2000, 250.0, 1.0);
  EXPECT_FALSE(r.divergence) << r.verdict();
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.limit_excess, 1e-9);
  EXPECT_LT(r.max_speed, 250.0 * 0.35);
}

// Strokes of 1e4 rad/s (valid, if far beyond what the 2 N m wing motors reach): afc_12 went
// non-finite at step 156 and its passive joints thousands of radians past their stops.
TEST(JointLimits, TwelveUnitChainAt1e4RadPerSecondStaysBounded) {
  const RunExtremes r = run("afc_12.urdf", 1600, 1e4, 1.0);
  EXPECT_FALSE(r.divergence) << r.verdict();
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.limit_excess, 1e-9);
  EXPECT_LT(r.max_speed, 9.81 * 1.6);  // slower than a free fall for 1.6 s
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

// ---- numbers that enter: a named error instead of NaN ----------------------------------

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The flap unit's URDF with the first occurrence of `from` replaced by `to`.
std::string flapUnitWith(const std::string& from, const std::string& to) {
  std::string text = readText(test::sourcePath("urdf/flap_unit.urdf"));
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string modelError(const std::string& urdf) {
  try {
    parseCreatureModel(urdf, "unit.urdf");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(parsed)";
}

TEST(ModelNumbers, BadNumbersAreNamedWithTheirLinkOrJoint) {
  struct Case {
    std::string from, to, expect;
  };
  const std::string wing_box =
      "<geometry><box size=\"0.22 0.35 0.002\"/></geometry>\n    </collision>";
  const Case cases[] = {
      // urdfdom dropped a <collision> it could not read: the wing had no boxes, no air.
      {wing_box, "<geometry><box size=\"nan 0.35 0.002\"/></geometry>\n    </collision>",
       "link 'unit0_wing_left' <collision>: <geometry/box size='nan 0.35 0.002'>"},
      {"<collision>\n      <origin xyz=\"0 0.175 0\"/>",
       "<collision>\n      <origin xyz=\"0 inf 0\"/>",
       "link 'unit0_wing_left' <collision>: <origin xyz='0 inf 0'>"},
      // was "has no positive mass"
      {"<origin xyz=\"0 0.175 0\"/>\n      <mass", "<origin xyz=\"nan 0.175 0\"/>\n      <mass",
       "link 'unit0_wing_left': <inertial/origin xyz='nan 0.175 0'>"},
      {"<mass value=\"0.004\"/>", "<mass value=\"1e300\"/>",
       "link 'unit0_wing_left': <inertial/mass value='1e300'>"},
      {"<origin xyz=\"0 0.03 0\"/>", "<origin xyz=\"0 1e200 0\"/>",
       "joint 'unit0_wing_left_joint': <origin xyz='0 1e200 0'>"},
      // was silently the world's default 5 N m
      {"effort=\"8\"", "effort=\"-8\"", "joint 'unit0_wing_left_joint': <limit effort='-8'>"},
      // was accepted: a wing pitching itself
      {"<wing joint=\"unit0_wing_left_joint\"/>",
       "<wing joint=\"unit0_wing_left_joint\" feather_joint=\"unit0_wing_left_joint\"/>",
       "names itself as its feather_joint"},
  };
  for (const Case& c : cases) {
    const std::string err = modelError(flapUnitWith(c.from, c.to));
    EXPECT_NE(err.find("unit.urdf: "), std::string::npos) << err;
    EXPECT_NE(err.find(c.expect), std::string::npos)
        << "'" << err << "' lacks '" << c.expect << "'";
  }
}

// Found by the fuzzer: a joint whose child is the root link escaped as std::out_of_range
// ("map::at"), naming nothing.
TEST(ModelErrors, AJointOutsideTheTreeIsNamed) {
  const std::string err =
      modelError(flapUnitWith("<child link=\"unit0_wing_left\"/>", "<child link=\"unit0_body\"/>"));
  EXPECT_NE(err.find("unit.urdf: "), std::string::npos) << err;
  EXPECT_NE(err.find("joint 'unit0_wing_left_joint'"), std::string::npos) << err;
}

std::string loadError(const std::string& path) {
  try {
    loadCreatureModel(path);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(loaded)";
}

// A directory was "EMPTY_DOCUMENT"; a FIFO blocked the reader for ever; /dev/zero was read
// until std::bad_alloc.
TEST(UrdfFiles, OnlyRegularFilesUpTo16MiBAreRead) {
  std::string dir_template =
      (std::filesystem::temp_directory_path() / "flapsim_files_XXXXXX").string();
  const std::string dir = ::mkdtemp(&dir_template[0]);
  const std::string fifo = dir + "/pipe.urdf", big = dir + "/big.urdf";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  {
    std::ofstream out(big);
    out << "<robot name='big'>";
  }
  ASSERT_EQ(::truncate(big.c_str(), static_cast<off_t>(kMaxUrdfFileBytes) + 1), 0);
  EXPECT_EQ(loadError(dir), dir + ": not a regular file");
  EXPECT_EQ(loadError(fifo), fifo + ": not a regular file");
  EXPECT_EQ(loadError("/dev/zero"), "/dev/zero: not a regular file");
  EXPECT_EQ(loadError(big), big + ": 16777217 bytes, over the limit of 16777216 bytes");
  EXPECT_EQ(loadError(dir + "/missing.urdf"), dir + "/missing.urdf: cannot open file");
  ::unlink(fifo.c_str());
  ::unlink(big.c_str());
  ::rmdir(dir.c_str());
}

std::string readError(const std::string& path, std::size_t limit) {
  try {
    readTextFile(path, limit);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}

// Issue 27: `evolve --resume` with checkpoint.txt linked to /dev/zero grew to 4.2 GB;
// ann_controller _weights:=<FIFO> hung for ever (and ignored SIGINT). Every reader of the
// package (weights, checkpoints, URDF) goes through readTextFile.
TEST(TextFiles, OnlyRegularFilesWithinTheLimitAreReadAndAFifoIsNotWaitedOn) {
  std::string dir_template =
      (std::filesystem::temp_directory_path() / "flapsim_text_XXXXXX").string();
  const std::string dir = ::mkdtemp(&dir_template[0]);
  const std::string fifo = dir + "/weights.yaml", zero = dir + "/checkpoint.txt";
  const std::string small = dir + "/small.txt";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ASSERT_EQ(::symlink("/dev/zero", zero.c_str()), 0);
  std::ofstream(small) << "0123456789";
  EXPECT_EQ(readError(fifo, 1 << 20), fifo + ": not a regular file");
  EXPECT_EQ(readError(zero, 1 << 20), zero + ": not a regular file");
  EXPECT_EQ(readError(dir, 1 << 20), dir + ": not a regular file");
  EXPECT_EQ(readError(small, 9), small + ": 10 bytes, over the limit of 9 bytes");
  EXPECT_EQ(readTextFile(small, 10), "0123456789");
  try {
    loadControllerYaml(fifo);
    FAIL() << "a FIFO was read as weights";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "controller YAML " + fifo + ": not a regular file");
  }
  try {
    readCheckpointFile(zero);
    FAIL() << "/dev/zero was read as a checkpoint";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), zero + ": not a regular file");
  }
  try {
    readCheckpointFile(dir);
    FAIL() << "a directory was read as a checkpoint";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": not a regular file");  // was "missing header"
  }
  ::unlink(fifo.c_str());
  ::unlink(zero.c_str());
  ::unlink(small.c_str());
  ::rmdir(dir.c_str());
}

std::string spawnError(World& w, const Pose& pose, const Twist& twist = Twist()) {
  try {
    w.spawn("c", loadUrdf("flap_unit.urdf"), pose, twist);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(spawned)";
}

TEST(SpawnNumbers, AbsurdPosesAndTwistsAreRefusedByName) {
  World w;
  const double big = 1e300;
  Pose tiny = at(0, 0, 1);
  tiny.orientation = Quat(1e-10, 0, 0, 0);
  Pose huge_q = at(0, 0, 1);
  huge_q.orientation = Quat(big, big, 0, 0);
  // was "pose is not finite"
  EXPECT_EQ(spawnError(w, tiny),
            "creature 'c': orientation quaternion has norm 1e-10 (must be finite and between "
            "1e-6 and 1e6; it is normalised)");
  // was accepted and made NaN
  EXPECT_NE(spawnError(w, huge_q).find("orientation quaternion has norm inf"), std::string::npos);
  EXPECT_NE(spawnError(w, at(0, 0, big)).find("position must be finite"), std::string::npos);
  EXPECT_NE(spawnError(w, at(0, 0, 1), Twist{Vec3(big, 0, 0), Vec3::Zero()})
                .find("linear twist must be finite and at most max_speed"),
            std::string::npos);
  EXPECT_NE(spawnError(w, at(0, 0, 1), Twist{Vec3::Zero(), Vec3(0, 0, big)}).find("angular twist"),
            std::string::npos);
  EXPECT_TRUE(w.creatureNames().empty());
}

TEST(Cells, TooManyAirCellsAreRefusedNamingTheCreatureAndLink) {
  WorldParams p;
  p.air.subdivisions_u = p.air.subdivisions_v = 1000;  // 6e6 cells per box: ~340 MB a link
  World w(p);
  EXPECT_EQ(spawnError(w, at(0, 0, 1)),
            "creature 'c' would have 18000000 air cells (link 'unit0_body' alone 6000000), over "
            "max_cells 200000 (boxes x 6 faces x subdivisions, plus cylinders', spheres' and "
            "meshes' cells)");
  EXPECT_TRUE(w.creatureNames().empty());

  World ok;
  ok.spawn("c", loadUrdf("flap_unit.urdf"), at(0, 0, 1));
  AirParams fine = ok.params().air;
  fine.subdivisions_u = fine.subdivisions_v = 1000;
  try {
    ok.setAirParams(fine);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("air change refused: creature 'c' would have"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(ok.params().air.subdivisions_u, 4);
}

TEST(AirNumbers, AbsurdAirAndSolverNumbersAreRefused) {
  World w;
  AirParams air = w.params().air;
  air.wind = Vec3(1e300, 0, 0);  // made every cell's force NaN
  EXPECT_THROW(w.setAirParams(air), InputError);
  air = w.params().air;
  air.density = 1e300;
  EXPECT_THROW(w.setAirParams(air), InputError);
  air = w.params().air;
  air.quasi_steady.lift_amplitude = 1e300;
  EXPECT_THROW(w.setAirParams(air), InputError);
  EXPECT_EQ(w.params().air.wind, Vec3::Zero());
  EXPECT_EQ(w.params().air.density, 1.204);
  EXPECT_EQ(w.params().air.quasi_steady.lift_amplitude, 1.58);
  EXPECT_EQ(modelError(flapUnitWith("<wing joint=\"unit0_wing_left_joint\"/>",
                                    "<wing joint=\"unit0_wing_left_joint\"/><aero "
                                    "link=\"unit0_body\" drag_coefficient=\"1e300\"/>")),
            "unit.urdf: <aero link='unit0_body'>: drag_coefficient must be in [0, 1000]");
  w.spawn("c", loadUrdf("flap_unit.urdf"), at(0, 0, 1));
  EXPECT_THROW(w.setJointVelocityTarget("c", "unit0_wing_left_joint", 1e300), InputError);
  WorldParams p;
  p.solver_iterations = 2000000000;  // Bullet's iterations: a step that never ends
  EXPECT_EQ(validateWorldParams(p), "solver_iterations must be in 1..1000");
}

// Duplicate joint names in a command: the last one won, silently.
TEST(WingCommands, AJointNamedTwiceIsRefused) {
  World w;
  w.spawn("c", loadUrdf("flap_unit.urdf"), at(0, 0, 1));
  const StrokeCommand a{10, 10, 0.5}, b{20, 20, 0.5};
  try {
    w.setWingCommands("c", {"unit0_wing_left_joint", "unit0_wing_left_joint"}, {a, b});
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "creature 'c': joint 'unit0_wing_left_joint' is named twice");
  }
  EXPECT_EQ(w.wingCommand("c", "unit0_wing_left_joint").downstroke_rate, 0.0);
  EXPECT_EQ(validateStroke(StrokeCommand{1e300, 10, 0.5}),
            "stroke rates must be at most 1e5 rad/s");
}

// A feather angle for a wing without a feather joint was ignored silently: refused by name,
// the wing's command kept; a wing with one (hover_1's) takes it.
TEST(WingCommands, AFeatherAngleForAWingThatCannotFeatherIsRefused) {
  World w;
  w.spawn("c", loadUrdf("flap_unit.urdf"), at(0, 0, 1));
  w.spawn("h", loadUrdf("hover_1.urdf"), at(2, 0, 1));
  StrokeCommand feathered{20, 20, 0.5};
  feathered.feather = 0.3;
  for (const char* joint : {"unit0_wing_left_joint", "unit0_wing_right_joint"}) {
    try {
      w.setWingCommands("c", {joint}, {feathered});
      ADD_FAILURE() << joint << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), std::string("creature 'c': joint '") + joint +
                                           "': a feather angle for a wing without a feather "
                                           "joint (<wing feather_joint=...>)");
    }
    EXPECT_EQ(w.wingCommand("c", joint).downstroke_rate, 0.0);
  }
  w.setWingCommands("h", {"wing_left_joint"}, {feathered});
  EXPECT_EQ(w.wingCommand("h", "wing_left_joint").feather, 0.3);
}

// A flap unit lying upside down on its wings, its wing motors told to stop them: with a
// velocity target of zero (what the node's `hold` did) the wings creep under the body's weight,
// since the contacts act after the servo; held (World::holdJoint, a servo towards the held
// angle) they stay put. Reference: the creep the same run measures without the hold.
TEST(WingCommands, AHeldWingDoesNotCreepUnderALoad) {
  double moved[2];
  for (int held = 0; held < 2; ++held) {
    WorldParams p;  // ground on
    World w(p);
    w.spawn("c", loadUrdf("flap_unit.urdf"),
            at(0, 0, 0.15, Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX()))));
    const std::vector<std::string> wings = {"unit0_wing_left_joint", "unit0_wing_right_joint"};
    for (const std::string& j : wings) {
      if (held) {
        w.holdJoint("c", j);
      } else {
        w.setJointVelocityTarget("c", j, 0.0);
      }
    }
    w.step(1000);  // fallen and lying on its wings
    const std::vector<double> start = w.state("c").joint_positions;
    w.step(2000);
    const std::vector<double> end = w.state("c").joint_positions;
    moved[held] = 0.0;
    for (const std::string& j : wings) {
      const int k = w.model("c")->findJoint(j);
      moved[held] = std::max(moved[held], std::abs(end[k] - start[k]));
    }
  }
  // Measured: 3.4e-4 rad in 2 s with a velocity target of zero, 3.4e-10 rad held.
  EXPECT_GT(moved[0], 1e-4) << "the load this test needs: a velocity target of zero creeps";
  EXPECT_LT(moved[1], 1e-6) << moved[0];
}

}  // namespace
}  // namespace flapsim
