#include "flapsim/controller_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "flapsim/cli_args.h"
#include "flapsim/text_file.h"
#include "io/yaml_keys.h"

namespace flapsim {

std::string controllerToYaml(const ControllerSpec& spec, const std::string& header,
                             const std::map<std::string, std::string>& metadata) {
  std::ostringstream out;
  out << commentLines(header);
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
  if (p.climb_input) {
    e << YAML::Key << "climb_input" << YAML::Value << p.climb_input;
    e << YAML::Key << "climb_scale" << YAML::Value << p.climb_scale;
  }
  if (p.chain_input) e << YAML::Key << "chain_input" << YAML::Value << p.chain_input;
  e << YAML::Key << "hidden" << YAML::Value << p.hidden;
  e << YAML::Key << "hidden_activation" << YAML::Value << toString(p.hidden_activation);
  e << YAML::Key << "output_activation" << YAML::Value << "sigmoid";
  e << YAML::Key << "min_downstroke_rate" << YAML::Value << p.min_downstroke_rate;
  e << YAML::Key << "max_downstroke_rate" << YAML::Value << p.max_downstroke_rate;
  e << YAML::Key << "upstroke_rate" << YAML::Value << p.upstroke_rate;
  if (p.max_upstroke_rate != 0.0) {
    e << YAML::Key << "max_upstroke_rate" << YAML::Value << p.max_upstroke_rate;
  }
  if (p.mixer_headroom != 0.0) {
    e << YAML::Key << "mixer_headroom" << YAML::Value << p.mixer_headroom;
  }
  e << YAML::Key << "amplitude" << YAML::Value << p.amplitude;
  if (p.stroke_offset != 0.0) e << YAML::Key << "stroke_offset" << YAML::Value << p.stroke_offset;
  e << YAML::Key << "control_period" << YAML::Value << p.control_period;
  e << YAML::Key << "phase_lock" << YAML::Value << p.phase_lock;
  e << YAML::Key << "pitch_gain" << YAML::Value << p.pitch_gain;
  e << YAML::Key << "pitch_limit" << YAML::Value << p.pitch_limit;
  e << YAML::Key << "pitch_max_downstroke_rate" << YAML::Value << p.pitch_max_downstroke_rate;
  if (p.roll_reflex_bank != 0.0) {
    e << YAML::Key << "roll_reflex_bank" << YAML::Value << p.roll_reflex_bank;
    e << YAML::Key << "roll_reflex_rate" << YAML::Value << p.roll_reflex_rate;
    e << YAML::Key << "roll_reflex_fast_rate" << YAML::Value << p.roll_reflex_fast_rate;
    e << YAML::Key << "roll_reflex_slow_rate" << YAML::Value << p.roll_reflex_slow_rate;
  }
  if (p.pitch_reflex_angle != 0.0) {
    e << YAML::Key << "pitch_reflex_angle" << YAML::Value << p.pitch_reflex_angle;
    e << YAML::Key << "pitch_reflex_ends" << YAML::Value << p.pitch_reflex_ends;
    e << YAML::Key << "pitch_reflex_fast_rate" << YAML::Value << p.pitch_reflex_fast_rate;
    e << YAML::Key << "pitch_reflex_slow_rate" << YAML::Value << p.pitch_reflex_slow_rate;
  }
  if (p.attitude_filter_time != 0.0) {
    e << YAML::Key << "attitude_filter_time" << YAML::Value << p.attitude_filter_time;
  }
  if (p.velocity_gain != 0.0) {
    e << YAML::Key << "velocity_gain" << YAML::Value << p.velocity_gain;
    e << YAML::Key << "velocity_tilt_limit" << YAML::Value << p.velocity_tilt_limit;
  }
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

namespace {

// The keys of `flap_unit_controller`: each is read, so a misspelt one is an error, not a
// default silently kept.
const std::vector<std::string> kKeys = {"network",
                                        "inputs",
                                        "outputs",
                                        "rate_inputs",
                                        "rate_scale",
                                        "altitude_input",
                                        "altitude_scale",
                                        "climb_input",
                                        "climb_scale",
                                        "chain_input",
                                        "hidden",
                                        "hidden_activation",
                                        "output_activation",
                                        "min_downstroke_rate",
                                        "max_downstroke_rate",
                                        "upstroke_rate",
                                        "max_upstroke_rate",
                                        "mixer_headroom",
                                        "amplitude",
                                        "stroke_offset",
                                        "control_period",
                                        "phase_lock",
                                        "pitch_gain",
                                        "pitch_limit",
                                        "pitch_max_downstroke_rate",
                                        "roll_reflex_bank",
                                        "roll_reflex_rate",
                                        "roll_reflex_fast_rate",
                                        "roll_reflex_slow_rate",
                                        "pitch_reflex_angle",
                                        "pitch_reflex_ends",
                                        "pitch_reflex_fast_rate",
                                        "pitch_reflex_slow_rate",
                                        "attitude_filter_time",
                                        "velocity_gain",
                                        "velocity_tilt_limit",
                                        "weights"};

ControllerSpec readController(const YAML::Node& c,
                              const std::function<std::runtime_error(const std::string&)>& fail) {
  const std::string bad = badYamlKey(c, kKeys);
  if (!bad.empty()) throw fail(bad);
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
  std::string act = toString(p.hidden_activation), output_act = "sigmoid";
  get("hidden", p.hidden);
  get("hidden_activation", act);
  get("output_activation", output_act);
  if (output_act != "sigmoid") throw fail("'output_activation' must be sigmoid");
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
  get("climb_input", p.climb_input);
  get("climb_scale", p.climb_scale);
  get("chain_input", p.chain_input);
  get("max_upstroke_rate", p.max_upstroke_rate);
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
      throw fail(std::string("'") + key + "' must be [" + want + "]");
    }
  }
  get("min_downstroke_rate", p.min_downstroke_rate);
  get("max_downstroke_rate", p.max_downstroke_rate);
  get("upstroke_rate", p.upstroke_rate);
  get("mixer_headroom", p.mixer_headroom);
  get("amplitude", p.amplitude);
  get("stroke_offset", p.stroke_offset);
  get("control_period", p.control_period);
  get("phase_lock", p.phase_lock);
  get("pitch_gain", p.pitch_gain);
  get("pitch_limit", p.pitch_limit);
  get("pitch_max_downstroke_rate", p.pitch_max_downstroke_rate);
  get("roll_reflex_bank", p.roll_reflex_bank);
  get("roll_reflex_rate", p.roll_reflex_rate);
  get("roll_reflex_fast_rate", p.roll_reflex_fast_rate);
  get("roll_reflex_slow_rate", p.roll_reflex_slow_rate);
  get("pitch_reflex_angle", p.pitch_reflex_angle);
  get("pitch_reflex_ends", p.pitch_reflex_ends);
  get("pitch_reflex_fast_rate", p.pitch_reflex_fast_rate);
  get("pitch_reflex_slow_rate", p.pitch_reflex_slow_rate);
  get("attitude_filter_time", p.attitude_filter_time);
  get("velocity_gain", p.velocity_gain);
  get("velocity_tilt_limit", p.velocity_tilt_limit);
  if (!c["weights"]) throw fail("no 'weights'");
  get("weights", spec.weights);
  return spec;
}

}  // namespace

ControllerSpec controllerFromYaml(const std::string& text, const std::string& source) {
  auto fail = [&](const std::string& what) {
    return std::runtime_error("controller YAML " + source + ": " + what);
  };
  ControllerSpec spec;
  try {
    const YAML::Node root = YAML::Load(text);
    const YAML::Node c = root.IsMap() ? root["flap_unit_controller"] : YAML::Node();
    if (!c || !c.IsMap()) throw fail("no map 'flap_unit_controller'");
    const std::string bad = badYamlKey(root, {"flap_unit_controller", "evolution"});
    if (!bad.empty()) throw fail(bad);
    spec = readController(c, fail);
  } catch (const YAML::Exception& e) {
    throw fail(e.what());
  }
  const FlapControllerParams& p = spec.params;
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
