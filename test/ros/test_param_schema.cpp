// Every place a simulator node parameter is written agrees with the one schema
// (flapsim_ros/param_schema.h): config/flapsim.yaml, cfg/Flapsim.cfg (through the config it
// generates), doc/ros_interface.md's parameter table, the node's parser, and the defaults of
// the structs it fills (the core's WorldParams, AirParams, TurbulenceParams, DiscreteGust,
// QuasiSteadyCoefficients and the node's own NodeParams).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <boost/any.hpp>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/FlapsimConfig.h"
#include "flapsim/turbulence.h"
#include "flapsim_ros/param_schema.h"
#include "flapsim_ros/params.h"
#include "yaml_params.h"

namespace {

using flapsim_ros::nodeParamSchema;
using flapsim_ros::ParamSpec;

std::string sourcePath(const std::string& relative) {
  return std::string(FLAPSIM_SOURCE_DIR) + "/" + relative;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string part; std::getline(in, part, sep);) out.push_back(part);
  return out;
}

// Equal YAML values: numbers by value (1 == 1.0), other scalars as text, lists elementwise.
bool sameValue(const YAML::Node& a, const YAML::Node& b) {
  if (a.IsSequence() || b.IsSequence()) {
    if (!a.IsSequence() || !b.IsSequence() || a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
      if (!sameValue(a[i], b[i])) return false;
    }
    return true;
  }
  if (!a.IsScalar() || !b.IsScalar()) return a.IsNull() && b.IsNull();
  double x, y;
  if (YAML::convert<double>::decode(a, x) && YAML::convert<double>::decode(b, y)) return x == y;
  return a.Scalar() == b.Scalar();
}

std::string text(const YAML::Node& n) {
  YAML::Emitter out;
  out << YAML::Flow << n;
  return out.c_str();
}

// The value at `name` ("air/gust/rise") in `root`, made if missing.
XmlRpc::XmlRpcValue& at(XmlRpc::XmlRpcValue& root, const std::string& name) {
  XmlRpc::XmlRpcValue* v = &root;
  for (const std::string& part : split(name, '/')) v = &(*v)[part];
  return *v;
}

// The schema's parameters set to their defaults, nested as the parameter server holds them.
XmlRpc::XmlRpcValue schemaDefaults() {
  XmlRpc::XmlRpcValue root;
  for (const ParamSpec& s : nodeParamSchema()) {
    if (s.in_config) at(root, s.name) = flapsim_test::toXmlRpc(YAML::Load(s.default_value));
  }
  return root;
}

// The leaves of `n` below `prefix` that no schema name covers.
void unclaimedKeys(const YAML::Node& n, const std::string& prefix, std::set<std::string>* out) {
  for (const auto& kv : n) {
    const std::string name = prefix + kv.first.as<std::string>();
    bool claimed = false;
    for (const ParamSpec& s : nodeParamSchema()) claimed = claimed || name == s.name;
    if (claimed) continue;
    if (kv.second.IsMap()) {
      unclaimedKeys(kv.second, name + "/", out);
    } else {
      out->insert(name);
    }
  }
}

TEST(ParamSchema, ConfigFileHoldsEveryParameterAtItsDefault) {
  const YAML::Node file = YAML::LoadFile(sourcePath("config/flapsim.yaml"));
  for (const ParamSpec& s : nodeParamSchema()) {
    YAML::Node n = YAML::Clone(file);
    for (const std::string& part : split(s.name, '/')) {
      n = n.IsMap() && n[part] ? n[part] : YAML::Node(YAML::NodeType::Undefined);
      if (!n.IsDefined()) break;
    }
    if (!s.in_config) {
      EXPECT_FALSE(n.IsDefined()) << s.name << " is set in config/flapsim.yaml";
      continue;
    }
    if (!n.IsDefined()) {
      ADD_FAILURE() << s.name << " is missing from config/flapsim.yaml";
      continue;
    }
    EXPECT_TRUE(sameValue(n, YAML::Load(s.default_value)))
        << s.name << ": config/flapsim.yaml " << text(n) << ", schema " << s.default_value;
  }
  std::set<std::string> extra;
  unclaimedKeys(file, "", &extra);
  EXPECT_TRUE(extra.empty()) << "not in the schema: " << *extra.begin();
}

