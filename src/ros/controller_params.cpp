#include "flapsim_ros/controller_params.h"

#include <cmath>
#include <sstream>

#include "flapsim/ann.h"
#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

namespace {

using XmlRpc::XmlRpcValue;

// The namespace to read: nothing set (not a struct at all) reads as an empty one.
ParamReader reader(const XmlRpcValue& ns) {
  static const XmlRpcValue kEmpty = [] {
    XmlRpcValue v;
    v.begin();  // an empty struct
    return v;
  }();
  return ParamReader(ns.getType() == XmlRpcValue::TypeInvalid ? kEmpty : ns, "");
}

int getPairs(const ParamReader& d) {
  const double p = d.number("pairs", 1);
  if (p < 1 || p != std::floor(p)) failParam(d.key("pairs"), "must be an integer >= 1");
  return static_cast<int>(p);
}

/// A number for every pair, or a list of one number per pair.
std::vector<double> perPair(const ParamReader& d, const std::string& key, int pairs, double def) {
  if (!d.has(key)) return std::vector<double>(pairs, def);
  const XmlRpcValue& v = d.at(key);
  if (v.getType() == XmlRpcValue::TypeInt || v.getType() == XmlRpcValue::TypeDouble) {
    return std::vector<double>(pairs, ParamReader::toNumber(v, d.key(key)));
  }
  if (v.getType() != XmlRpcValue::TypeArray || v.size() != pairs) {
    failParam(d.key(key), "must be a number or a list of " + std::to_string(pairs) +
                              " numbers (one per wing pair)");
  }
  return d.numbers(key);
}

std::string creatureName(const ParamReader& d, const std::string& def) {
  const std::string c = d.string("creature", def);
  const std::string err = validateCreatureName(c);
  if (!err.empty()) failParam(d.key("creature"), "'" + c + "': " + err);
  return c;
}

void atLeast(const ParamReader& d, const std::string& key, double value, double bound,
             bool strict) {
  if (strict ? value <= bound : value < bound) {
    std::ostringstream msg;
    msg << "must be " << (strict ? "> " : ">= ") << bound;
    failParam(d.key(key), msg.str());
  }
}

void inRange(const ParamReader& d, const std::string& key, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    std::ostringstream msg;
    msg << "must be in [" << lo << ", " << hi << "]";
    failParam(d.key(key), msg.str());
  }
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
  const ParamReader d = reader(ns);
  StrokeControllerParams p;
  p.creature = creatureName(d, default_creature);
  p.pairs = getPairs(d);
  p.rate = d.number("rate", p.rate);
  atLeast(d, "rate", p.rate, 0.0, true);
  p.reread_period = d.number("reread_period", p.reread_period);
  atLeast(d, "reread_period", p.reread_period, 0.0, true);
  const auto down = perPair(d, "downstroke_rate", p.pairs, 40.0);
  const auto up = perPair(d, "upstroke_rate", p.pairs, 10.0);
  const auto amp = perPair(d, "amplitude", p.pairs, 0.8);
  flapsim::StrokeShape shape = flapsim::StrokeShape::kTriangle;
  try {
    shape = flapsim::strokeShapeFromString(d.string("shape", "triangle"));
  } catch (const std::invalid_argument& e) {
    failParam(d.key("shape"), e.what());
  }
  for (int i = 0; i < p.pairs; ++i) {
    flapsim::StrokeCommand c;
    c.downstroke_rate = down[i];
    c.upstroke_rate = up[i];
    c.amplitude = amp[i];
    c.shape = shape;
    const std::string err = flapsim::validateStroke(c);
    if (!err.empty()) throw ParamError("wing pair " + std::to_string(i) + ": " + err);
    p.strokes.push_back(c);
  }
  d.rejectUnknown();  // as a weights or gains file refuses a key it does not read
  return p;
}

flapsim::WingCommand strokeCommandMsg(const std::vector<flapsim::StrokeCommand>& strokes) {
  WingCommandRequest r;  // every wing joint, in URDF order: left, right of each pair
  for (const auto& s : strokes) r.strokes.insert(r.strokes.end(), 2, s);
  return toMsg(r);
}

