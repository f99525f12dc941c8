// Golden trajectories: a handful of scenarios that between them run every stage of a step
// (strokes and their turns in substeps, velocity targets, feathering, passive springs, the
// pressure and quasi-steady air models, buoyancy, added mass in water, implicit drag (in
// water without added mass), contact with the ground, external wrenches, the momentum
// balance, the lean step, threads, the evolved controller with sensor noise and a wind step)
// are compared to the bit with the trajectories stored in test/golden/. A refactoring that
// changes no physics passes; any change of a result, however small, fails and prints the
// largest difference.
//
// A change of the physics made on purpose regenerates the files:
//   FLAPSIM_UPDATE_GOLDEN=1 build/devel/lib/flapsim/test_golden
// and says why in its commit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"
#include "flapsim/make_creature.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::loadUrdf;
using test::sourcePath;

// A trajectory: one line per sample, each a label and numbers.
struct Trajectory {
  std::vector<std::string> labels;
  std::vector<std::vector<double>> rows;

  void add(const std::string& label, std::vector<double> row) {
    labels.push_back(label);
    rows.push_back(std::move(row));
  }
};

std::string hexDouble(double x) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%a", x);
  return buf;
}

std::string toText(const Trajectory& t) {
  std::ostringstream out;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    out << t.labels[i];
    for (double x : t.rows[i]) out << " " << hexDouble(x);
    out << "\n";
  }
  return out.str();
}

Trajectory fromText(const std::string& text) {
  Trajectory t;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string label, word;
    l >> label;
    std::vector<double> row;
    while (l >> word) row.push_back(std::strtod(word.c_str(), nullptr));
    t.add(label, row);
  }
  return t;
}

// Root pose and twist, then every joint's position, velocity and effort.
std::vector<double> stateRow(const World& w, const std::string& creature) {
  const CreatureState s = w.state(creature);
  std::vector<double> row;
  const Pose& p = s.link_poses[0];
  const Twist& v = s.link_twists[0];
  for (int i = 0; i < 3; ++i) row.push_back(p.position[i]);
  for (int i = 0; i < 4; ++i) row.push_back(p.orientation.coeffs()[i]);
  for (int i = 0; i < 3; ++i) row.push_back(v.linear[i]);
  for (int i = 0; i < 3; ++i) row.push_back(v.angular[i]);
  for (size_t j = 0; j < s.joint_positions.size(); ++j) {
    row.push_back(s.joint_positions[j]);
    row.push_back(s.joint_velocities[j]);
    row.push_back(s.joint_efforts[j]);
  }
  return row;
}

// Steps `w` for `steps` steps, sampling every creature every `every` steps.
Trajectory record(World& w, int steps, int every) {
  Trajectory t;
  for (int s = every; s <= steps; s += every) {
    w.step(every);
    for (const std::string& name : w.creatureNames()) {
      t.add(name + "@" + std::to_string(s), stateRow(w, name));
    }
  }
  return t;
}

std::vector<StrokeCommand> strokes(const CreatureModel& m, double down, double up, double amp,
                                   double feather = 0.0) {
  return std::vector<StrokeCommand>(m.wing_joints.size(), {down, up, amp, feather});
}

