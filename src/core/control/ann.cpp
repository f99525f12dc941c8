#include "flapsim/ann.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "flapsim/output_mixer.h"

namespace flapsim {

namespace {

double activate(Activation a, double x) {
  switch (a) {
    case Activation::kTanh:
      return std::tanh(x);
    case Activation::kSigmoid:
      return 1.0 / (1.0 + std::exp(-x));
    case Activation::kLinear:
      break;
  }
  return x;
}

// Unit `unit`'s place along a chain of `units` (>= 2): s_k = 1 - 2k/(n-1), +1 at the nose,
// -1 at the tail (the chain pitch term's and the pitch reflex's).
double chainPosition(int unit, int units) { return 1.0 - 2.0 * unit / (units - 1); }

}  // namespace

Activation activationFromString(const std::string& name) {
  if (name == "linear") return Activation::kLinear;
  if (name == "tanh") return Activation::kTanh;
  if (name == "sigmoid") return Activation::kSigmoid;
  throw std::invalid_argument("unknown activation '" + name +
                              "' (expected linear, tanh or sigmoid)");
}

std::string toString(Activation a) {
  switch (a) {
    case Activation::kTanh:
      return "tanh";
    case Activation::kSigmoid:
      return "sigmoid";
    case Activation::kLinear:
      break;
  }
  return "linear";
}

// ---- FeedForwardNet ------------------------------------------------------------------------

FeedForwardNet::FeedForwardNet(const std::vector<int>& layer_sizes, Activation hidden,
                               Activation output)
    : layer_sizes_(layer_sizes), hidden_(hidden), output_(output) {
  parameters_.assign(parameterCount(layer_sizes), 0.0);
}

int FeedForwardNet::parameterCount(const std::vector<int>& sizes) {
  if (sizes.size() < 2) throw std::invalid_argument("a net needs at least two layers");
  int count = 0;
  for (size_t l = 0; l < sizes.size(); ++l) {
    if (sizes[l] < 1) {
      throw std::invalid_argument("layer " + std::to_string(l) + " has " +
                                  std::to_string(sizes[l]) + " neurons (need >= 1)");
    }
    if (l > 0) count += sizes[l] * (sizes[l - 1] + 1);
  }
  return count;
}

void FeedForwardNet::setParameters(const std::vector<double>& p) {
  if (static_cast<int>(p.size()) != parameterCount()) {
    throw std::invalid_argument("net takes " + std::to_string(parameterCount()) +
                                " parameters, got " + std::to_string(p.size()));
  }
  for (size_t i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p[i])) {
      throw std::invalid_argument("net parameter " + std::to_string(i) + " is not finite");
    }
  }
  parameters_ = p;
}

std::vector<double> FeedForwardNet::evaluate(const std::vector<double>& input) const {
  if (static_cast<int>(input.size()) != inputCount()) {
    throw std::invalid_argument("net takes " + std::to_string(inputCount()) + " inputs, got " +
                                std::to_string(input.size()));
  }
  std::vector<double> x = input;
  size_t k = 0;
  for (size_t l = 1; l < layer_sizes_.size(); ++l) {
    const Activation act = l + 1 == layer_sizes_.size() ? output_ : hidden_;
    std::vector<double> y(layer_sizes_[l]);
    for (double& yj : y) {
      double sum = 0.0;
      for (double xi : x) sum += parameters_[k++] * xi;
      sum += parameters_[k++];  // bias
      yj = activate(act, sum);
    }
    x.swap(y);
  }
  return x;
}

// ---- The per-wing-pair controller ------------------------------------------------------------

FlapNetwork flapNetworkFromString(const std::string& name) {
  if (name == "paper") return FlapNetwork::kPaper;
  if (name == "mirror") return FlapNetwork::kMirror;
  throw std::invalid_argument("unknown network '" + name + "' (expected paper or mirror)");
}

std::string toString(FlapNetwork network) {
  return network == FlapNetwork::kMirror ? "mirror" : "paper";
}

