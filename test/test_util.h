// Helpers shared by the core tests.
#pragma once

#include <string>
#include <vector>

#include "dynamics/momentum.h"
#include "flapsim/creature_model.h"
#include "flapsim/episode_evaluator.h"
#include "flapsim/world.h"

namespace flapsim {
namespace test {

inline std::string sourcePath(const std::string& relative) {
  return std::string(FLAPSIM_SOURCE_DIR) + "/" + relative;
}

// Evaluates the tasks one at a time in reverse order, on a runner of its own: as a farm would,
// answering in any order. Counts the tasks it evaluated.
class ReverseEvaluator : public EpisodeEvaluator {
 public:
  explicit ReverseEvaluator(const EvaluationSpec& spec) : runner_(spec) {}
  std::vector<double> evaluate(const std::vector<EpisodeTask>& tasks) override {
    std::vector<double> out(tasks.size());
    for (size_t i = tasks.size(); i-- > 0;) out[i] = runner_.evaluate(tasks[i]);
    tasks_ += static_cast<int>(tasks.size());
    batches_.emplace_back();
    for (const EpisodeTask& t : tasks) batches_.back().push_back(t.episode);
    return out;
  }
  int workersUp() const override { return 1; }
  int tasks_ = 0;
  std::vector<std::vector<int>> batches_;  // the episodes each batch asked for, in task order

 private:
  EpisodeRunner runner_;
};

// A tool's arguments `args` with `flag` given `values`: those it has there replaced, else the
// flag appended with them (the flag walks of test_evolve_flags and test_flight_check_flags).
inline std::vector<std::string> withFlag(std::vector<std::string> args, const std::string& flag,
                                         const std::vector<std::string>& values) {
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] != flag) continue;
    for (size_t k = 0; k < values.size(); ++k) args[i + 1 + k] = values[k];
    return args;
  }
  args.push_back(flag);
  args.insert(args.end(), values.begin(), values.end());
  return args;
}

inline CreatureModelPtr loadUrdf(const std::string& name) {
  return loadCreatureModel(sourcePath("urdf/" + name));
}

/// URDF text `urdf` with its link `root` fixed to the world (a test stand).
inline std::string anchoredUrdf(std::string urdf, const std::string& root) {
  urdf.insert(urdf.rfind("</robot>"),
              "<link name=\"world\"/><joint name=\"anchor\" type=\"fixed\"><parent "
              "link=\"world\"/><child link=\"" +
                  root + "\"/></joint>\n");
  return urdf;
}

/// A world without ground (so long falls are unobstructed) and default air.
inline WorldParams openSky() {
  WorldParams p;
  p.ground = false;
  return p;
}

/// openSky() without air.
inline WorldParams vacuum() {
  WorldParams p = openSky();
  p.air.enabled = false;
  return p;
}

/// A flap (10 g, COM 0.1 m from the hinge) on a fixed hinge of `type` about `axis`;
/// `joint_extra` goes inside the <joint>, `robot_extra` after it.
inline CreatureModelPtr flapOnHinge(const std::string& type, const std::string& axis,
                                    const std::string& joint_extra,
                                    const std::string& robot_extra = "") {
  return parseCreatureModel(R"(<robot name="h"><link name="world"/>
    <link name="flap"><inertial><origin xyz="0 0.1 0"/><mass value="0.01"/>
      <inertia ixx="3.4e-5" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="3.4e-5"/></inertial>
      <collision><origin xyz="0 0.1 0"/><geometry><box size="0.05 0.2 0.002"/></geometry></collision></link>
    <joint name="hinge" type=")" +
                            type + R"("><parent link="world"/><child link="flap"/>
      <axis xyz=")" + axis + R"("/>)" +
                            joint_extra + "</joint>" + robot_extra + "</robot>");
}

/// Inertia of flapOnHinge's flap about its hinge (x or z axis): own + m d^2.
constexpr double kFlapHingeInertia = 3.4e-5 + 0.01 * 0.1 * 0.1;

inline Pose at(double x, double y, double z, const Quat& q = Quat::Identity()) {
  return Pose{Vec3(x, y, z), q};
}

/// The bodies of a creature's state for systemMomentum(): each link's mass, COM velocity
/// and world-axes inertia.
inline std::vector<BodyMotion> bodyMotions(const CreatureModel& m, const CreatureState& s) {
  std::vector<BodyMotion> bodies;
  for (size_t k = 0; k < m.links.size(); ++k) {
    const LinkModel& l = m.links[k];
    const Pose frame = l.fromUrdf(s.link_poses[k]);  // the link frame (principal axes)
    const Mat3 r = frame.orientation.toRotationMatrix();
    BodyMotion b;
    b.mass = l.mass;
    b.com = frame.apply(l.com);
    b.inertia = r * l.inertia.asDiagonal() * r.transpose();
    b.angular_velocity = s.link_twists[k].angular;
    b.velocity = s.link_twists[k].linear + b.angular_velocity.cross(b.com - frame.position);
    bodies.push_back(b);
  }
  return bodies;
}

/// True when every number of the two states is identical to the bit.
inline bool bitIdentical(const CreatureState& a, const CreatureState& b) {
  if (a.link_poses.size() != b.link_poses.size()) return false;
  for (size_t i = 0; i < a.link_poses.size(); ++i) {
    if (a.link_poses[i].position != b.link_poses[i].position) return false;
    if (a.link_poses[i].orientation.coeffs() != b.link_poses[i].orientation.coeffs()) return false;
    if (a.link_twists[i].linear != b.link_twists[i].linear) return false;
    if (a.link_twists[i].angular != b.link_twists[i].angular) return false;
  }
  return a.joint_positions == b.joint_positions && a.joint_velocities == b.joint_velocities &&
         a.joint_efforts == b.joint_efforts;
}

}  // namespace test
}  // namespace flapsim