// The schema's entry and component that dynamic_reconfigure's `name` is, or nullptr.
const ParamSpec* reconfigured(const std::string& name, size_t* component) {
  for (const ParamSpec& s : nodeParamSchema()) {
    const std::vector<std::string> names = split(s.reconfigure, ' ');
    for (size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) {
        *component = i;
        return &s;
      }
    }
  }
  return nullptr;
}

TEST(ParamSchema, ReconfigureMatchesTheLiveParameters) {
  using flapsim::FlapsimConfig;
  std::set<std::string> in_cfg;
  for (const auto& d : FlapsimConfig::__getParamDescriptions__()) {
    in_cfg.insert(d->name);
    size_t k = 0;
    const ParamSpec* s = reconfigured(d->name, &k);
    ASSERT_NE(s, nullptr) << "cfg/Flapsim.cfg's " << d->name << " is no schema parameter's";
    YAML::Node def = YAML::Load(s->default_value);
    if (def.IsSequence()) def = def[k];
    boost::any v, lo, hi;
    d->getValue(FlapsimConfig::__getDefault__(), v);
    d->getValue(FlapsimConfig::__getMin__(), lo);
    d->getValue(FlapsimConfig::__getMax__(), hi);
    if (d->type == "bool") {
      EXPECT_EQ(boost::any_cast<bool>(v), def.as<bool>()) << d->name;
      continue;
    }
    ASSERT_EQ(d->type, "double") << d->name;
    EXPECT_EQ(boost::any_cast<double>(v), def.as<double>()) << d->name << " default";
    const flapsim_ros::ParamRange r = flapsim_ros::parseParamRange(s->range);
    EXPECT_EQ(boost::any_cast<double>(lo), r.lo) << d->name << " min, schema " << s->range;
    EXPECT_EQ(boost::any_cast<double>(hi), r.hi) << d->name << " max, schema " << s->range;
  }
  for (const ParamSpec& s : nodeParamSchema()) {
    for (const std::string& name : split(s.reconfigure, ' ')) {
      EXPECT_TRUE(in_cfg.count(name)) << s.name << "'s " << name << " is not in cfg/Flapsim.cfg";
    }
  }
}

// The cells of a markdown table row (`\|` inside a cell is not a separator).
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  for (size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '|' && row[i - 1] != '\\') {
      const size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
      out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
      cell.clear();
    } else {
      cell += row[i];
    }
  }
  return out;
}

std::string unquote(std::string s) {
  if (s.size() >= 2 && s.front() == '`' && s.back() == '`') s = s.substr(1, s.size() - 2);
  return s;
}

TEST(ParamSchema, DocTableListsEveryParameterWithItsDefaultAndUnit) {
  std::ifstream doc(sourcePath("doc/ros_interface.md"));
  std::string line;
  while (std::getline(doc, line) && line.rfind("## Parameters", 0) != 0) {
  }
  while (std::getline(doc, line) && line.rfind("| parameter |", 0) != 0) {
  }
  ASSERT_EQ(cells(line), (std::vector<std::string>{"parameter", "default", "unit", "meaning"}));
  std::getline(doc, line);  // | --- |
  std::map<std::string, std::vector<std::string>> rows;
  while (std::getline(doc, line) && line.rfind("|", 0) == 0) {
    const std::vector<std::string> c = cells(line);
    ASSERT_EQ(c.size(), 4u) << line;
    EXPECT_TRUE(rows.emplace(unquote(c[0]), c).second) << c[0] << " is listed twice";
  }
  for (const ParamSpec& s : nodeParamSchema()) {
    const auto row = rows.find(s.name);
    if (row == rows.end()) {
      ADD_FAILURE() << s.name << " is missing from doc/ros_interface.md's table";
      continue;
    }
    const std::string def = unquote(row->second[1]);
    EXPECT_TRUE(sameValue(YAML::Load(def), YAML::Load(s.default_value)))
        << s.name << ": the docs say " << def << ", the schema " << s.default_value;
    EXPECT_EQ(row->second[2], s.unit) << s.name << "'s unit";
    rows.erase(row);
  }
  for (const auto& [name, row] : rows) ADD_FAILURE() << "the docs list " << name << ", no schema";
}

