// Every place a simulator node parameter is written agrees with the one schema
// (flapsim_ros/param_schema.h): config/flapsim.yaml, cfg/Flapsim.cfg (through the config it
// generates), doc/ros_interface.md's parameter table, and the node's parser.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <boost/any.hpp>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/FlapsimConfig.h"
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
}

}  // namespace