// Compares with test/golden/<name>.txt, or writes it with FLAPSIM_UPDATE_GOLDEN=1.
void expectGolden(const std::string& name, const Trajectory& actual) {
  const std::string path = sourcePath("test/golden/" + name + ".txt");
  if (std::getenv("FLAPSIM_UPDATE_GOLDEN") != nullptr) {
    std::ofstream(path) << toText(actual);
    GTEST_SKIP() << "wrote " << path;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in.good()) << "no golden file " << path;
  std::stringstream text;
  text << in.rdbuf();
  const Trajectory golden = fromText(text.str());
  ASSERT_EQ(golden.rows.size(), actual.rows.size()) << name << ": number of samples";
  size_t differing = 0;
  double largest = 0.0;
  std::string first;
  for (size_t i = 0; i < golden.rows.size(); ++i) {
    ASSERT_EQ(golden.labels[i], actual.labels[i]) << name << ": sample " << i;
    ASSERT_EQ(golden.rows[i].size(), actual.rows[i].size()) << name << ": " << golden.labels[i];
    for (size_t k = 0; k < golden.rows[i].size(); ++k) {
      const double a = golden.rows[i][k], b = actual.rows[i][k];
      if (std::memcmp(&a, &b, sizeof(double)) == 0) continue;
      ++differing;
      largest = std::max(largest, std::abs(a - b));
      if (first.empty()) {
        first = golden.labels[i] + " value " + std::to_string(k) + ": " + hexDouble(a) + " now " +
                hexDouble(b);
      }
    }
  }
  EXPECT_EQ(differing, 0u) << name << ": " << differing << " numbers differ from " << path
                           << ", the largest by " << largest << "; first: " << first;
}

// A 12-unit chain stroking 30/10/0.8 high in the air (the benchmark's chain_12): 2 s.
TEST(Golden, Chain12StrokingTwoSeconds) {
  const CreatureModelPtr m = parseCreatureModel(makeCreatureUrdf(12, "chain_12"));
  World w;
  w.spawn("c", m, Pose{Vec3(0, 0, 50), Quat::Identity()});
  w.setWingCommands("c", {}, strokes(*m, 30.0, 10.0, 0.8));
  expectGolden("chain_12", record(w, 2000, 100));
}

// The flap unit of the demo (60/10/0.8) from the ground, at 1 and at 0.5 ms: 2 s.
TEST(Golden, FlapUnitClimbingTwoSeconds) {
  const CreatureModelPtr m = loadUrdf("flap_unit.urdf");
  for (double dt : {0.001, 0.0005}) {
    WorldParams p;
    p.step_size = dt;
    World w(p);
    w.spawn("fu", m, Pose{Vec3(0, 0, 0.3), Quat::Identity()});
    w.setWingCommands("fu", {}, strokes(*m, 60.0, 10.0, 0.8));
    const int steps = static_cast<int>(std::lround(2.0 / dt));
    expectGolden(dt == 0.001 ? "flap_unit_1ms" : "flap_unit_05ms", record(w, steps, steps / 20));
  }
}

// The swimmer in water (swim.launch): buoyancy, added mass, implicit drag: 2 s.
TEST(Golden, SwimmerInWaterTwoSeconds) {
  const CreatureModelPtr m = loadUrdf("swimmer.urdf");
  WorldParams p;
  p.air = waterParams();
  World w(p);
  w.spawn("swimmer", m, Pose{Vec3(0, 0, 2.0), Quat::Identity()});
  w.setWingCommands("swimmer", {}, strokes(*m, 3.0, 1.0, 0.8));
  expectGolden("swimmer", record(w, 2000, 100));
  // Without added mass its plates' drag is stiff at 1 ms (in about one step in eight): the
  // implicit drag, which the carried water (175 times a plate's mass) makes unnecessary above.
  p.air.added_mass = false;
  World bare(p);
  bare.spawn("swimmer", m, Pose{Vec3(0, 0, 2.0), Quat::Identity()});
  bare.setWingCommands("swimmer", {}, strokes(*m, 3.0, 1.0, 0.8));
  expectGolden("swimmer_implicit_drag", record(bare, 2000, 100));
}

// The feathering unit (feather.launch, 1.2 rad) and the flap unit under the quasi-steady
// model with a side wind: 2 s each.
TEST(Golden, FeatherAndQuasiSteadyTwoSeconds) {
  const CreatureModelPtr feather = loadUrdf("feather_unit.urdf");
  World w;
  w.spawn("feather_unit", feather, Pose{Vec3(0, 0, 5.0), Quat::Identity()});
  w.setWingCommands("feather_unit", {}, strokes(*feather, 30.0, 10.0, 0.8, 1.2));
  expectGolden("feather", record(w, 2000, 100));

  WorldParams p;
  p.air.model = "quasi_steady";
  p.air.wind = Vec3(0.0, 1.0, 0.0);
  World q(p);
  const CreatureModelPtr fu = loadUrdf("flap_unit.urdf");
  q.spawn("fu", fu, Pose{Vec3(0, 0, 5.0), Quat(Eigen::AngleAxisd(0.1, Vec3::UnitX()))});
  q.setWingCommands("fu", {}, strokes(*fu, 40.0, 10.0, 0.8));
  expectGolden("quasi_steady", record(q, 2000, 100));
}