namespace {

// The upstroke output's settings (max_upstroke_rate).
std::string upstrokeOutputError(const FlapControllerParams& p) {
  if (p.max_upstroke_rate == 0.0) return "";
  if (!(p.max_upstroke_rate > p.upstroke_rate && p.max_upstroke_rate <= kMaxStrokeRate)) {
    return "max_upstroke_rate must be 0 (off) or in (upstroke_rate, 1e5] rad/s";
  }
  if (p.network != FlapNetwork::kMirror) return "max_upstroke_rate needs network mirror";
  if (p.phase_lock) return "max_upstroke_rate needs phase_lock off (the net sets the upstrokes)";
  return "";
}

// Empty if the inputs' scales are in (0, kMaxInputScale], else the first that is not.
std::string inputScaleError(const FlapControllerParams& p) {
  for (const auto& [name, v] : {std::pair<const char*, double>{"rate_scale", p.rate_scale},
                                {"altitude_scale", p.altitude_scale},
                                {"climb_scale", p.climb_scale}}) {
    if (!(v > 0.0 && v <= kMaxInputScale)) return std::string(name) + " must be in (0, 1e6]";
  }
  return "";
}

}  // namespace

std::string validateFlapControllerParams(const FlapControllerParams& p) {
  if (p.hidden < 1 || p.hidden > kMaxHidden) {
    return "hidden must be in [1, " + std::to_string(kMaxHidden) + "]";
  }
  if (!(p.max_downstroke_rate <= kMaxStrokeRate && p.upstroke_rate <= kMaxStrokeRate &&
        p.pitch_max_downstroke_rate <= kMaxStrokeRate && p.amplitude <= kMaxStrokeAmplitude)) {
    return "rates must be at most 1e5 rad/s, the amplitude at most 1000 rad";
  }
  const std::string scale = inputScaleError(p);
  if (!scale.empty()) return scale;
  if (!std::isfinite(p.min_downstroke_rate) || p.min_downstroke_rate < 0.0) {
    return "min_downstroke_rate must be finite and >= 0";
  }
  if (!std::isfinite(p.max_downstroke_rate) || p.max_downstroke_rate < p.min_downstroke_rate) {
    return "max_downstroke_rate must be finite and >= min_downstroke_rate";
  }
  if (!std::isfinite(p.upstroke_rate) || p.upstroke_rate < 0.0) {
    return "upstroke_rate must be finite and >= 0";
  }
  if (!std::isfinite(p.amplitude) || p.amplitude <= 0.0) return "amplitude must be > 0";
  if (!(std::abs(p.stroke_offset) <= kMaxStrokeAmplitude)) {
    return "stroke_offset must be finite and within +-1000 rad";
  }
  if (!(p.control_period >= kMinControlPeriod && p.control_period <= kMaxControlPeriod)) {
    return "control_period must be in [0.001, 10] s";
  }
  if (p.phase_lock &&
      !(p.min_downstroke_rate > 0.0 && p.upstroke_rate > 0.0 &&
        1.0 / p.min_downstroke_rate <
            2.0 / (p.min_downstroke_rate + p.max_downstroke_rate) + 1.0 / p.upstroke_rate)) {
    return "phase_lock needs min_downstroke_rate > 0, upstroke_rate > 0 and a downstroke at "
           "min_downstroke_rate shorter than the locked period";
  }
  for (const std::string& e : {upstrokeOutputError(p), mixerHeadroomError(p.mixer_headroom)}) {
    if (!e.empty()) return e;
  }
  if (!(p.pitch_gain >= 0.0 && p.pitch_gain <= kMaxPitchGain)) {
    return "pitch_gain must be in [0, 1000]";
  }
  if (!std::isfinite(p.pitch_limit) || p.pitch_limit < 0.0 || p.pitch_limit >= 1.0) {
    return "pitch_limit must be in [0, 1)";
  }
  if (!std::isfinite(p.pitch_max_downstroke_rate) ||
      p.pitch_max_downstroke_rate < p.max_downstroke_rate) {
    return "pitch_max_downstroke_rate must be finite and >= max_downstroke_rate";
  }
  if (!(p.roll_reflex_bank >= 0.0 && p.roll_reflex_bank < M_PI / 2)) {
    return "roll_reflex_bank must be in [0, pi/2) rad";
  }
  if (!(p.roll_reflex_rate >= 0.0 && p.roll_reflex_rate <= kMaxStrokeRate)) {
    return "roll_reflex_rate must be in [0, 1e5] rad/s";
  }
  if (!(p.pitch_reflex_angle >= 0.0 && p.pitch_reflex_angle < M_PI / 2)) {
    return "pitch_reflex_angle must be in [0, pi/2) rad";
  }
  if (!(p.pitch_reflex_ends >= 0.0 && p.pitch_reflex_ends < 1.0)) {
    return "pitch_reflex_ends must be in [0, 1)";
  }
  if (!(p.attitude_filter_time >= 0.0 && p.attitude_filter_time <= 10.0)) {
    return "attitude_filter_time must be in [0, 10] s";
  }
  if (!(p.velocity_gain >= 0.0 && p.velocity_gain <= 10.0)) {
    return "velocity_gain must be in [0, 10] rad per m/s";
  }
  if (!(p.velocity_tilt_limit >= 0.0 && p.velocity_tilt_limit <= 0.5)) {
    return "velocity_tilt_limit must be in [0, 0.5] rad";
  }
  for (const auto& [name, rate] :
       {std::pair<const char*, double>{"roll_reflex_fast_rate", p.roll_reflex_fast_rate},
        {"roll_reflex_slow_rate", p.roll_reflex_slow_rate},
        {"pitch_reflex_fast_rate", p.pitch_reflex_fast_rate},
        {"pitch_reflex_slow_rate", p.pitch_reflex_slow_rate}}) {
    if (!(rate > 0.0 && rate <= kMaxStrokeRate)) {
      return std::string(name) + " must be in (0, 1e5] rad/s";
    }
  }
  return "";
}

