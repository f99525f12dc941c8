#include "flapsim/controller_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flapsim {

std::string controllerToYaml(const ControllerSpec& spec, const std::string& header,
                             const std::map<std::string, std::string>& metadata) {
  std::ostringstream out;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  const FlapControllerParams& p = spec.params;
  e << YAML::BeginMap << YAML::Key << "flap_unit_controller" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "inputs" << YAML::Value << YAML::Flow << YAML::BeginSeq
    << "world_up.body_forward"
    << "world_up.body_left" << YAML::EndSeq;
  e << YAML::Key << "outputs" << YAML::Value << YAML::Flow << YAML::BeginSeq
    << "right_downstroke_rate"
    << "left_downstroke_rate" << YAML::EndSeq;
  e << YAML::Key << "hidden" << YAML::Value << p.hidden;
  e << YAML::Key << "hidden_activation" << YAML::Value << toString(p.hidden_activation);
  e << YAML::Key << "output_activation" << YAML::Value << "sigmoid";
  e << YAML::Key << "min_downstroke_rate" << YAML::Value << p.min_downstroke_rate;
  e << YAML::Key << "max_downstroke_rate" << YAML::Value << p.max_downstroke_rate;
  e << YAML::Key << "upstroke_rate" << YAML::Value << p.upstroke_rate;
  e << YAML::Key << "amplitude" << YAML::Value << p.amplitude;
  e << YAML::Key << "control_period" << YAML::Value << p.control_period;
  e << YAML::Key << "phase_lock" << YAML::Value << p.phase_lock;
  e << YAML::Key << "pitch_gain" << YAML::Value << p.pitch_gain;
  e << YAML::Key << "pitch_limit" << YAML::Value << p.pitch_limit;
  e << YAML::Key << "pitch_max_downstroke_rate" << YAML::Value << p.pitch_max_downstroke_rate;
  e << YAML::Key << "weights" << YAML::Value << YAML::Flow << spec.weights;
  e << YAML::EndMap;
  if (!metadata.empty()) {
    e << YAML::Key << "evolution" << YAML::Value << YAML::BeginMap;
    for (const auto& kv : metadata) e << YAML::Key << kv.first << YAML::Value << kv.second;
    e << YAML::EndMap;
  }
  e << YAML::EndMap;
  out << e.c_str() << "\n";
  return out.str();
}

ControllerSpec controllerFromYaml(const std::string& text, const std::string& source) {
  auto fail = [&](const std::string& what) {
    return std::runtime_error("controller YAML " + source + ": " + what);
  };
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw fail(e.what());
  }
  const YAML::Node c = root["flap_unit_controller"];
  if (!c || !c.IsMap()) throw fail("no map 'flap_unit_controller'");
  ControllerSpec spec;
  FlapControllerParams& p = spec.params;
  auto get = [&](const char* key, auto& value) {
    const YAML::Node n = c[key];
    if (!n) return;  // keep the default
    try {
      value = n.as<std::remove_reference_t<decltype(value)>>();
    } catch (const YAML::Exception&) {
      throw fail(std::string("bad value of '") + key + "'");
    }
  };
  get("hidden", p.hidden);
  std::string act = toString(p.hidden_activation);
  get("hidden_activation", act);
  try {
    p.hidden_activation = activationFromString(act);
  } catch (const std::invalid_argument& e) {
    throw fail(e.what());
  }
  get("min_downstroke_rate", p.min_downstroke_rate);
  get("max_downstroke_rate", p.max_downstroke_rate);
  get("upstroke_rate", p.upstroke_rate);
  get("amplitude", p.amplitude);
  get("control_period", p.control_period);
  get("phase_lock", p.phase_lock);
  get("pitch_gain", p.pitch_gain);
  get("pitch_limit", p.pitch_limit);
  get("pitch_max_downstroke_rate", p.pitch_max_downstroke_rate);
  if (!c["weights"]) throw fail("no 'weights'");
  get("weights", spec.weights);
  const std::string err = validateFlapControllerParams(p);
  if (!err.empty()) throw fail(err);
  const int n = FlapUnitController::weightCount(p);
  if (static_cast<int>(spec.weights.size()) != n) {
    throw fail("'weights' has " + std::to_string(spec.weights.size()) + " numbers, the net takes " +
               std::to_string(n));
  }
  for (double w : spec.weights) {
    if (!std::isfinite(w)) throw fail("a weight is not finite");
  }
  return spec;
}

ControllerSpec loadControllerYaml(const std::string& path) {
  std::string text;
  try {
    text = readTextFile(path, kMaxControllerFileBytes);
  } catch (const InputError& e) {
    throw std::runtime_error(std::string("controller YAML ") + e.what());
  }
  return controllerFromYaml(text, path);
}

}  // namespace flapsim
