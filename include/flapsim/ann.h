// The paper's balance controller: a small feed-forward neural network per wing
// pair (sec. IV.A), on top of a general fully connected feed-forward net.
// ROS-free; no clock; plain structs for parameters.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/sensors.h"
#include "flapsim/stroke.h"
#include "flapsim/types.h"

namespace flapsim {

enum class Activation { kLinear, kTanh, kSigmoid };

/// "linear", "tanh", "sigmoid"; throws std::invalid_argument otherwise.
Activation activationFromString(const std::string& name);
std::string toString(Activation activation);

/// A fully connected feed-forward net. Parameters are one flat vector, layer
/// by layer; within a layer, neuron by neuron: its weights from every input
/// of the layer, then its bias. So a layer with n inputs and m neurons takes
/// m * (n + 1) numbers.
class FeedForwardNet {
 public:
  /// `layer_sizes` = {inputs, hidden..., outputs}, at least two entries, all
  /// >= 1. Parameters start at zero. Throws std::invalid_argument.
  FeedForwardNet(const std::vector<int>& layer_sizes, Activation hidden, Activation output);

  const std::vector<int>& layerSizes() const { return layer_sizes_; }
  int inputCount() const { return layer_sizes_.front(); }
  int outputCount() const { return layer_sizes_.back(); }
  int parameterCount() const { return parameterCount(layer_sizes_); }
  static int parameterCount(const std::vector<int>& layer_sizes);

  /// Throws std::invalid_argument for a wrong length or a non-finite value.
  void setParameters(const std::vector<double>& parameters);
  const std::vector<double>& parameters() const { return parameters_; }

  /// Throws std::invalid_argument for a wrong input length.
  std::vector<double> evaluate(const std::vector<double>& input) const;

