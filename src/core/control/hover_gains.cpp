#include "flapsim/hover_gains.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "flapsim/text_file.h"
#include "io/yaml_keys.h"

namespace flapsim {

std::string hoverGainsToYaml(const HoverControllerParams& params, const std::string& header,
                             const std::map<std::string, std::string>& metadata) {
  std::ostringstream out;
  out << commentLines(header);
  for (const HoverParamField& f : hoverParamFields()) {
    if (std::strcmp(f.name, "altitude") != 0)
      out << f.name << ": " << shortestDecimal(params.*f.member) << "\n";
  }
  for (const auto& kv : metadata) out << commentLines(kv.first + ": " + kv.second);
  return out.str();
}

HoverControllerParams hoverGainsFromYaml(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": not YAML: " + e.what());
  }
  if (!root.IsMap()) throw InputError(source + ": not a map of hover controller gains");
  std::vector<std::string> known;
  for (const HoverParamField& f : hoverParamFields()) known.push_back(f.name);
  const std::string bad = badYamlKey(root, known);
  if (!bad.empty()) throw InputError(source + ": " + bad);
  HoverControllerParams p;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    const HoverParamField* field = nullptr;
    for (const HoverParamField& f : hoverParamFields()) {
      if (key == f.name) field = &f;
    }
    if (field == nullptr) throw InputError(source + ": unknown key '" + key + "'");
    double value = NAN;
    try {
      value = kv.second.as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(source + ": '" + key + "' is not a number");
    }
    if (!std::isfinite(value)) throw InputError(source + ": '" + key + "' is not finite");
    p.*field->member = value;
  }
  const std::string err = validateHoverControllerParams(p);
  if (!err.empty()) throw InputError(source + ": " + err);
  return p;
}

HoverControllerParams loadHoverGainsYaml(const std::string& path) {
  return hoverGainsFromYaml(readTextFile(path, kMaxHoverGainsFileBytes), path);
}

}  // namespace flapsim