bool applyRollReflex(const FlapControllerParams& p, const Quat& body, const Vec3& rate,
                     WingPairCommand& command) {
  if (p.roll_reflex_bank <= 0.0) return false;
  // world_up . body_left = sin(bank), > 0 with the right wing low (flapInputs); a positive
  // roll rate about body x lowers the right wing further.
  const double bank = std::asin(std::clamp(flapInputs(body)[1], -1.0, 1.0));
  const double over = bank > 0.0 ? rate.x() : -rate.x();
  if (!(std::abs(bank) > p.roll_reflex_bank && over > p.roll_reflex_rate)) return false;
  StrokeCommand& low = bank > 0.0 ? command.right : command.left;
  StrokeCommand& high = bank > 0.0 ? command.left : command.right;
  low.downstroke_rate = high.upstroke_rate = p.roll_reflex_fast_rate;
  low.upstroke_rate = high.downstroke_rate = p.roll_reflex_slow_rate;
  return true;
}

bool applyPitchReflex(const FlapControllerParams& p, int unit, int units, double pitch,
                      WingPairCommand& command) {
  if (p.pitch_reflex_angle <= 0.0 || units < 2) return false;
  if (!(std::abs(pitch) > std::sin(p.pitch_reflex_angle))) return false;
  const double s = chainPosition(unit, units);
  if (!(std::abs(s) > p.pitch_reflex_ends)) return false;
  // Nose up (pitch > 0): the tail (s < 0) is the low end, and needs the lift.
  const bool low = s * pitch < 0.0;
  // The unit's left/right ratio, its roll control, is kept: the pair's mean downstroke rate
  // goes to the reflex's, each wing's scaled by its share of the network's mean.
  const double mean = 0.5 * (command.left.downstroke_rate + command.right.downstroke_rate);
  for (StrokeCommand* w : {&command.left, &command.right}) {
    const double rate = low ? p.pitch_reflex_fast_rate : p.pitch_reflex_slow_rate;
    w->downstroke_rate = std::clamp(rate * (w->downstroke_rate / mean), p.min_downstroke_rate,
                                    p.pitch_max_downstroke_rate);
    w->upstroke_rate = low ? p.pitch_reflex_slow_rate : p.pitch_reflex_fast_rate;
  }
  return true;
}