TEST(ParamSchema, TheParserReadsEveryParameterAndNamesOthers) {
  const flapsim_ros::NodeParams p = flapsim_ros::parseNodeParams(schemaDefaults());
  EXPECT_TRUE(p.unknown_keys.empty()) << p.unknown_keys.front();
  // Below a namespace, an unknown key is refused by name; at the top it is listed (and warned).
  std::set<std::string> namespaces;
  for (const ParamSpec& s : nodeParamSchema()) {
    const std::string name = s.name;
    if (name.find('/') != std::string::npos) namespaces.insert(name.substr(0, name.rfind('/')));
  }
  ASSERT_EQ(namespaces.size(), 7u);
  for (const std::string& ns : namespaces) {
    XmlRpc::XmlRpcValue bad = schemaDefaults();
    at(bad, ns + "/not_in_schema") = 1;
    try {
      flapsim_ros::parseNodeParams(bad);
      ADD_FAILURE() << ns << "/not_in_schema was accepted";
    } catch (const flapsim_ros::ParamError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + ns + "/not_in_schema': unknown parameter"),
                std::string::npos)
          << e.what();
    }
  }
  XmlRpc::XmlRpcValue top = schemaDefaults();
  top["not_in_schema"] = 1;
  EXPECT_EQ(flapsim_ros::parseNodeParams(top).unknown_keys,
            std::vector<std::string>{"not_in_schema"});
  // A value outside a string parameter's choices is refused, naming the parameter and value.
  XmlRpc::XmlRpcValue meter = schemaDefaults();
  meter["motor_work"] = "impulse";
  try {
    flapsim_ros::parseNodeParams(meter);
    ADD_FAILURE() << "motor_work: impulse was accepted";
  } catch (const flapsim_ros::ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("motor_work"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'impulse' is not one of transmitted, servo"),
              std::string::npos)
        << e.what();
  }
  meter["motor_work"] = "servo";
  EXPECT_EQ(flapsim_ros::parseNodeParams(meter).world.motor_work,
            flapsim::MotorWorkMeter::kServoImpulse);
}

// A Vec3 as a YAML list.
YAML::Node list(const flapsim::Vec3& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (int i = 0; i < 3; ++i) n.push_back(v[i]);
  return n;
}

// The turbulence level whose wind `wind_at_6m` is, or the number if none is.
YAML::Node turbulenceLevel(double wind_at_6m) {
  for (const char* level : {"none", "light", "moderate", "severe"}) {
    if (flapsim::turbulenceLevelWind(level) == wind_at_6m) return YAML::Node(level);
  }
  return YAML::Node(wind_at_6m);
}

using flapsim_ros::NodeParams;
using Field = std::function<YAML::Node(const NodeParams&)>;