// Contact, wrenches, velocity targets, springs and threads: a tilted plate lands, a flap
// unit is pushed while one wing holds a velocity target, the bamboo copter spins, two
// threads step them: 1.5 s.
TEST(Golden, ContactWrenchesAndThreads) {
  WorldParams p;
  p.threads = 2;
  World w(p);
  w.spawn("plate", loadUrdf("plate.urdf"),
          Pose{Vec3(0, 0, 0.4), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()))});
  const CreatureModelPtr fu = loadUrdf("flap_unit.urdf");
  w.spawn("fu", fu, Pose{Vec3(3, 0, 2.0), Quat::Identity()});
  w.setWingCommands("fu", {}, strokes(*fu, 40.0, 10.0, 0.8));
  w.setJointVelocityTarget("fu", fu->joints[fu->wing_joints[0]].name, 2.0);
  ExternalWrench push;
  push.force = Vec3(0.5, 0.2, 1.0);
  push.torque = Vec3(0.0, 0.01, 0.0);
  push.point = Vec3(3.0, 0.05, 2.0);
  push.duration = 0.3;
  w.applyWrench("fu", push);
  Twist spin;
  spin.angular = Vec3(0, 0, 150);
  w.spawn("copter", loadUrdf("bamboo_copter.urdf"), Pose{Vec3(-3, 0, 1.0), Quat::Identity()}, spin);
  w.spawn("afc", loadUrdf("afc_4.urdf"), Pose{Vec3(0, 3, 1.0), Quat::Identity()});
  expectGolden("contact_wrench_threads", record(w, 1500, 75));
}

// afc_1 under its evolved network through an episode of the robust preset (start attitude
// and rate, sensor noise, a wind step, a drawn step size): 3 s, each sample's height,
// up-component and commanded rates.
TEST(Golden, EvolvedControllerEpisode) {
  const ControllerSpec spec = loadControllerYaml(sourcePath("config/afc_1_weights.yaml"));
  const AnnWingController ann(FlapUnitController(spec.params, spec.weights));
  // The robust episodes of the controller's evolution, spelled out (the preset moves on).
  EvolveParams e;
  e.episode.duration = 3.0;
  e.episode.seed = 7;
  e.episode.episodes = 2;
  e.episode.min_roll = 0.0;
  e.episode.max_roll = 0.35;
  e.episode.max_pitch = 0.35;
  e.episode.max_start_rate = 1.0;
  e.episode.max_gust = 1.0;
  e.episode.imu_noise.orientation = 0.02;
  e.episode.step_sizes = {0.001, 0.0005};
  e.episode.flip_penalty = 20.0;
  const CreatureModelPtr m = loadUrdf("afc_1.urdf");
  Trajectory t;
  const std::vector<EpisodeStart> starts = episodeStarts(e.episode);
  for (size_t k = 0; k < starts.size(); ++k) {
    const EpisodeResult r =
        runEpisode(m, ann, spec.params.control_period, e.episode, starts[k], true);
    for (size_t i = 0; i < r.trace.size(); i += 10) {
      std::vector<double> row{r.trace[i].time, r.trace[i].height, r.trace[i].upright};
      row.insert(row.end(), r.trace[i].downstroke.begin(), r.trace[i].downstroke.end());
      t.add("episode" + std::to_string(k) + "@" + std::to_string(i), row);
    }
    t.add("episode" + std::to_string(k) + "_fitness", {r.fitness, r.final_height});
  }
  expectGolden("afc_1_episode", t);
}

}  // namespace
}  // namespace flapsim