 private:
  std::vector<int> layer_sizes_;
  Activation hidden_;
  Activation output_;
  std::vector<double> parameters_;
};

/// The per-unit network's form.
enum class FlapNetwork {
  /// The paper's: one net, output 0 the right wing's downstroke rate, output 1 the left's.
  kPaper,
  /// Left-right mirror-symmetric by construction (an extension): one net with one output,
  /// the right wing's rate from the unit's inputs; the left wing's rate is the same net on
  /// the mirrored inputs (the reflection y -> -y of the body: up . left, the roll rate and the
  /// yaw rate change sign). Half the weights of two outputs, and no steady bank in still air:
  /// a level unit commands equal rates whatever the weights.
  kMirror,
};

/// "paper", "mirror"; throws std::invalid_argument otherwise.
FlapNetwork flapNetworkFromString(const std::string& name);
std::string toString(FlapNetwork network);

/// Settings of the per-wing-pair network (the paper: 2 inputs, 2 hidden, 2
/// outputs). The outputs (sigmoid, 0..1) are mapped linearly (mixer_headroom 0) onto
/// [min_downstroke_rate, max_downstroke_rate]; upstroke rate and amplitude
/// are fixed here. The inputs (flapNetworkInputs) are the paper's two, then optionally the
/// unit's gyro rates and the altitude error; the output neurons' biases are the trim of the
/// rates (the rate commanded with every input zero).
struct FlapControllerParams {
  FlapNetwork network = FlapNetwork::kPaper;
  /// Gyro inputs (an extension): the unit body's roll, pitch and yaw rates (its angular
  /// velocity in its own axes, from the IMU), each divided by rate_scale. They let the net
  /// damp a roll before the attitude shows it (a gust, a push on a wing).
  bool rate_inputs = false;
  double rate_scale = 10.0;  // rad/s per unit input
  /// Altitude input (an extension): clamp((setpoint - altitude) / altitude_scale, -1, 1),
  /// the altimeter's error; +1 without a setpoint (climb, the paper's aim).
  bool altitude_input = false;
  double altitude_scale = 1.0;  // m
  /// Climb input (an extension): clamp(v_z / climb_scale, -1, 1), the root's vertical speed
  /// (m/s, > 0: climbing) from its velocity as a ground-speed sensor gives it (odometry's
  /// twist; FlapSensing::velocity, with its noise), turned into the world by the root's
  /// sensed attitude. With the altitude input it lets the net damp a climb or a sink before
  /// the altitude error grows, as a PD controller's derivative term does; the net has no
  /// memory to take it from the altimeter.
  bool climb_input = false;
  double climb_scale = 1.0;  // m/s per unit input
  /// Chain input (an extension for creatures of several units; off: the paper's): unit k of
  /// n sees s_k p, its place along the chain (s_k = 1 - 2k/(n-1): +1 at the nose, -1 at the
  /// tail) times the chain's mean pitch input p (world_up . body_forward averaged over the
  /// units, > 0: nose up), which its neighbours' attitudes make. Every unit's copy of the
  /// network then sees the chain pitch from where it sits, and evolution can find the
  /// nose-slow, tail-fast answer the hand-set pitch term (pitch_gain) gives. 0 on one unit.
  bool chain_input = false;
  int hidden = 2;
  Activation hidden_activation = Activation::kTanh;
  double min_downstroke_rate = 20.0;  // rad/s
  double max_downstroke_rate = 60.0;  // rad/s
  double upstroke_rate = 10.0;        // rad/s
  /// Upstroke output (an extension; 0: off, the upstrokes are upstroke_rate or phase-locked).
  /// The mirror network gets a second output per wing, its upstroke rate, mapped linearly
  /// onto [upstroke_rate, max_upstroke_rate]: evolution finds what the hand-set roll reflex
  /// does (a fast upstroke of the high wing and a slow one of the low wing push a roll back)
  /// wherever it helps. Needs network mirror and phase_lock off.
  double max_upstroke_rate = 0.0;  // rad/s
  /// Attitude-first mixer (an extension; 0: off, each output maps onto its rate's range as
  /// the paper's). With headroom h > 0 each output maps onto its range widened by h of its
  /// span at both ends, and the two wings' downstrokes, and their upstrokes, are mixed back
  /// into the range keeping their difference (the roll moment) first and moving their mean
  /// (climb or sink) by what that needs (outputRates, flapsim/output_mixer.h). Without it a
  /// pair near the end of its range has little difference left: the unit sinking hardest,
  /// both upstrokes at max_upstroke_rate, cannot roll back (doc/flight_and_evolution.md).
  double mixer_headroom = 0.0;
  double amplitude = 1.2;  // rad (at 0.8 the unit rolls over within ~2 s)
  /// Stroke offset (an extension; 0 is the paper's): both wings' stroke turns at
  /// stroke_offset -+ amplitude (rad; > 0 raises it). Raised strokes are a dihedral: air from
  /// the side pushes the windward wing up and the leeward one down, which rolls the unit away
  /// from a side wind instead of into it (doc/flight_and_evolution.md).
  double stroke_offset = 0.0;
  double control_period = 0.02;  // s between network updates
  /// Phase lock (an extension of the paper's controller): each wing's upstroke rate follows
  /// its downstroke rate so that its stroke period stays that of the middle downstroke rate
  /// with upstroke_rate, 2 theta0 (1/w1 + 1/w2). Without it a wing beating faster than the
  /// other drifts out of phase with it, and the body rocks in roll with a growing amplitude
  /// instead of turning (flap unit at 30/10 vs 60/10: +-35 deg within 3 s, mean roll 2 deg);
  /// locked, the faster wing lifts its side.
  bool phase_lock = false;
  /// Chain pitch term, an extension for creatures of several units (0: off, the paper's
  /// controller). Units chained by roll joints form a chain rigid in pitch, and every unit's
  /// network sees the same pitch, so no copy of it can make a pitching moment: a 12-unit chain
  /// started 5 deg nose up holds that pitch for ~15 s, then pitches over and sinks
  /// (doc/flight_and_evolution.md). With the term, unit k of n (s_k = 1 - 2k/(n-1): +1 at the
  /// nose, -1 at the tail) scales both its downstroke rates by
  /// 1 - clamp(pitch_gain s_k p, +-pitch_limit),
  /// where p = world_up . body_forward averaged over the units (> 0: nose up), and may exceed
  /// max_downstroke_rate up to pitch_max_downstroke_rate: while the nose is up, the nose beats
  /// slower and the tail faster. A unit's left/right ratio, its roll control, is kept.
  double pitch_gain = 0.0;
  double pitch_limit = 0.2;
  double pitch_max_downstroke_rate = 75.0;  // rad/s
  /// Roll reflex (an extension, set by hand, not evolved; roll_reflex_bank 0: off). The net
  /// can only steer the downstroke rates, and under phase_lock its upstrokes stay near
  /// upstroke_rate: a roll moment of a quarter of what a 1 N push on a wing makes. While a
  /// unit is banked beyond roll_reflex_bank (rad) and its gyro says it still rolls further
  /// over faster than roll_reflex_rate (rad/s), the reflex takes over its strokes: the low
  /// wing beats down at roll_reflex_fast_rate and up at roll_reflex_slow_rate (air pushes it
  /// up), the high wing the other way round (air pushes it down). The gyro is the body's:
  /// it swings by tens of rad/s with each stroke, so the bank gates it
  /// (doc/flight_and_evolution.md).
  double roll_reflex_bank = 0.0;        // rad
  double roll_reflex_rate = 5.0;        // rad/s
  double roll_reflex_fast_rate = 65.0;  // rad/s
  double roll_reflex_slow_rate = 40.0;  // rad/s
  /// Chain pitch reflex (an extension for chains, set by hand, not evolved;
  /// pitch_reflex_angle 0: off). The chain pitch term steers only the downstroke rates, and
  /// pinned at pitch_limit it cannot right a chain that a side wind has pitched over: the
  /// chain sinks, and its slow upstrokes, which under phase_lock take most of each stroke,
  /// meet the air rising past it and push it down. While the chain's mean pitch is beyond
  /// pitch_reflex_angle (rad, either way), the units of its low end beat down at
  /// pitch_reflex_fast_rate and up at pitch_reflex_slow_rate (the air pushes them up), those of
  /// its high end the other way round (the air pushes them down): the units whose |s_k|
  /// (chainPitchScale's) exceeds pitch_reflex_ends; the middle ones keep their command
  /// (doc/flight_and_evolution.md). "Beat down at" is the pair's mean: each wing's downstroke
  /// keeps its share of the network's (within min_downstroke_rate and
  /// pitch_max_downstroke_rate), so the unit keeps its roll control while the reflex acts.
  double pitch_reflex_angle = 0.0;       // rad
  double pitch_reflex_ends = 0.3;        // of |s_k| in [0, 1]
  double pitch_reflex_fast_rate = 65.0;  // rad/s
  double pitch_reflex_slow_rate = 40.0;  // rad/s
  /// Attitude filter (an extension, set by hand, not evolved; 0: off): the time constant (s)
  /// of the complementary filter (AttitudeFilter, flapsim/sensors.h) that whoever runs the
  /// controller puts between the root's IMU and unitSensing(): the episodes of evolution and
  /// flight_check, and ann_controller on <creature>/imu. The IMU's orientation noise reaches
  /// every unit's input at once through the joint encoders, and the chain's reflexes act on
  /// thresholds it crosses (doc/flight_and_evolution.md).
  double attitude_filter_time = 0.0;  // s
  /// Ground-speed damping (an extension, set by hand, not evolved; 0: off). Levelled, a
  /// flier keeps any horizontal speed it picks up: the chain's air damping is weak (0.16 deg
  /// of mean pitch carried the 12-unit chain 21 m in a minute), and no attitude input can
  /// tell it moves. With the root's velocity sensed (FlapSensing::velocity, from
  /// odometry's twist through ROS), every unit's network and the chain pitch term see the
  /// world's up tilted against the horizontal velocity v by min(velocity_gain |v|,
  /// velocity_tilt_limit) rad: holding "level" then tilts the flier back, its thrust brakes
  /// the speed (the velocity loop of a multirotor cascade,
  /// doc/flight_and_evolution.md).
  double velocity_gain = 0.0;         // rad per m/s
  double velocity_tilt_limit = 0.05;  // rad
};

/// The up direction a controller with ground-speed damping levels the units to: the world's
/// up tilted away from the root's horizontal velocity (`velocity`, in the root's axes as
/// odometry reports it; `root` the root's sensed orientation) by min(velocity_gain |v_h|,
/// velocity_tilt_limit). The world's up if velocity_gain is 0.
Vec3 levelledUp(const FlapControllerParams& params, const Quat& root, const Vec3& velocity);

/// The factor unit `unit` of `units` scales its downstroke rates by under the chain pitch
/// term, for a mean pitch input `pitch` (world_up . body_forward); 1 for a single unit or
/// pitch_gain 0.
double chainPitchScale(const FlapControllerParams& params, int unit, int units, double pitch);

/// The upstroke rate of a wing whose downstroke rate is `downstroke` under `params`: the
/// fixed upstroke_rate, or with phase_lock the one that keeps the stroke period.
double upstrokeRate(const FlapControllerParams& params, double downstroke);

/// Limits of the network's settings (doc/reliability.md).
constexpr int kMaxHidden = 256;             // hidden neurons
constexpr double kMinControlPeriod = 1e-3;  // s: at most 1 kHz of network updates
constexpr double kMaxControlPeriod = 10.0;  // s
constexpr double kMaxPitchGain = 1e3;
constexpr double kMaxInputScale = 1e6;  // rate_scale, altitude_scale, climb_scale

/// Empty if valid, else a message naming the bad field.
std::string validateFlapControllerParams(const FlapControllerParams& params);

/// The paper's inputs for a unit body with orientation `body` (body x =
/// forward, y = left wing direction, z = up): {world_up . body_x,
/// world_up . body_y}. A unit rolled to the right (right wing low) has
/// input[1] > 0; nose up has input[0] > 0.
std::vector<double> flapInputs(const Quat& body);

/// The inputs of the network `params` describes, for one unit: flapInputs(body), then with
/// rate_inputs its body-frame angular velocity / rate_scale (roll, pitch, yaw), then with
/// altitude_input `altitude_input` (see FlapControllerParams::altitude_input), then with
/// climb_input `climb_input` (climbInput()), then with chain_input `chain_pitch` (chainInput()).
std::vector<double> flapNetworkInputs(const FlapControllerParams& params, const Quat& body,
                                      const Vec3& rate, double altitude_input,
                                      double chain_pitch = 0.0, double climb_input = 0.0);
/// The climb input for the root's sensed attitude `root` and velocity `velocity` in its own
/// axes (FlapControllerParams::climb_input): clamp(v_z / climb_scale, -1, 1).
double climbInput(const FlapControllerParams& params, const Quat& root, const Vec3& velocity);
/// The chain input of unit `unit` of `units` for the chain's mean pitch input `pitch`
/// (FlapControllerParams::chain_input): s_k pitch, 0 for a single unit.
double chainInput(int unit, int units, double pitch);
/// Their count, and their names as the weights file lists them.
int flapInputCount(const FlapControllerParams& params);
std::vector<std::string> flapInputNames(const FlapControllerParams& params);
std::vector<std::string> flapOutputNames(const FlapControllerParams& params);

/// The inputs of the mirror image of a unit (FlapNetwork::kMirror): up . left, the roll rate
/// and the yaw rate negated.
std::vector<double> mirroredInputs(const FlapControllerParams& params,
                                   const std::vector<double>& inputs);

/// The altitude input for an altimeter reading `altitude` and a setpoint (none: climb, +1).
double altitudeInput(const FlapControllerParams& params, double altitude,
                     const std::optional<double>& setpoint);

/// Left and right wing stroke of one unit.
struct WingPairCommand {
  StrokeCommand left;
  StrokeCommand right;
};

/// The roll reflex (FlapControllerParams::roll_reflex_bank) on a unit with orientation `body`
/// and body-frame angular velocity `rate`: replaces `command`'s stroke rates if it acts, and
/// says whether it did.
bool applyRollReflex(const FlapControllerParams& params, const Quat& body, const Vec3& rate,
                     WingPairCommand& command);

/// The chain pitch reflex (FlapControllerParams::pitch_reflex_angle) on unit `unit` of
/// `units`, for the chain's mean pitch input `pitch` (world_up . body_forward, > 0: nose up):
/// replaces `command`'s stroke rates if it acts, and says whether it did.
bool applyPitchReflex(const FlapControllerParams& params, int unit, int units, double pitch,
                      WingPairCommand& command);

/// One unit's network: output 0 = right downstroke rate, output 1 = left
/// (the paper's order).
class FlapUnitController {
 public:
  /// Throws std::invalid_argument on bad params or a wrong weight count.
  FlapUnitController(const FlapControllerParams& params, const std::vector<double>& weights);
  static int weightCount(const FlapControllerParams& params);

