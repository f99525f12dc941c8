// The one check of a YAML map's keys that every reader of the package's files (controller
// weights, hover gains) applies: unknown and repeated keys are refused by name. Private to
// flapsim_core.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace flapsim {

/// Empty if every key of the YAML map `map` is one of `known` and none appears twice (yaml-cpp
/// keeps both entries of a repeated key and a lookup finds the first: a silent answer), else
/// "unknown key 'k'" or "key 'k' given twice", for the first such key.
std::string badYamlKey(const YAML::Node& map, const std::vector<std::string>& known);

}  // namespace flapsim