Vec3 levelledUp(const FlapControllerParams& p, const Quat& root, const Vec3& velocity) {
  Vec3 horizontal = root * velocity;
  horizontal.z() = 0.0;
  const double speed = horizontal.norm();
  if (p.velocity_gain == 0.0 || !(speed > 0.0)) return Vec3::UnitZ();
  const double tilt = std::min(p.velocity_gain * speed, p.velocity_tilt_limit);
  return std::cos(tilt) * Vec3::UnitZ() - std::sin(tilt) / speed * horizontal;
}

double chainPitchScale(const FlapControllerParams& p, int unit, int units, double pitch) {
  if (units < 2 || p.pitch_gain == 0.0) return 1.0;
  const double s = chainPosition(unit, units);
  return 1.0 - std::clamp(p.pitch_gain * s * pitch, -p.pitch_limit, p.pitch_limit);
}

double upstrokeRate(const FlapControllerParams& p, double downstroke) {
  if (!p.phase_lock) return p.upstroke_rate;
  // Period T = 2 a (1/w_mid + 1/w_up); the wing's upstroke takes what its downstroke leaves.
  const double middle = 0.5 * (p.min_downstroke_rate + p.max_downstroke_rate);
  const double up_time = 1.0 / middle + 1.0 / p.upstroke_rate - 1.0 / downstroke;
  return 1.0 / up_time;
}

std::vector<double> flapInputs(const Quat& body) {
  const Eigen::Matrix3d r = body.normalized().toRotationMatrix();
  // Column i of r is body axis i in the world; its z component is world_up . axis.
  return {r(2, 0), r(2, 1)};
}

int flapInputCount(const FlapControllerParams& p) {
  return 2 + (p.rate_inputs ? 3 : 0) + (p.altitude_input ? 1 : 0) + (p.climb_input ? 1 : 0) +
         (p.chain_input ? 1 : 0);
}

double chainInput(int unit, int units, double pitch) {
  return units < 2 ? 0.0 : chainPosition(unit, units) * pitch;
}

std::vector<std::string> flapInputNames(const FlapControllerParams& p) {
  std::vector<std::string> names = {"world_up.body_forward", "world_up.body_left"};
  if (p.rate_inputs) names.insert(names.end(), {"roll_rate", "pitch_rate", "yaw_rate"});
  if (p.altitude_input) names.push_back("altitude_error");
  if (p.climb_input) names.push_back("climb_rate");
  if (p.chain_input) names.push_back("chain_position.chain_pitch");
  return names;
}

std::vector<std::string> flapOutputNames(const FlapControllerParams& p) {
  if (p.network == FlapNetwork::kMirror && p.max_upstroke_rate > 0.0) {
    return {"right_downstroke_rate", "right_upstroke_rate"};
  }
  if (p.network == FlapNetwork::kMirror) return {"right_downstroke_rate"};
  return {"right_downstroke_rate", "left_downstroke_rate"};
}

std::vector<double> flapNetworkInputs(const FlapControllerParams& p, const Quat& body,
                                      const Vec3& rate, double altitude_input, double chain_pitch,
                                      double climb_input) {
  std::vector<double> x = flapInputs(body);
  if (p.rate_inputs) {
    for (int i = 0; i < 3; ++i) x.push_back(rate[i] / p.rate_scale);
  }
  if (p.altitude_input) x.push_back(altitude_input);
  if (p.climb_input) x.push_back(climb_input);
  if (p.chain_input) x.push_back(chain_pitch);
  return x;
}

