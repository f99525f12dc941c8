#include "world/world_checks.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dynamics/servo_stage.h"
#include "flapsim/world.h"
#include "fluid/mesh_surface.h"
#include "fluid/surface.h"

namespace flapsim {

namespace {

bool inRange(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }
bool finiteWithin(const Vec3& v, double most) {
  return v.allFinite() && v.cwiseAbs().maxCoeff() <= most;
}
bool finiteNorm(const Vec3& v, double most) { return v.allFinite() && v.norm() <= most; }

// A rule: whether the argument passes, and the message if not (`message`, or what
// `describe` says of the value).
template <typename T>
struct Rule {
  bool (*ok)(const T&);
  const char* message;
  std::string (*describe)(const T&) = nullptr;
};

template <typename T, size_t N>
std::string firstFailure(const Rule<T> (&rules)[N], const T& value) {
  for (const Rule<T>& r : rules) {
    if (!r.ok(value)) return r.describe ? r.describe(value) : r.message;
  }
  return "";
}

const Rule<WorldParams> kWorldRules[] = {
    {[](const WorldParams& p) { return inRange(p.step_size, 1e-6, 0.1); },
     "step_size must be in [1e-6, 0.1] s"},
    // (Substeps shorter than 1e-7 s would cut a step into more pieces than an int counts.)
    {[](const WorldParams& p) {
       return p.turn_substep == 0.0 || (std::isfinite(p.turn_substep) && p.turn_substep >= 1e-7);
     },
     "turn_substep must be 0 (off) or finite and >= 1e-7 s"},
    {[](const WorldParams& p) { return finiteNorm(p.gravity, kMaxGravity); },
     "gravity must be finite and at most 1e4 m/s^2"},
    {[](const WorldParams& p) { return inRange(p.ground_friction, 0.0, 1e3); },
     "ground_friction must be in [0, 1000]"},
    {[](const WorldParams& p) { return p.solver_iterations >= 1 && p.solver_iterations <= 1000; },
     "solver_iterations must be in 1..1000"},
    {[](const WorldParams& p) { return p.threads >= 1 && p.threads <= 256; },
     "threads must be in 1..256"},
    {[](const WorldParams& p) {
       return inRange(p.default_wing_effort, 0.0, 1e9) && p.default_wing_effort > 0.0;
     },
     "default_wing_effort must be in (0, 1e9] N m"},
    {[](const WorldParams& p) { return p.max_cells >= 1; }, "max_cells must be >= 1"},
    {[](const WorldParams& p) { return inRange(p.max_speed, 0.0, 3e8) && p.max_speed > 0.0; },
     "max_speed must be in (0, 3e8] m/s"},
};

const Rule<AirParams> kAirRules[] = {
    {[](const AirParams& a) { return inRange(a.density, 0.0, kMaxDensity); },
     "air density must be in [0, 1e5] kg/m^3"},
    {[](const AirParams& a) { return finiteWithin(a.wind, 1e3); },
     "air wind must be finite, each component within +-1000 m/s"},
    {[](const AirParams& a) { return makeAirModel(a.model) != nullptr; }, nullptr,
     [](const AirParams& a) { return unknownAirModelMessage(a.model); }},
    // The parameters each law reads (the drag coefficient, the quasi-steady coefficients).
    {[](const AirParams& a) { return checkAirModels(a).empty(); }, nullptr,
     [](const AirParams& a) { return checkAirModels(a); }},
    {[](const AirParams& a) { return checkTurbulence(a.turbulence).empty(); }, nullptr,
     [](const AirParams& a) { return checkTurbulence(a.turbulence); }},
    {[](const AirParams& a) { return checkGust(a.gust).empty(); }, nullptr,
     [](const AirParams& a) { return checkGust(a.gust); }},
    {[](const AirParams& a) {
       return a.subdivisions_u >= 1 && a.subdivisions_v >= 1 && a.subdivisions_u <= 1000 &&
              a.subdivisions_v <= 1000;
     },
     "air subdivisions must be in 1..1000"},
};

const Rule<ExternalWrench> kWrenchRules[] = {
    {[](const ExternalWrench& w) { return finiteNorm(w.force, kMaxForce); },
     "force must be finite and at most 1e6 N"},
    {[](const ExternalWrench& w) { return finiteNorm(w.torque, kMaxTorque); },
     "torque must be finite and at most 1e6 N m"},
    {[](const ExternalWrench& w) { return finiteWithin(w.point, kMaxPosition); },
     "point must be finite, each coordinate within +-1e6 m"},
    {[](const ExternalWrench& w) {
       return std::isfinite(w.duration) && w.duration <= kMaxWrenchDuration;
     },
     "duration must be finite and at most 1e9 s (< 0: until cleared)"},
    {[](const ExternalWrench& w) {
       return std::isfinite(w.start_time) && std::abs(w.start_time) <= kMaxWrenchDuration;
     },
     "start_time must be finite and within +-1e9 s (s of sim time; 0: the next step)"},
};

}  // namespace

std::string validateWorldParams(const WorldParams& p) {
  const std::string err = firstFailure(kWorldRules, p);
  return err.empty() ? checkAir(p.air) : err;
}

std::string checkAir(const AirParams& a) { return firstFailure(kAirRules, a); }

std::string checkGravity(const Vec3& gravity) {
  return finiteNorm(gravity, kMaxGravity) ? "" : "gravity must be finite and at most 1e4 m/s^2";
}

std::string checkPose(const Pose& pose) {
  if (!finiteWithin(pose.position, kMaxPosition)) {
    return "position must be finite, each coordinate within +-1e6 m";
  }
  const double norm = pose.orientation.coeffs().allFinite() ? pose.orientation.norm() : NAN;
  if (!(norm >= 1e-6 && norm <= 1e6)) {
    std::ostringstream msg;
    msg << "orientation quaternion has norm " << norm
        << " (must be finite and between 1e-6 and 1e6; it is normalised)";
    return msg.str();
  }
  return "";
}

std::string checkTwist(const Twist& twist, double max_speed) {
  if (!finiteNorm(twist.linear, max_speed)) {
    return "linear twist must be finite and at most max_speed (" + std::to_string(max_speed) +
           " m/s)";
  }
  if (!finiteNorm(twist.angular, kMaxSpin)) {
    return "angular twist must be finite and at most 1e5 rad/s";
  }
  return "";
}

std::string checkJointValues(const CreatureModel& m, const std::vector<double>& values,
                             const std::string& what, bool positions) {
  if (values.empty()) return "";
  if (values.size() != m.joints.size()) {
    return std::to_string(values.size()) + " " + what + " for " + std::to_string(m.joints.size()) +
           " joints (give one per joint, in URDF order, or none)";
  }
  for (size_t j = 0; j < values.size(); ++j) {
    const JointModel& joint = m.joints[j];
    std::ostringstream msg;
    msg << "joint '" << joint.name << "': " << what << " " << values[j];
    if (!std::isfinite(values[j])) return msg.str() + " is not finite";
    if (!joint.movable()) {
      if (values[j] != 0.0) return msg.str() + " must be 0 (a fixed joint)";
      continue;
    }
    if (!positions) {
      if (std::abs(values[j]) > kMaxSpin) return msg.str() + " is beyond +-1e5";
    } else if (joint.limited && joint.lower < joint.upper &&
               (values[j] < joint.lower || values[j] > joint.upper)) {
      msg << " is outside its limits [" << joint.lower << ", " << joint.upper << "]";
      return msg.str();
    } else if (std::abs(values[j]) > kMaxPosition) {
      return msg.str() + " is beyond +-1e6";
    }
  }
  return "";
}

std::string checkWrench(const ExternalWrench& wrench) { return firstFailure(kWrenchRules, wrench); }

std::string checkCells(const std::string& name, const CreatureModel& m, const AirParams& air,
                       int max_cells) {
  double total = 0.0, largest = 0.0;
  std::string largest_link;
  for (const LinkModel& l : m.links) {
    if (!l.aero.enabled || !l.hasShapes()) continue;
    const int nu = subdivisionsU(l, air), nv = subdivisionsV(l, air);
    double cells = 6.0 * static_cast<double>(l.boxes.size()) * nu * nv;
    for (const RoundShape& r : l.rounds) cells += roundCellCount(r, nu, nv);
    for (const MeshShape& mesh : l.meshes) cells += meshCellCount(*mesh.mesh, nu, nv);
    total += cells;
    if (cells > largest) {
      largest = cells;
      largest_link = l.name;
    }
  }
  if (total <= max_cells) return "";
  std::ostringstream msg;
  msg.precision(10);
  msg << "creature '" << name << "' would have " << total << " air cells (link '" << largest_link
      << "' alone " << largest << "), over max_cells " << max_cells
      << " (boxes x 6 faces x subdivisions, plus cylinders', spheres' and meshes' cells)";
  return msg.str();
}

std::vector<int> checkWingCommands(const CreatureModel& model,
                                   const std::vector<std::string>& joints,
                                   const std::vector<StrokeCommand>& commands) {
  std::vector<int> targets;
  if (joints.empty()) {
    targets = model.wing_joints;
  } else {
    for (const std::string& name : joints) {
      const int j = model.findJoint(name);
      if (j < 0) throw InputError("no joint '" + name + "'");
      if (!model.joints[j].wing) throw InputError("joint '" + name + "' is not a wing joint");
      if (std::find(targets.begin(), targets.end(), j) != targets.end()) {
        throw InputError("joint '" + name + "' is named twice");
      }
      targets.push_back(j);
    }
  }
  if (targets.size() != commands.size()) {
    throw InputError(std::to_string(commands.size()) + " commands for " +
                     std::to_string(targets.size()) + " wing joints");
  }
  for (size_t i = 0; i < commands.size(); ++i) {
    const JointModel& j = model.joints[targets[i]];
    const std::string err = validateStroke(commands[i]);
    if (!err.empty()) throw InputError("joint '" + j.name + "': " + err);
    // A feather angle was ignored silently on a wing that cannot feather.
    if ((commands[i].feather != 0.0 || commands[i].downstroke_feather != 0.0) &&
        j.feather_joint < 0) {
      throw InputError("joint '" + j.name +
                       "': a feather angle for a wing without a feather joint (<wing "
                       "feather_joint=...>)");
    }
    // The stroke turns where the wing reaches offset -+ amplitude: beyond a limit the wing
    // would rest on its stop with the motor pushing, and never turn.
    const double amplitude = commands[i].amplitude, offset = commands[i].offset;
    if (j.limited && j.lower < j.upper &&
        (offset + amplitude >= j.upper || offset - amplitude <= j.lower)) {
      std::ostringstream msg;
      msg << "joint '" << j.name << "': amplitude " << amplitude;
      if (offset != 0.0) msg << " about offset " << offset;
      msg << " rad does not fit inside its limits [" << j.lower << ", " << j.upper << "]";
      throw InputError(msg.str());
    }
  }
  return targets;
}

WorldParams checked(const WorldParams& p) {
  std::string err = validateWorldParams(p);
  if (!err.empty()) throw InputError(err);
  return p;
}

void refuse(const std::string& name, const std::string& err) {
  if (!err.empty()) throw InputError("creature '" + name + "': " + err);
}

std::vector<std::string> implicitJointValues(const CreatureModel& model, double step_size) {
  std::vector<std::string> out;
  auto note = [&](const JointModel& j, const char* what, double value, double limit) {
    std::ostringstream line;
    line.precision(4);
    line << "joint '" << j.name << "': " << what << " " << value
         << " is more than an explicit step of " << step_size << " s keeps stable (" << limit
         << "): it acts implicitly, its motion faster than the step damped out";
    out.push_back(line.str());
  };
  for (const JointModel& j : model.joints) {
    if (!j.movable() || !implicitJoint(model, j, step_size)) continue;
    const double damping = dampingLimit(model, j, step_size);
    const double stiffness = stiffnessLimit(model, j, step_size);
    if (j.damping > damping) note(j, "damping", j.damping, damping);
    if (j.stiffness > stiffness) note(j, "spring stiffness", j.stiffness, stiffness);
  }
  return out;
}

}  // namespace flapsim
