#include "flapsim_ros/controller_params.h"

#include <cmath>

namespace flapsim_ros {

namespace {

using XmlRpc::XmlRpcValue;

bool isNumber(const XmlRpcValue& v) {
  return v.getType() == XmlRpcValue::TypeInt || v.getType() == XmlRpcValue::TypeDouble;
}

double number(const XmlRpcValue& v, const std::string& key) {
  if (!isNumber(v)) throw ParamError("parameter '" + key + "' must be a number");
  XmlRpcValue& x = const_cast<XmlRpcValue&>(v);
  const double d =
      x.getType() == XmlRpcValue::TypeInt ? static_cast<int>(x) : static_cast<double>(x);
  if (!std::isfinite(d)) throw ParamError("parameter '" + key + "' must be finite");
  return d;
}

bool has(const XmlRpcValue& ns, const std::string& key) {
  return ns.getType() == XmlRpcValue::TypeStruct && const_cast<XmlRpcValue&>(ns).hasMember(key);
}

const XmlRpcValue& at(const XmlRpcValue& ns, const std::string& key) {
  return const_cast<XmlRpcValue&>(ns)[key];
}

double getNumber(const XmlRpcValue& ns, const std::string& key, double def) {
  return has(ns, key) ? number(at(ns, key), key) : def;
}

std::string getString(const XmlRpcValue& ns, const std::string& key, const std::string& def) {
  if (!has(ns, key)) return def;
  const XmlRpcValue& v = at(ns, key);
  if (v.getType() != XmlRpcValue::TypeString) {
    throw ParamError("parameter '" + key + "' must be a string");
  }
  return static_cast<std::string>(const_cast<XmlRpcValue&>(v));
}

bool getBool(const XmlRpcValue& ns, const std::string& key, bool def) {
  if (!has(ns, key)) return def;
  const XmlRpcValue& v = at(ns, key);
  if (v.getType() != XmlRpcValue::TypeBoolean) {
    throw ParamError("parameter '" + key + "' must be true or false");
  }
  return static_cast<bool>(const_cast<XmlRpcValue&>(v));
}

int getPairs(const XmlRpcValue& ns) {
  const double p = getNumber(ns, "pairs", 1);
  if (p < 1 || p != std::floor(p)) throw ParamError("parameter 'pairs' must be an integer >= 1");
  return static_cast<int>(p);
}

/// A number for every pair, or a list of one number per pair.
std::vector<double> perPair(const XmlRpcValue& ns, const std::string& key, int pairs, double def) {
  if (!has(ns, key)) return std::vector<double>(pairs, def);
  const XmlRpcValue& v = at(ns, key);
  if (isNumber(v)) return std::vector<double>(pairs, number(v, key));
  if (v.getType() != XmlRpcValue::TypeArray || v.size() != pairs) {
    throw ParamError("parameter '" + key + "' must be a number or a list of " +
                     std::to_string(pairs) + " numbers (one per wing pair)");
  }
  std::vector<double> out;
  for (int i = 0; i < pairs; ++i) {
    out.push_back(number(const_cast<XmlRpcValue&>(v)[i], key + "[" + std::to_string(i) + "]"));
  }
  return out;
}

std::string creatureName(const XmlRpcValue& ns, const std::string& def) {
  const std::string c = getString(ns, "creature", def);
  const std::string err = validateCreatureName(c);
  if (!err.empty()) throw ParamError("parameter 'creature' ('" + c + "'): " + err);
  return c;
}

}  // namespace

std::string namespaceBasename(const std::string& ns) {
  std::string s = ns;
  while (!s.empty() && s.back() == '/') s.pop_back();
  const size_t slash = s.rfind('/');
  return slash == std::string::npos ? s : s.substr(slash + 1);
}

StrokeControllerParams parseStrokeControllerParams(const XmlRpcValue& ns,
                                                   const std::string& default_creature) {
  StrokeControllerParams p;
  p.creature = creatureName(ns, default_creature);
  p.pairs = getPairs(ns);
  p.rate = getNumber(ns, "rate", p.rate);
  if (p.rate <= 0.0) throw ParamError("parameter 'rate' must be > 0");
  p.reread_period = getNumber(ns, "reread_period", p.reread_period);
  if (p.reread_period <= 0.0) throw ParamError("parameter 'reread_period' must be > 0");
  const auto down = perPair(ns, "downstroke_rate", p.pairs, 40.0);
  const auto up = perPair(ns, "upstroke_rate", p.pairs, 10.0);
  const auto amp = perPair(ns, "amplitude", p.pairs, 0.8);
  for (int i = 0; i < p.pairs; ++i) {
    flapsim::StrokeCommand c;
    c.downstroke_rate = down[i];
    c.upstroke_rate = up[i];
    c.amplitude = amp[i];
    const std::string err = flapsim::validateStroke(c);
    if (!err.empty()) throw ParamError("wing pair " + std::to_string(i) + ": " + err);
    p.strokes.push_back(c);
  }
  return p;
}

flapsim::WingCommand strokeCommandMsg(const std::vector<flapsim::StrokeCommand>& strokes) {
  flapsim::WingCommand msg;
  for (const auto& s : strokes) {
    for (int side = 0; side < 2; ++side) {
      msg.downstroke_rate.push_back(s.downstroke_rate);
      msg.upstroke_rate.push_back(s.upstroke_rate);
      msg.amplitude.push_back(s.amplitude);
    }
  }
  return msg;
}

AnnControllerParams parseAnnControllerParams(const XmlRpcValue& ns,
                                             const std::string& default_creature) {
  AnnControllerParams p;
  p.creature = creatureName(ns, default_creature);
  p.weights_file = getString(ns, "weights", "");
  if (p.weights_file.empty()) throw ParamError("parameter 'weights' (a weights YAML) is required");
  p.pairs = getPairs(ns);
  p.world_frame = getString(ns, "world_frame", p.world_frame);
  p.rate = getNumber(ns, "rate", p.rate);
  if (p.rate < 0.0) throw ParamError("parameter 'rate' must be >= 0");
  p.lockstep = getBool(ns, "lockstep", p.lockstep);
  p.lockstep_duration = getNumber(ns, "lockstep_duration", p.lockstep_duration);
  if (p.lockstep_duration < 0.0) throw ParamError("parameter 'lockstep_duration' must be >= 0");
  p.lockstep_wait_for_start = getBool(ns, "lockstep_wait_for_start", p.lockstep_wait_for_start);
  p.step_service = getString(ns, "step_service", p.step_service);
  p.step_size = getNumber(ns, "step_size", p.step_size);
  if (p.step_size <= 0.0) throw ParamError("parameter 'step_size' must be > 0");
  p.wait_timeout = getNumber(ns, "wait_timeout", p.wait_timeout);
  if (p.wait_timeout <= 0.0) throw ParamError("parameter 'wait_timeout' must be > 0");
  return p;
}

flapsim::WingCommand annCommandMsg(const flapsim::FlapUnitLayout& layout,
                                   const std::vector<flapsim::StrokeCommand>& strokes) {
  flapsim::WingCommand msg;
  msg.joint_names = layout.wing_joints;
  for (const auto& s : strokes) {
    msg.downstroke_rate.push_back(s.downstroke_rate);
    msg.upstroke_rate.push_back(s.upstroke_rate);
    msg.amplitude.push_back(s.amplitude);
  }
  return msg;
}

}  // namespace flapsim_ros