std::vector<double> mirroredInputs(const FlapControllerParams& p,
                                   const std::vector<double>& inputs) {
  std::vector<double> m = inputs;
  m[1] = -m[1];  // up . left
  if (p.rate_inputs) {
    m[2] = -m[2];  // roll rate (a pseudovector's x and z change sign under y -> -y)
    m[4] = -m[4];  // yaw rate
  }
  return m;
}

double altitudeInput(const FlapControllerParams& p, double altitude,
                     const std::optional<double>& setpoint) {
  if (!setpoint) return 1.0;
  return std::clamp((*setpoint - altitude) / p.altitude_scale, -1.0, 1.0);
}

double climbInput(const FlapControllerParams& p, const Quat& root, const Vec3& velocity) {
  return std::clamp((root * velocity).z() / p.climb_scale, -1.0, 1.0);
}

namespace {
const FlapControllerParams& checked(const FlapControllerParams& p) {
  const std::string err = validateFlapControllerParams(p);
  if (!err.empty()) throw std::invalid_argument("flap controller: " + err);
  return p;
}

// The layer sizes of the net `p` describes.
std::vector<int> netLayers(const FlapControllerParams& p) {
  return {flapInputCount(p), p.hidden, static_cast<int>(flapOutputNames(p).size())};
}

}  // namespace

FlapUnitController::FlapUnitController(const FlapControllerParams& params,
                                       const std::vector<double>& weights)
    : params_(checked(params)),
      net_(netLayers(params), params.hidden_activation, Activation::kSigmoid) {
  net_.setParameters(weights);
}

int FlapUnitController::weightCount(const FlapControllerParams& params) {
  return FeedForwardNet::parameterCount(netLayers(checked(params)));
}

WingPairCommand FlapUnitController::strokes(const std::vector<double>& inputs) const {
  const FlapControllerParams& p = params_;
  const std::vector<double> y = net_.evaluate(inputs);
  // The downstroke and upstroke outputs in 0..1 (upstroke: -1 if the net has none)
  WingRates down{y[0], 0.0}, up{-1.0, -1.0};
  if (p.network == FlapNetwork::kMirror) {
    const std::vector<double> left = net_.evaluate(mirroredInputs(p, inputs));
    down.left = left[0];
    if (p.max_upstroke_rate > 0.0) up = {y[1], left[1]};
  } else {
    down.left = y[1];
  }
  const double h = p.mixer_headroom;
  const WingRates d = outputRates(down, p.min_downstroke_rate, p.max_downstroke_rate, h);
  const WingRates u = up.right < 0.0 ? WingRates{upstrokeRate(p, d.right), upstrokeRate(p, d.left)}
                                     : outputRates(up, p.upstroke_rate, p.max_upstroke_rate, h);
  WingPairCommand c;
  c.right = StrokeCommand{d.right, u.right, p.amplitude};
  c.left = StrokeCommand{d.left, u.left, p.amplitude};
  c.right.offset = c.left.offset = p.stroke_offset;
  return c;
}

std::vector<double> FlapUnitController::rates(const std::vector<double>& inputs) const {
  const WingPairCommand c = strokes(inputs);
  return {c.right.downstroke_rate, c.left.downstroke_rate};
}

WingPairCommand FlapUnitController::command(const Quat& body, const Vec3& rate,
                                            double altitude_input, double chain_pitch,
                                            double climb_input) const {
  return strokes(flapNetworkInputs(params_, body, rate, altitude_input, chain_pitch, climb_input));
}

// ---- Layout and wing controllers -------------------------------------------------------------

FlapUnitLayout flapUnitLayout(int pairs) {
  if (pairs < 1) throw std::invalid_argument("pairs must be >= 1, got " + std::to_string(pairs));
  FlapUnitLayout layout;
  for (int k = 0; k < pairs; ++k) {
    const std::string u = "unit" + std::to_string(k);
    layout.body_links.push_back(u + "_body");
    layout.wing_joints.push_back(u + "_wing_left_joint");
    layout.wing_joints.push_back(u + "_wing_right_joint");
  }
  return layout;
}

