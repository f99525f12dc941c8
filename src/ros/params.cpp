#include "flapsim_ros/params.h"

#include <limits.h>
#include <ros/param.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "flapsim/air_model.h"
#include "flapsim_ros/param_schema.h"
#include "flapsim_ros/urdf_source.h"

namespace flapsim_ros {

namespace {

using XmlRpc::XmlRpcValue;

std::string typeName(const XmlRpcValue& v) { return paramTypeName(v); }

[[noreturn]] void fail(const std::string& key, const std::string& what) { failParam(key, what); }

using Dict = ParamReader;

// air/turbulence: a named level or the wind at 6 m, the height, shared or per creature, seed.
flapsim::TurbulenceParams parseTurbulence(const Dict& d) {
  flapsim::TurbulenceParams t;
  if (d.has("level") && d.has("wind_at_6m")) {
    fail(d.key("level"), "give a level or wind_at_6m, not both");
  }
  if (d.has("level")) {
    try {
      t.wind_at_6m = flapsim::turbulenceLevelWind(d.string("level", ""));
    } catch (const flapsim::InputError& e) {
      fail(d.key("level"), e.what());
    }
  }
  t.wind_at_6m = d.number("wind_at_6m", t.wind_at_6m);
  t.height = d.number("height", t.height);
  t.per_creature = d.boolean("per_creature", t.per_creature);
  t.frozen = d.boolean("frozen", t.frozen);
  const int seed = d.integer("seed", 0);
  if (seed < 0) fail(d.key("seed"), "must be >= 0");
  t.seed = static_cast<std::uint64_t>(seed);
  const std::string err = flapsim::checkTurbulence(t);
  if (!err.empty()) fail(d.name(), err);
  d.rejectUnknown();
  return t;
}

// air/gust: the discrete 1-cosine gust.
flapsim::DiscreteGust parseGust(const Dict& d) {
  flapsim::DiscreteGust g;
  g.velocity = d.vec3("velocity", g.velocity);
  g.start = d.number("start", g.start);
  g.rise = d.number("rise", g.rise);
  g.hold = d.number("hold", g.hold);
  const std::string err = flapsim::checkGust(g);
  if (!err.empty()) fail(d.name(), err);
  d.rejectUnknown();
  return g;
}

flapsim::AirParams parseAir(const Dict& d, flapsim::AirParams air) {
  air.density = d.number("density", air.density);
  air.drag_coefficient = d.number("drag_coefficient", air.drag_coefficient);
  air.wind = d.vec3("wind", air.wind);
  air.buoyancy = d.boolean("buoyancy", air.buoyancy);
  air.added_mass = d.boolean("added_mass", air.added_mass);
  for (const char* old : {"added_mass_velocity_products", "added_mass_shed_products"}) {
    if (d.has(old)) {
      fail(d.key(old),
           "replaced by air/added_mass_products (shed, the default; kirchhoff; or "
           "omitted, the air before December 2026)");
    }
  }
  if (d.has("added_mass_products")) {
    try {
      air.added_mass_products = flapsim::parseAddedMassProducts(
          d.string("added_mass_products", flapsim::addedMassProductsName(air.added_mass_products)));
    } catch (const flapsim::InputError& e) {
      fail(d.key("added_mass_products"), e.what());
    }
  }
  air.rotational_lift = d.boolean("rotational_lift", air.rotational_lift);
  air.centre_of_pressure_shift =
      d.boolean("centre_of_pressure_shift", air.centre_of_pressure_shift);
  air.enabled = d.boolean("enabled", air.enabled);
  air.model = d.string("model", air.model);
  if (!flapsim::makeAirModel(air.model)) {
    fail(d.key("model"), flapsim::unknownAirModelMessage(air.model));
  }
  if (d.has("quasi_steady")) {
    Dict q(d.at("quasi_steady"), d.key("quasi_steady"));
    flapsim::QuasiSteadyCoefficients& c = air.quasi_steady;
    c.lift_mean = q.number("lift_mean", c.lift_mean);
    c.lift_amplitude = q.number("lift_amplitude", c.lift_amplitude);
    c.lift_frequency = q.number("lift_frequency", c.lift_frequency);
    c.lift_phase = q.number("lift_phase", c.lift_phase);
    c.drag_mean = q.number("drag_mean", c.drag_mean);
    c.drag_amplitude = q.number("drag_amplitude", c.drag_amplitude);
    c.drag_frequency = q.number("drag_frequency", c.drag_frequency);
    c.drag_phase = q.number("drag_phase", c.drag_phase);
    q.rejectUnknown();
  }
  if (d.has("turbulence")) {
    air.turbulence = parseTurbulence(Dict(d.at("turbulence"), d.key("turbulence")));
  }
  if (d.has("gust")) air.gust = parseGust(Dict(d.at("gust"), d.key("gust")));
  if (d.has("subdivisions")) {
    std::vector<double> s = d.numbers("subdivisions");
    if (s.size() != 2 || s[0] != std::floor(s[0]) || s[1] != std::floor(s[1])) {
      fail(d.key("subdivisions"), "must be two integers [nu, nv]");
    }
    air.subdivisions_u = static_cast<int>(s[0]);
    air.subdivisions_v = static_cast<int>(s[1]);
  }
  d.rejectUnknown();
  return air;
}

MarkerParams parseMarkers(const Dict& d, MarkerParams m) {
  m.enabled = d.boolean("enabled", m.enabled);
  m.scale = d.number("scale", m.scale);
  m.per_cell = d.boolean("per_cell", m.per_cell);
  m.width = d.number("width", m.width);
  requireInRange("markers/scale", m.scale, d.key("scale"));
  requireInRange("markers/width", m.width, d.key("width"));
  d.rejectUnknown();
  return m;
}

ImuParams parseImu(const Dict& d, ImuParams m) {
  m.orientation_noise = d.number("orientation_noise", m.orientation_noise);
  m.angular_velocity_noise = d.number("angular_velocity_noise", m.angular_velocity_noise);
  m.linear_acceleration_noise = d.number("linear_acceleration_noise", m.linear_acceleration_noise);
  m.seed = d.integer("seed", m.seed);
  for (const char* k :
       {"orientation_noise", "angular_velocity_noise", "linear_acceleration_noise"}) {
    requireInRange(std::string("imu/") + k, d.number(k, 0.0), d.key(k));
  }
  d.rejectUnknown();
  return m;
}

// A list of directories, or one string of ':'-separated directories ("": the defaults).
std::vector<std::string> parseUrdfRoots(const Dict& d) {
  if (d.at("urdf_roots").getType() != XmlRpcValue::TypeString) {
    std::vector<std::string> roots = d.strings("urdf_roots");
    if (roots.empty()) fail("urdf_roots", "must list at least one directory");
    return roots;
  }
  std::vector<std::string> roots;
  std::istringstream in(d.string("urdf_roots", ""));
  for (std::string dir; std::getline(in, dir, ':');) {
    if (!dir.empty()) roots.push_back(dir);
  }
  return roots;
}

ViewParams parseView(const Dict& d, ViewParams v) {
  v.distance = d.number("distance", v.distance);
  v.yaw = d.number("yaw", v.yaw);
  v.pitch = d.number("pitch", v.pitch);
  requireInRange("view/distance", v.distance, d.key("distance"));
  if (std::abs(v.pitch) >= M_PI / 2) fail(d.key("pitch"), "must be within +-pi/2 (exclusive)");
  if (std::abs(v.yaw) > 1e3) fail(d.key("yaw"), "must be within +-1000 rad");
  d.rejectUnknown();
  return v;
}

// A wing command entry: scalars (one stroke for all wings) or equal-length lists.
std::vector<flapsim::StrokeCommand> parseWingCommand(const Dict& d) {
  const char* keys[3] = {"downstroke_rate", "upstroke_rate", "amplitude"};
  std::vector<std::vector<double>> v(3);
  // An optional entry: a number (every stroke) or a list; empty if absent.
  auto numbers = [&d](const char* key) -> std::vector<double> {
    if (!d.has(key)) return {};
    const XmlRpcValue& x = d.at(key);
    return x.getType() == XmlRpcValue::TypeArray
               ? d.numbers(key)
               : std::vector<double>{Dict::toNumber(x, d.key(key))};
  };
  const std::vector<double> feather = numbers("feather");
  const std::vector<double> downstroke_feather = numbers("downstroke_feather");
  const std::vector<double> offset = numbers("offset");
  std::vector<std::string> shape;
  if (d.has("shape")) {
    shape = d.at("shape").getType() == XmlRpcValue::TypeArray
                ? d.strings("shape")
                : std::vector<std::string>{d.string("shape", "")};
  }
  for (int i = 0; i < 3; ++i) {
    if (!d.has(keys[i])) fail(d.key(keys[i]), "missing");
    const XmlRpcValue& x = d.at(keys[i]);
    if (x.getType() == XmlRpcValue::TypeArray) {
      v[i] = d.numbers(keys[i]);
    } else {
      v[i] = {Dict::toNumber(x, d.key(keys[i]))};
    }
  }
  d.rejectUnknown();
  const size_t n = v[0].size();
  if (v[1].size() != n || v[2].size() != n || n == 0) {
    fail(d.name(), "needs downstroke_rate, upstroke_rate and amplitude of equal, non-zero length");
  }
  // A scalar of an optional entry applies to every stroke; a list needs one per stroke.
  auto at = [&](const auto& values, const char* key, size_t k, auto fallback) {
    if (values.empty()) return fallback;
    if (values.size() == 1) return values[0];
    if (values.size() != n) fail(d.key(key), "must have as many entries as downstroke_rate");
    return values[k];
  };
  std::vector<flapsim::StrokeCommand> out;
  for (size_t k = 0; k < n; ++k) {
    flapsim::StrokeCommand c{v[0][k], v[1][k], v[2][k], at(feather, "feather", k, 0.0)};
    c.downstroke_feather = at(downstroke_feather, "downstroke_feather", k, 0.0);
    c.offset = at(offset, "offset", k, 0.0);
    try {
      c.shape = flapsim::strokeShapeFromString(at(shape, "shape", k, std::string("triangle")));
    } catch (const std::invalid_argument& e) {
      fail(d.key("shape"), e.what());
    }
    std::string err = flapsim::validateStroke(c);
    if (!err.empty()) fail(d.name(), err);
    out.push_back(c);
  }
  return out;
}

}  // namespace

std::string validateCreatureName(const std::string& name) {
  if (name.empty()) return "creature name is empty";
  const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (!letter(name[0])) return "creature name '" + name + "' must start with a letter";
  for (char c : name) {
    if (!letter(c) && !digit(c) && c != '_') {
      return "creature name '" + name + "' may only contain letters, digits and '_'";
    }
  }
  return "";
}

CreatureSpec parseCreatureSpec(const XmlRpcValue& entry, const std::string& where) {
  Dict d(entry, where);
  CreatureSpec c;
  if (!d.has("name")) fail(d.key("name"), "missing");
  c.name = d.string("name", "");
  std::string err = validateCreatureName(c.name);
  if (!err.empty()) fail(d.key("name"), err);
  c.urdf_file = d.string("urdf_file", "");
  c.urdf_param = d.string("urdf_param", "");
  c.urdf_xml = d.string("urdf_xml", "");
  const int sources = !c.urdf_file.empty() + !c.urdf_param.empty() + !c.urdf_xml.empty();
  if (sources != 1) {
    fail(where, "creature '" + c.name + "' needs exactly one of urdf_file, urdf_param, urdf_xml");
  }
  if (d.has("pose")) {
    Dict p(d.at("pose"), d.key("pose"));
    c.pose = flapsim::poseFromXyzRpy(p.vec3("xyz", flapsim::Vec3::Zero()),
                                     p.vec3("rpy", flapsim::Vec3::Zero()));
    p.rejectUnknown();
  }
  if (d.has("twist")) {
    Dict t(d.at("twist"), d.key("twist"));
    c.twist.linear = t.vec3("linear", flapsim::Vec3::Zero());
    c.twist.angular = t.vec3("angular", flapsim::Vec3::Zero());
    t.rejectUnknown();
  }
  if (d.has("wing_command")) {
    c.wing_command = parseWingCommand(Dict(d.at("wing_command"), d.key("wing_command")));
  }
  c.controller = d.string("controller", "");
  d.rejectUnknown();
  return c;
}

NodeParams parseNodeParams(const XmlRpcValue& params) {
  NodeParams p;
  if (!params.valid()) return p;  // nothing set: all defaults
  Dict d(params, "");
  flapsim::WorldParams& w = p.world;
  w.step_size = d.number("step_size", w.step_size);
  w.turn_substep = d.number("turn_substep", w.turn_substep);
  w.gravity = d.vec3("gravity", w.gravity);
  w.ground = d.boolean("ground", w.ground);
  w.ground_friction = d.number("ground_friction", w.ground_friction);
  w.solver_iterations = d.integer("solver_iterations", w.solver_iterations);
  w.threads = d.integer("threads", w.threads);
  w.default_wing_effort = d.number("default_wing_effort", w.default_wing_effort);
  w.max_speed = d.number("max_speed", w.max_speed);
  w.max_cells = d.integer("max_cells", w.max_cells);
  const std::string meter = d.string("motor_work", flapsim::motorWorkMeterName(w.motor_work));
  if (!flapsim::motorWorkMeterFromName(meter, &w.motor_work)) {
    fail(d.key("motor_work"), "'" + meter + "' is not one of transmitted, servo");
  }
  if (d.has("air")) w.air = parseAir(Dict(d.at("air"), "air"), w.air);
  std::string err = flapsim::validateWorldParams(w);
  if (!err.empty()) throw ParamError("bad world parameters: " + err);

  p.publish_rate = d.number("publish_rate", p.publish_rate);
  requireInRange("publish_rate", p.publish_rate);
  p.real_time_factor = d.number("real_time_factor", p.real_time_factor);
  if (p.real_time_factor != 0.0 && (p.real_time_factor < 1e-3 || p.real_time_factor > 1e6)) {
    fail("real_time_factor", "must be 0 (as fast as possible) or in [0.001, 1e6]");
  }
  p.max_steps_per_call = d.integer("max_steps_per_call", p.max_steps_per_call);
  if (p.max_steps_per_call < 1) fail("max_steps_per_call", "must be >= 1");
  if (d.has("urdf_roots")) p.urdf_roots = parseUrdfRoots(d);
  p.wing_command_timeout = d.number("wing_command_timeout", p.wing_command_timeout);
  requireInRange("wing_command_timeout", p.wing_command_timeout);
  const std::string action = d.string("wing_command_timeout_action", "hold");
  if (action != "hold" && action != "release") {
    fail("wing_command_timeout_action", "must be 'hold' or 'release', got '" + action + "'");
  }
  p.wing_command_timeout_action =
      action == "hold" ? CommandTimeoutAction::kHold : CommandTimeoutAction::kRelease;
  p.controller_wait_timeout = d.number("controller_wait_timeout", p.controller_wait_timeout);
  requireInRange("controller_wait_timeout", p.controller_wait_timeout);
  if (d.has("view")) p.view = parseView(Dict(d.at("view"), "view"), p.view);
  p.paused = d.boolean("paused", p.paused);
  p.world_frame = d.string("world_frame", p.world_frame);
  if (p.world_frame.empty()) fail("world_frame", "must not be empty");
  if (d.has("markers")) p.markers = parseMarkers(Dict(d.at("markers"), "markers"), p.markers);
  if (d.has("imu")) p.imu = parseImu(Dict(d.at("imu"), "imu"), p.imu);

  if (d.has("creatures")) {
    const XmlRpcValue& list = d.at("creatures");
    if (list.getType() != XmlRpcValue::TypeArray) {
      fail("creatures", "must be a list of dictionaries, got " + typeName(list));
    }
    std::set<std::string> names;
    for (int i = 0; i < list.size(); ++i) {
      CreatureSpec c = parseCreatureSpec(const_cast<XmlRpcValue&>(list)[i],
                                         "creatures[" + std::to_string(i) + "]");
      if (!names.insert(c.name).second) {
        fail("creatures[" + std::to_string(i) + "]/name",
             "creature name '" + c.name + "' is taken");
      }
      p.creatures.push_back(std::move(c));
    }
  }
  // Written by the node's dynamic_reconfigure server (what runs): outputs, not inputs.
  for (const ParamSpec& s : nodeParamSchema()) {
    std::istringstream names(s.reconfigure);
    for (std::string k; names >> k;) {
      if (d.has(k)) d.at(k);
    }
  }
  p.unknown_keys = d.unknownKeys();
  return p;
}

NodeParams loadNodeParams(const ros::NodeHandle& pnh) {
  XmlRpcValue all;
  if (!ros::param::get(pnh.getNamespace(), all)) all = XmlRpcValue();
  NodeParams p = parseNodeParams(all);
  if (p.urdf_roots.empty()) {
    char cwd[PATH_MAX];
    p.urdf_roots =
        defaultUrdfRoots(std::getenv("ROS_PACKAGE_PATH"), ::getcwd(cwd, sizeof cwd) ? cwd : "");
  }
  for (CreatureSpec& c : p.creatures) {
    if (c.urdf_param.empty()) continue;
    if (!pnh.getParam(c.urdf_param, c.urdf_xml)) {
      throw ParamError("creature '" + c.name + "': urdf_param '" + pnh.resolveName(c.urdf_param) +
                       "' is not set or not a string");
    }
  }
  return p;
}

std::uint64_t publishEvery(const NodeParams& p) {
  return std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(1.0 / (p.publish_rate * p.world.step_size))));
}

int publishQueueSize(const NodeParams& p) {
  return static_cast<int>(std::clamp(std::ceil(p.publish_rate * kPublishQueueSeconds), 10.0, 1e4));
}

}  // namespace flapsim_ros
