// The simulator node's parameters, each written once: its name as the node reads it, type,
// default, range, unit, one line of doc and its dynamic_reconfigure name. params.cpp takes
// its range checks from here; test_param_schema checks config/flapsim.yaml, cfg/Flapsim.cfg,
// the parameter table of doc/ros_interface.md and the defaults of the structs the parser fills
// (the core's WorldParams and AirParams with theirs, NodeParams) against it.
#pragma once

#include <string>
#include <vector>

namespace flapsim_ros {

enum class ParamType { kBool, kInt, kDouble, kString, kVec3, kIntPair, kStrings, kList };

struct ParamSpec {
  const char* name;  // as the node reads it, e.g. "air/density"
  ParamType type;
  /// YAML text of the default, e.g. "1.204", "[0.0, 0.0, -9.81]", "hold".
  const char* default_value;
  /// "[lo, hi]" with "(" or ")" for an open end (each component of a vector), allowed values
  /// "a|b|c", or "" (none).
  const char* range;
  const char* unit;  // "" for none
  const char* doc;   // one line
  /// dynamic_reconfigure's name(s), one per component ("wind_x wind_y wind_z"); "": not live.
  const char* reconfigure;
  /// Set in config/flapsim.yaml (false: set by the launch files, or excluding another).
  bool in_config = true;
};

/// Every parameter of the simulator node, in the order of doc/ros_interface.md's table.
const std::vector<ParamSpec>& nodeParamSchema();

/// The entry named `name`; throws std::out_of_range if there is none.
const ParamSpec& paramSpec(const std::string& name);

/// A numeric range "[lo, hi]" of a ParamSpec, parsed.
struct ParamRange {
  double lo, hi;
  bool lo_open, hi_open;
  bool contains(double x) const;
};
ParamRange parseParamRange(const std::string& range);

/// Throws ParamError naming `key` ("must be in [0.01, 1e6] Hz") unless `value` is in the
/// range of the schema's `name` (`key` defaults to `name`).
void requireInRange(const std::string& name, double value, const std::string& key = "");

}  // namespace flapsim_ros
