#include "flapsim/controller_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
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
  e << YAML::Key << "network" << YAML::Value << toString(p.network);
  e << YAML::Key << "inputs" << YAML::Value << YAML::Flow << flapInputNames(p);
  e << YAML::Key << "outputs" << YAML::Value << YAML::Flow << flapOutputNames(p);
  e << YAML::Key << "rate_inputs" << YAML::Value << p.rate_inputs;
  e << YAML::Key << "rate_scale" << YAML::Value << p.rate_scale;
  e << YAML::Key << "altitude_input" << YAML::Value << p.altitude_input;
  e << YAML::Key << "altitude_scale" << YAML::Value << p.altitude_scale;
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
  std::string network = toString(p.network);
  get("network", network);
  try {
    p.hidden_activation = activationFromString(act);
    p.network = flapNetworkFromString(network);
  } catch (const std::invalid_argument& e) {
    throw fail(e.what());
  }
  get("rate_inputs", p.rate_inputs);
  get("rate_scale", p.rate_scale);
  get("altitude_input", p.altitude_input);
  get("altitude_scale", p.altitude_scale);
  // The lists of inputs and outputs are what the settings above make them: a file whose
  // lists disagree was edited by hand or written by another version.
  const std::pair<const char*, std::vector<std::string>> lists[] = {
      {"inputs", flapInputNames(p)}, {"outputs", flapOutputNames(p)}};
  for (const auto& [key, expected] : lists) {
    std::vector<std::string> names = expected;
    get(key, names);
    if (names != expected) {
      std::string want;
      for (const auto& n : expected) want += (want.empty() ? "" : ", ") + n;
      throw fail(std::string("'") + key + "' does not match the network's settings (" + want +
                 ")");
    }
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
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read controller YAML '" + path + "'");
  std::stringstream buf;
  buf << in.rdbuf();
  return controllerFromYaml(buf.str(), path);
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace flapsim