FlapUnitLayout flapUnitLayout(const CreatureModel& model) {
  FlapUnitLayout layout;
  for (int k = 0;; ++k) {
    const std::string u = "unit" + std::to_string(k);
    if (model.findLink(u + "_body") < 0) break;
    for (const char* side : {"_wing_left_joint", "_wing_right_joint"}) {
      const int j = model.findJoint(u + side);
      if (j < 0 || !model.joints[j].wing) {
        throw InputError("creature '" + model.name + "' (" + model.source + "): unit " +
                         std::to_string(k) + " has no wing joint '" + u + side + "'");
      }
      layout.wing_joints.push_back(u + side);
    }
    layout.body_links.push_back(u + "_body");
  }
  if (layout.body_links.empty()) {
    throw InputError("creature '" + model.name + "' (" + model.source +
                     ") has no flap unit (no link 'unit0_body')");
  }
  return layout;
}

std::vector<StrokeCommand> AnnWingController::commands(const FlapSensing& sensed) const {
  const FlapControllerParams& p = unit_.params();
  if (sensed.rates.size() != sensed.orientations.size()) {
    throw std::invalid_argument("ann controller: " + std::to_string(sensed.rates.size()) +
                                " rates for " + std::to_string(sensed.orientations.size()) +
                                " units");
  }
  // Ground-speed damping: the units level to an up tilted against the velocity, i.e. see
  // themselves turned by the rotation that takes that up to the world's.
  std::vector<Quat> tilted;
  if (p.velocity_gain > 0.0 && sensed.velocity && !sensed.orientations.empty()) {
    const Vec3 up = levelledUp(p, sensed.orientations[0], *sensed.velocity);
    const Quat turn = Quat::FromTwoVectors(up, Vec3::UnitZ());
    for (const Quat& q : sensed.orientations) tilted.push_back((turn * q).normalized());
  }
  const std::vector<Quat>& bodies = tilted.empty() ? sensed.orientations : tilted;
  const double altitude = altitudeInput(p, sensed.altitude, sensed.setpoint);
  double climb = 0.0;
  if (p.climb_input) {
    if (!sensed.velocity || sensed.orientations.empty()) {
      throw std::invalid_argument("ann controller: the climb input needs the root's velocity");
    }
    climb = climbInput(p, sensed.orientations[0], *sensed.velocity);
  }
  const int units = static_cast<int>(bodies.size());
  double pitch = 0.0;
  if (p.pitch_gain > 0.0 || p.pitch_reflex_angle > 0.0 || p.chain_input) {
    for (const Quat& q : bodies) pitch += flapInputs(q)[0];
    pitch /= std::max(1, units);
  }
  std::vector<StrokeCommand> out;
  out.reserve(2 * bodies.size());
  for (int k = 0; k < units; ++k) {
    WingPairCommand c =
        unit_.command(bodies[k], sensed.rates[k], altitude, chainInput(k, units, pitch), climb);
    const double scale = chainPitchScale(p, k, units, pitch);
    if (scale != 1.0) {
      for (StrokeCommand* s : {&c.left, &c.right}) {
        s->downstroke_rate = std::clamp(scale * s->downstroke_rate, p.min_downstroke_rate,
                                        p.pitch_max_downstroke_rate);
        if (p.max_upstroke_rate == 0.0) s->upstroke_rate = upstrokeRate(p, s->downstroke_rate);
      }
    }
    applyRollReflex(p, bodies[k], sensed.rates[k], c);
    applyPitchReflex(p, k, units, pitch, c);
    out.push_back(c.left);
    out.push_back(c.right);
  }
  return out;
}

std::vector<StrokeCommand> OpenLoopWingController::commands(const FlapSensing& sensed) const {
  return std::vector<StrokeCommand>(2 * sensed.orientations.size(), stroke_);
}

}  // namespace flapsim