  /// The command for a unit at `body`, turning at `rate` (own axes), with altitude input
  /// `altitude_input` (altitudeInput()), chain input `chain_pitch` (chainInput()) and climb
  /// input `climb_input` (climbInput()); the last four are read only if the net takes them.
  WingPairCommand command(const Quat& body, const Vec3& rate = Vec3::Zero(),
                          double altitude_input = 1.0, double chain_pitch = 0.0,
                          double climb_input = 0.0) const;
  /// Downstroke rates {right, left} for raw inputs (flapNetworkInputs; for tests and plots).
  std::vector<double> rates(const std::vector<double>& inputs) const;
  /// The strokes of both wings for raw inputs.
  WingPairCommand strokes(const std::vector<double>& inputs) const;

  const FlapControllerParams& params() const { return params_; }
  const std::vector<double>& weights() const { return net_.parameters(); }

 private:
  FlapControllerParams params_;
  FeedForwardNet net_;
};

/// Names of a chain of flap units as makeCreatureUrdf() builds them: unit k
/// has body link `unit<k>_body` and wing joints `unit<k>_wing_left_joint`,
/// `unit<k>_wing_right_joint`.
struct FlapUnitLayout {
  std::vector<std::string> body_links;   // one per unit
  std::vector<std::string> wing_joints;  // left, right per unit
  int units() const { return static_cast<int>(body_links.size()); }
};

/// Layout for `pairs` units (>= 1; std::invalid_argument otherwise).
FlapUnitLayout flapUnitLayout(int pairs);
/// Layout of every unit found in `model` (unit0, unit1, ... while present).
/// Throws InputError if there is no unit0 or a unit lacks a wing joint.
FlapUnitLayout flapUnitLayout(const CreatureModel& model);

/// Something that turns the sensed units (FlapSensing) into stroke commands in
/// FlapUnitLayout::wing_joints order (left, right per unit).
class WingController {
 public:
  virtual ~WingController() = default;
  virtual std::vector<StrokeCommand> commands(const FlapSensing& sensed) const = 0;
  /// The time constant of the attitude filter its runner puts before unitSensing() (s; 0:
  /// the IMU's orientation as it reads).
  virtual double attitudeFilterTime() const { return 0.0; }
};

/// The same network on every unit (the paper's multi-pair creatures), with the chain pitch
/// term of its params on top (FlapControllerParams::pitch_gain), holding the sensing's
/// setpoint if it has one (FlapSensing::setpoint), else climbing.
class AnnWingController : public WingController {
 public:
  explicit AnnWingController(const FlapUnitController& unit) : unit_(unit) {}
  std::vector<StrokeCommand> commands(const FlapSensing& sensed) const override;
  double attitudeFilterTime() const override { return unit_.params().attitude_filter_time; }
  const FlapUnitController& unit() const { return unit_; }

 private:
  FlapUnitController unit_;
};

/// A fixed stroke on every wing, whatever the orientation (open loop).
class OpenLoopWingController : public WingController {
 public:
  explicit OpenLoopWingController(const StrokeCommand& stroke) : stroke_(stroke) {}
  std::vector<StrokeCommand> commands(const FlapSensing& sensed) const override;

 private:
  StrokeCommand stroke_;
};

}  // namespace flapsim
