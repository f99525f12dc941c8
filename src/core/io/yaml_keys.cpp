#include "io/yaml_keys.h"

#include <algorithm>
#include <set>

#include "flapsim/cli_args.h"

namespace flapsim {

std::string badYamlKey(const YAML::Node& map, const std::vector<std::string>& known) {
  std::set<std::string> seen;
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      return "unknown key " + quoteValue(key);
    }
    if (!seen.insert(key).second) return "key " + quoteValue(key) + " given twice";
  }
  return "";
}

}  // namespace flapsim