AnnControllerParams parseAnnControllerParams(const XmlRpcValue& ns,
                                             const std::string& default_creature) {
  const ParamReader d = reader(ns);
  AnnControllerParams p;
  p.creature = creatureName(d, default_creature);
  p.weights_file = d.string("weights", "");
  if (p.weights_file.empty()) failParam("weights", "(a weights YAML) is required");
  p.pairs = getPairs(d);
  const std::string source = d.string("attitude_source", "imu");
  if (source != "imu" && source != "tf") {
    failParam(d.key("attitude_source"), "'" + source + "' is neither imu nor tf");
  }
  p.attitude_source = source == "tf" ? AttitudeSource::kTf : AttitudeSource::kImu;
  if (d.has("altitude")) {
    p.altitude = d.number("altitude", 0.0);
    if (!(std::abs(*p.altitude) <= flapsim::kMaxPosition)) {
      failParam(d.key("altitude"), "must be finite (at most 1e6 m)");
    }
  }
  p.altitude_noise = d.number("altitude_noise", p.altitude_noise);
  inRange(d, "altitude_noise", p.altitude_noise, 0.0, 1e3);
  p.velocity_noise = d.number("velocity_noise", p.velocity_noise);
  inRange(d, "velocity_noise", p.velocity_noise, 0.0, 1e3);
  p.gyro_bias = d.vec3("gyro_bias", p.gyro_bias);
  if (!(p.gyro_bias.cwiseAbs().maxCoeff() <= 1e3)) {
    failParam(d.key("gyro_bias"), "must be three finite numbers, each within +-1000 rad/s");
  }
  if (p.attitude_source == AttitudeSource::kTf && d.has("gyro_bias")) {
    failParam(d.key("gyro_bias"), "is set, but tf (attitude_source) has no gyro to bias");
  }
  p.noise_seed = d.integer("noise_seed", p.noise_seed);
  p.world_frame = d.string("world_frame", p.world_frame);
  p.rate = d.number("rate", p.rate);
  if (p.rate != 0.0 &&
      !(p.rate >= 1.0 / flapsim::kMaxControlPeriod && p.rate <= 1.0 / flapsim::kMinControlPeriod)) {
    failParam(d.key("rate"),
              "must be 0 (the weights file's control period) or in [0.1, 1000] Hz, as a control "
              "period in [0.001, 10] s");
  }
  readLockstepParams(d, p);
  p.lockstep_wait_for_start = d.boolean("lockstep_wait_for_start", p.lockstep_wait_for_start);
  if (d.has("lockstep_creatures")) {
    // Only a lockstep node flies several creatures: without it the list would be ignored.
    if (!p.lockstep) {
      failParam(d.key("lockstep_creatures"), "is set, but '" + d.key("lockstep") + "' is not true");
    }
    p.lockstep_creatures = d.strings("lockstep_creatures");
    for (size_t i = 0; i < p.lockstep_creatures.size(); ++i) {
      if (p.lockstep_creatures[i].empty()) {
        failParam(d.key("lockstep_creatures") + "[" + std::to_string(i) + "]", "is empty");
      }
    }
  }
  d.rejectUnknown();  // as a weights or gains file refuses a key it does not read
  return p;
}

void readLockstepParams(const ParamReader& d, LockstepParams& p) {
  p.lockstep = d.boolean("lockstep", p.lockstep);
  p.lockstep_duration = d.number("lockstep_duration", p.lockstep_duration);
  atLeast(d, "lockstep_duration", p.lockstep_duration, 0.0, false);
  p.step_service = d.string("step_service", p.step_service);
  if (d.has("step_size")) {
    p.step_size = d.number("step_size", p.step_size);
    atLeast(d, "step_size", p.step_size, 0.0, true);
  }
  p.wait_timeout = d.number("wait_timeout", p.wait_timeout);
  atLeast(d, "wait_timeout", p.wait_timeout, 0.0, true);
}

std::string annControllerMismatch(const AnnControllerParams& params,
                                  const flapsim::FlapControllerParams& network,
                                  const std::string& attitude_source_key,
                                  const std::string& altitude_key) {
  if (params.attitude_source == AttitudeSource::kTf && network.rate_inputs) {
    return "parameter '" + attitude_source_key +
           "': tf has no angular velocities, and the network of " + params.weights_file +
           " takes the gyro's rates: use imu";
  }
  if (params.attitude_source == AttitudeSource::kTf && network.climb_input) {
    return "parameter '" + attitude_source_key + "': tf gives no velocity, and the network of " +
           params.weights_file + " takes the climb rate (odom's twist): use imu";
  }
  if (params.altitude && !network.altitude_input) {
    return "parameter '" + altitude_key + "': the network of " + params.weights_file +
           " has no altitude input and cannot hold a height (it climbs): leave it unset, or fly "
           "one that has (config/afc_1_altitude_weights.yaml, config/afc_12_altitude_weights.yaml)";
  }
  return "";
}

flapsim::WingCommand annCommandMsg(const flapsim::FlapUnitLayout& layout,
                                   const std::vector<flapsim::StrokeCommand>& strokes) {
  return toMsg(WingCommandRequest{layout.wing_joints, strokes});
}

}  // namespace flapsim_ros
