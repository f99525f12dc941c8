#include "flapsim_ros/param_schema.h"

#include <cmath>
#include <stdexcept>

#include "flapsim_ros/param_reader.h"

namespace flapsim_ros {

namespace {

using T = ParamType;

// One row per parameter, in the order of doc/ros_interface.md's table.
const std::vector<ParamSpec> kSchema = {
    {"step_size", T::kDouble, "0.001", "[1e-6, 0.1]", "s", "fixed step", ""},
    {"turn_substep", T::kDouble, "0.0005", "[0, inf)", "s",
     "longest substep while a wing's stroke turns (0: no substeps)", ""},
    {"publish_rate", T::kDouble, "100.0", "[0.01, 1e6]", "Hz",
     "of sim time, rounded to whole steps", "publish_rate"},
    {"real_time_factor", T::kDouble, "1.0", "[0, 1e6]", "",
     "sim s per wall s; 0 = as fast as possible, else at least 0.001", "real_time_factor"},
    {"max_speed", T::kDouble, "1000.0", "(0, 3e8]", "m/s",
     "the watchdog freezes a creature with a link point faster", ""},
    {"max_cells", T::kInt, "200000", "[1, inf)", "", "air cells a creature may have", ""},
    {"motor_work", T::kString, "transmitted", "transmitted|servo", "",
     "how the motors' work and power are taken (flapsim/power; transmitted: in vacuum and "
     "with the added mass's velocity products)",
     ""},
    {"max_steps_per_call", T::kInt, "100000", "[1, inf)", "",
     "flapsim/step requests for more steps are refused", ""},
    {"urdf_roots", T::kStrings, "\"\"", "", "",
     "where flapsim/spawn may read urdf_file (\"\": ROS_PACKAGE_PATH, working directory)", ""},
    {"wing_command_timeout", T::kDouble, "0.0", "[0, 1e6]", "s",
     "of sim time without a wing command after which the wings stop (0: never)", ""},
    {"controller_wait_timeout", T::kDouble, "30.0", "[0, 1e6]", "s",
     "of wall time sim time holds for a creature's controller (0: no wait)", ""},
    {"wing_command_timeout_action", T::kString, "hold", "hold|release", "",
     "what the wings do on a timeout", ""},
    {"view/distance", T::kDouble, "2.5", "(0, 1e4]", "m",
     "least distance of flapsim/camera from flapsim/view", ""},
    {"view/yaw", T::kDouble, "0.8", "[-1e3, 1e3]", "rad", "camera direction about world z", ""},
    {"view/pitch", T::kDouble, "0.35", "(-1.5707963267948966, 1.5707963267948966)", "rad",
     "camera direction above the horizontal", ""},
    {"paused", T::kBool, "false", "", "", "start paused", ""},
    {"world_frame", T::kString, "world", "", "", "the fixed frame", ""},
    {"gravity", T::kVec3, "[0.0, 0.0, -9.81]", "[-1e4, 1e4]", "m/s^2",
     "world frame; its norm at most 1e4", "gravity_x gravity_y gravity_z"},
    {"ground", T::kBool, "true", "", "", "plane z = 0 with contact", ""},
    {"ground_friction", T::kDouble, "0.8", "[0, 1e3]", "", "friction of the ground", ""},
    {"solver_iterations", T::kInt, "10", "[1, 1000]", "", "Bullet's solver iterations", ""},
    {"threads", T::kInt, "1", "[1, 256]", "", "creatures stepped in parallel", ""},
    {"default_wing_effort", T::kDouble, "5.0", "(0, 1e9]", "N m",
     "wing joints without a URDF effort limit", ""},
    {"air/density", T::kDouble, "1.204", "[0, 1e5]", "kg/m^3", "1000 for water", "density"},
    {"air/drag_coefficient", T::kDouble, "1.15", "[0, 1e3]", "", "Cd of every face",
     "drag_coefficient"},
    {"air/wind", T::kVec3, "[0.0, 0.0, 0.0]", "[-1e3, 1e3]", "m/s", "steady wind, world frame",
     "wind_x wind_y wind_z"},
    {"air/turbulence/level", T::kString, "none", "none|light|moderate|severe", "",
     "Dryden turbulence level (or wind_at_6m, not both)", ""},
    {"air/turbulence/wind_at_6m", T::kDouble, "0.0", "[0, 100]", "m/s",
     "Dryden turbulence's W20 (or level, not both)", "", false},
    {"air/turbulence/height", T::kDouble, "5.0", "[3.048, 304.8]", "m",
     "height of the turbulence's intensities and scale lengths", ""},
    {"air/turbulence/per_creature", T::kBool, "false", "", "", "each creature its own turbulence",
     ""},
    {"air/turbulence/frozen", T::kBool, "false", "", "",
     "Taylor's frozen field; false: the air mass decorrelates over Hanna's Lagrangian time", ""},
    {"air/turbulence/seed", T::kInt, "0", "[0, inf)", "", "seed of the turbulence", ""},
    {"air/gust/velocity", T::kVec3, "[0.0, 0.0, 0.0]", "[-1e3, 1e3]", "m/s",
     "the 1-cosine gust's peak, world frame", ""},
    {"air/gust/start", T::kDouble, "0.0", "[0, inf)", "s", "the gust's start, sim time", ""},
    {"air/gust/rise", T::kDouble, "1.0", "(0, 1e6]", "s", "the gust's rise", ""},
    {"air/gust/hold", T::kDouble, "-1.0", "(-inf, 1e9]", "s", "the gust's hold (< 0: stays)", ""},
    {"air/buoyancy", T::kBool, "true", "", "", "buoyancy of every link", ""},
    {"air/enabled", T::kBool, "true", "", "", "air forces at all", ""},
    {"air/added_mass", T::kBool, "true", "", "", "added mass of plates, implicit", ""},
    {"air/added_mass_products", T::kString, "shed", "shed|kirchhoff|omitted", "",
     "what the added mass does beyond -A dnu: its velocity products shed into the wake (each "
     "plate -A dnu/dt), Kirchhoff's equations, or omitted (energy does not balance)",
     ""},
    {"air/rotational_lift", T::kBool, "true", "", "",
     "quasi_steady: rotational lift (Sane & Dickinson 2002)", ""},
    {"air/centre_of_pressure_shift", T::kBool, "true", "", "",
     "quasi_steady: the centre of pressure moves with the angle of attack (Whitney & Wood 2010)",
     ""},
    {"air/subdivisions", T::kIntPair, "[4, 4]", "[1, 1000]", "", "cells per face edge (nu, nv)",
     ""},
    {"air/model", T::kString, "pressure", "pressure|quasi_steady", "", "the air force law", ""},
    {"air/quasi_steady/lift_mean", T::kDouble, "0.225", "", "", "quasi_steady: C_L's mean", ""},
    {"air/quasi_steady/lift_amplitude", T::kDouble, "1.58", "", "", "quasi_steady: C_L's amplitude",
     ""},
    {"air/quasi_steady/lift_frequency", T::kDouble, "2.13", "", "",
     "quasi_steady: C_L's frequency in alpha", ""},
    {"air/quasi_steady/lift_phase", T::kDouble, "-7.20", "", "rad", "quasi_steady: C_L's phase",
     ""},
    {"air/quasi_steady/drag_mean", T::kDouble, "1.92", "", "", "quasi_steady: C_D's mean", ""},
    {"air/quasi_steady/drag_amplitude", T::kDouble, "1.55", "", "", "quasi_steady: C_D's amplitude",
     ""},
    {"air/quasi_steady/drag_frequency", T::kDouble, "2.04", "", "",
     "quasi_steady: C_D's frequency in alpha", ""},
    {"air/quasi_steady/drag_phase", T::kDouble, "-9.82", "", "rad", "quasi_steady: C_D's phase",
     ""},
    {"markers/enabled", T::kBool, "true", "", "", "force arrows on ~aero_markers", "show_markers"},
    {"markers/scale", T::kDouble, "2.0", "[0, inf)", "m/N", "arrow length per force", ""},
    {"markers/per_cell", T::kBool, "false", "", "", "also one arrow per surface cell", ""},
    {"markers/width", T::kDouble, "0.012", "(0, inf)", "m", "arrow shaft diameter", ""},
    {"imu/orientation_noise", T::kDouble, "0.0", "[0, 1e3]", "rad",
     "standard deviation of the IMU's orientation noise", ""},
    {"imu/angular_velocity_noise", T::kDouble, "0.0", "[0, 1e3]", "rad/s",
     "standard deviation of the IMU's angular velocity noise", ""},
    {"imu/linear_acceleration_noise", T::kDouble, "0.0", "[0, 1e3]", "m/s^2",
     "standard deviation of the IMU's acceleration noise", ""},
    {"imu/seed", T::kInt, "0", "", "", "seed of the IMU's noise", ""},
    {"creatures", T::kList, "[]", "", "", "the creatures spawned at start-up", "", false},
};

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

}  // namespace

const std::vector<ParamSpec>& nodeParamSchema() { return kSchema; }

const ParamSpec& paramSpec(const std::string& name) {
  for (const ParamSpec& s : kSchema) {
    if (name == s.name) return s;
  }
  throw std::out_of_range("no parameter '" + name + "' in the schema");
}

bool ParamRange::contains(double x) const {
  if (std::isnan(x)) return false;
  return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
}

ParamRange parseParamRange(const std::string& range) {
  const size_t comma = range.find(',');
  if (range.size() < 5 || comma == std::string::npos ||
      (range.front() != '[' && range.front() != '(') ||
      (range.back() != ']' && range.back() != ')')) {
    throw std::invalid_argument("not a range: '" + range + "'");
  }
  ParamRange r;
  r.lo = std::stod(trim(range.substr(1, comma - 1)));
  r.hi = std::stod(trim(range.substr(comma + 1, range.size() - comma - 2)));
  r.lo_open = range.front() == '(';
  r.hi_open = range.back() == ')';
  return r;
}

void requireInRange(const std::string& name, double value, const std::string& key) {
  const ParamSpec& s = paramSpec(name);
  if (parseParamRange(s.range).contains(value)) return;
  const std::string unit = *s.unit ? std::string(" ") + s.unit : "";
  failParam(key.empty() ? name : key, std::string("must be in ") + s.range + unit);
}

}  // namespace flapsim_ros