// Per schema parameter, the struct field the node's parser fills from it, as YAML.
const std::map<std::string, Field> kFields = {
    {"step_size", [](const NodeParams& p) { return YAML::Node(p.world.step_size); }},
    {"turn_substep", [](const NodeParams& p) { return YAML::Node(p.world.turn_substep); }},
    {"publish_rate", [](const NodeParams& p) { return YAML::Node(p.publish_rate); }},
    {"real_time_factor", [](const NodeParams& p) { return YAML::Node(p.real_time_factor); }},
    {"max_speed", [](const NodeParams& p) { return YAML::Node(p.world.max_speed); }},
    {"max_cells", [](const NodeParams& p) { return YAML::Node(p.world.max_cells); }},
    {"motor_work",
     [](const NodeParams& p) {
       return YAML::Node(std::string(flapsim::motorWorkMeterName(p.world.motor_work)));
     }},
    {"max_steps_per_call", [](const NodeParams& p) { return YAML::Node(p.max_steps_per_call); }},
    {"urdf_roots",  // the ':'-separated string a launch argument gives ("": the defaults)
     [](const NodeParams& p) {
       std::string roots;
       for (const std::string& r : p.urdf_roots) roots += (roots.empty() ? "" : ":") + r;
       return YAML::Node(roots);
     }},
    {"wing_command_timeout",
     [](const NodeParams& p) { return YAML::Node(p.wing_command_timeout); }},
    {"controller_wait_timeout",
     [](const NodeParams& p) { return YAML::Node(p.controller_wait_timeout); }},
    {"wing_command_timeout_action",
     [](const NodeParams& p) {
       return YAML::Node(p.wing_command_timeout_action == flapsim_ros::CommandTimeoutAction::kHold
                             ? "hold"
                             : "release");
     }},
    {"view/distance", [](const NodeParams& p) { return YAML::Node(p.view.distance); }},
    {"view/yaw", [](const NodeParams& p) { return YAML::Node(p.view.yaw); }},
    {"view/pitch", [](const NodeParams& p) { return YAML::Node(p.view.pitch); }},
    {"paused", [](const NodeParams& p) { return YAML::Node(p.paused); }},
    {"world_frame", [](const NodeParams& p) { return YAML::Node(p.world_frame); }},
    {"gravity", [](const NodeParams& p) { return list(p.world.gravity); }},
    {"ground", [](const NodeParams& p) { return YAML::Node(p.world.ground); }},
    {"ground_friction", [](const NodeParams& p) { return YAML::Node(p.world.ground_friction); }},
    {"solver_iterations",
     [](const NodeParams& p) { return YAML::Node(p.world.solver_iterations); }},
    {"threads", [](const NodeParams& p) { return YAML::Node(p.world.threads); }},
    {"default_wing_effort",
     [](const NodeParams& p) { return YAML::Node(p.world.default_wing_effort); }},
    {"air/density", [](const NodeParams& p) { return YAML::Node(p.world.air.density); }},
    {"air/drag_coefficient",
     [](const NodeParams& p) { return YAML::Node(p.world.air.drag_coefficient); }},
    {"air/wind", [](const NodeParams& p) { return list(p.world.air.wind); }},
    {"air/turbulence/level",
     [](const NodeParams& p) { return turbulenceLevel(p.world.air.turbulence.wind_at_6m); }},
    {"air/turbulence/wind_at_6m",
     [](const NodeParams& p) { return YAML::Node(p.world.air.turbulence.wind_at_6m); }},
    {"air/turbulence/height",
     [](const NodeParams& p) { return YAML::Node(p.world.air.turbulence.height); }},
    {"air/turbulence/per_creature",
     [](const NodeParams& p) { return YAML::Node(p.world.air.turbulence.per_creature); }},
    {"air/turbulence/frozen",
     [](const NodeParams& p) { return YAML::Node(p.world.air.turbulence.frozen); }},
    {"air/turbulence/seed",
     [](const NodeParams& p) { return YAML::Node(p.world.air.turbulence.seed); }},
    {"air/gust/velocity", [](const NodeParams& p) { return list(p.world.air.gust.velocity); }},
    {"air/gust/start", [](const NodeParams& p) { return YAML::Node(p.world.air.gust.start); }},
    {"air/gust/rise", [](const NodeParams& p) { return YAML::Node(p.world.air.gust.rise); }},
    {"air/gust/hold", [](const NodeParams& p) { return YAML::Node(p.world.air.gust.hold); }},
    {"air/buoyancy", [](const NodeParams& p) { return YAML::Node(p.world.air.buoyancy); }},
    {"air/enabled", [](const NodeParams& p) { return YAML::Node(p.world.air.enabled); }},
    {"air/added_mass", [](const NodeParams& p) { return YAML::Node(p.world.air.added_mass); }},
    {"air/added_mass_products",
     [](const NodeParams& p) {
       return YAML::Node(
           std::string(flapsim::addedMassProductsName(p.world.air.added_mass_products)));
     }},
    {"air/rotational_lift",
     [](const NodeParams& p) { return YAML::Node(p.world.air.rotational_lift); }},
    {"air/centre_of_pressure_shift",
     [](const NodeParams& p) { return YAML::Node(p.world.air.centre_of_pressure_shift); }},
    {"air/subdivisions",
     [](const NodeParams& p) {
       YAML::Node n(YAML::NodeType::Sequence);
       n.push_back(p.world.air.subdivisions_u);
       n.push_back(p.world.air.subdivisions_v);
       return n;
     }},
    {"air/model", [](const NodeParams& p) { return YAML::Node(p.world.air.model); }},
    {"air/quasi_steady/lift_mean",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.lift_mean); }},
    {"air/quasi_steady/lift_amplitude",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.lift_amplitude); }},
    {"air/quasi_steady/lift_frequency",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.lift_frequency); }},
    {"air/quasi_steady/lift_phase",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.lift_phase); }},
    {"air/quasi_steady/drag_mean",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.drag_mean); }},
    {"air/quasi_steady/drag_amplitude",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.drag_amplitude); }},
    {"air/quasi_steady/drag_frequency",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.drag_frequency); }},
    {"air/quasi_steady/drag_phase",
     [](const NodeParams& p) { return YAML::Node(p.world.air.quasi_steady.drag_phase); }},
    {"markers/enabled", [](const NodeParams& p) { return YAML::Node(p.markers.enabled); }},
    {"markers/scale", [](const NodeParams& p) { return YAML::Node(p.markers.scale); }},
    {"markers/per_cell", [](const NodeParams& p) { return YAML::Node(p.markers.per_cell); }},
    {"markers/width", [](const NodeParams& p) { return YAML::Node(p.markers.width); }},
    {"imu/orientation_noise",
     [](const NodeParams& p) { return YAML::Node(p.imu.orientation_noise); }},
    {"imu/angular_velocity_noise",
     [](const NodeParams& p) { return YAML::Node(p.imu.angular_velocity_noise); }},
    {"imu/linear_acceleration_noise",
     [](const NodeParams& p) { return YAML::Node(p.imu.linear_acceleration_noise); }},
    {"imu/seed", [](const NodeParams& p) { return YAML::Node(p.imu.seed); }},
    {"creatures",
     [](const NodeParams& p) {
       YAML::Node n(YAML::NodeType::Sequence);
       for (const flapsim_ros::CreatureSpec& c : p.creatures) n.push_back(c.name);
       return n;
     }},
};

TEST(ParamSchema, TheParserAndTheDefaultConstructedStructsGiveEveryParameterItsSchemaDefault) {
  XmlRpc::XmlRpcValue nothing;
  nothing.begin();  // an empty struct: the parser runs, every key missing
  const std::map<std::string, NodeParams> sources = {
      {"parsed from an empty parameter set", flapsim_ros::parseNodeParams(nothing)},
      {"default-constructed", NodeParams()}};
  for (const ParamSpec& s : nodeParamSchema()) {
    const auto field = kFields.find(s.name);
    if (field == kFields.end()) {
      ADD_FAILURE() << s.name << " has no struct field in this test's table";
      continue;
    }
    const YAML::Node schema = YAML::Load(s.default_value);
    for (const auto& [how, p] : sources) {
      const YAML::Node value = field->second(p);
      EXPECT_TRUE(sameValue(value, schema)) << s.name << ": " << text(value) << " " << how
                                            << ", the schema's default " << s.default_value;
    }
  }
  EXPECT_EQ(kFields.size(), nodeParamSchema().size()) << "the table names a parameter twice "
                                                         "or one the schema does not have";
}

}  // namespace
