// The flight check: a creature flown by its controller from held-out starts (a seed of its
// own, not the evolution's), in still air or in disturbances nobody trained on (a steady
// wind from a heading drawn per start, a roll torque or a push on a wing at a time drawn
// per start, sensor noise), climbing or holding an altitude; each start reported as flipped
// or not, its lowest up-component, its final and lowest height, the fraction of time it was
// upright, the altitude error's rms after 10 s, its lateral drift and its mean bank. Used by
// the flight_check executable and the tests. ROS-free; no clock.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/cli_args.h"
#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"
#include "flapsim/hover_flight.h"

namespace flapsim {

struct FlightCheckParams {
  int starts = 20;
  std::uint64_t seed = 2024;  // held out: evolution draws its starts from mixSeed(ga seed)
  double max_roll = 0.26;     // rad (15 deg): roll uniform in +-max_roll
  double max_pitch = 0.26;    // rad: pitch uniform in +-max_pitch
  double duration = 60.0;     // s
  double start_height = 1.0;  // m, root body
  double step_size = 0.001;   // s
  double turn_substep = WorldParams().turn_substep;  // s (0: off)
  int threads = 1;                                   // results do not depend on it
  // Disturbances (EpisodeParams says how each is drawn per start from `seed`).
  double wind = 0.0;  // m/s: steady from t = 0, from a heading drawn per start
  double gust_torque =
      0.0;  // N m: a roll torque at a drawn time (10-60 % of the flight), sign drawn
  double gust_force = 0.0;      // N: a vertical push (> 0: up) on gust_link at a drawn time
  std::string gust_link;        // empty: a wing drawn per start, pushed up or down
  double gust_time = 0.5;       // s: how long each gust acts
  double noise = 0.0;           // the IMU's noise: orientation (rad) and angular velocity (rad/s)
  double altitude_noise = 0.0;  // m: the altimeter's
  double velocity_noise = 0.0;  // m/s: the ground-speed sensor's
  // the air's AirParams::added_mass_products
  AddedMassProducts added_mass_products = AddedMassProducts::kShed;
  MotorWorkMeter motor_work = WorldParams().motor_work;  // how the W/kg figures take the work
  /// Dryden turbulence: the wind at 6 m (0: none; turbulenceLevelWind), at the episode's
  /// height (its altitude setpoint, else its start height; at least 10 ft), a realisation
  /// per start.
  double turbulence = 0.0;
  double gyro_bias = 0.0;  // rad/s: a constant bias per start, up to this, any direction
  /// Real air, all at once (realAirParams): a steady 1 m/s wind, light turbulence, a roll
  /// torque for 0.5 s and a push on a drawn wing for 0.2 s at drawn times, IMU noise, a gyro
  /// bias and altimeter noise.
  bool real_air = false;
  /// With real_air: this roll torque (N m) and push (N) instead of real air's (0: none; their
  /// signs are drawn), from flight_check --real-air --gust-torque T / --gust-force F.
  std::optional<double> real_air_torque, real_air_force;
  /// With real_air: this steady wind (m/s, its heading drawn) and turbulence (the wind at 6 m,
  /// m/s; 0: none) instead of real air's 1 m/s and light, from flight_check --real-air --wind
  /// SPEED / --turbulence LEVEL (the "moderate turbulence and 2 m/s wind").
  std::optional<double> real_air_wind, real_air_turbulence;
  std::optional<double> altitude;  // m: hold it (the root link frame's height); none: climb
  int trace_start = -1;            // record this start's samples (FlightCheckRun::trace); -1: none
};

/// `p` with real air's settings for `model` (p.real_air): wind 1 m/s from a drawn heading,
/// light turbulence, a roll torque of 0.5 x weight x half-span (the creature's, N m) for
/// 0.5 s and a push of 4 x the weight of the pushed wing's unit (N) for 0.2 s at drawn times
/// (afc_1: 0.043 N m and 0.90 N), IMU noise 0.05 rad and 0.05 rad/s, a gyro bias up to
/// 0.02 rad/s, altimeter noise 0.05 m.
FlightCheckParams realAirParams(FlightCheckParams p, const CreatureModel& model);

/// "real air", and the wind and turbulence given instead of its own (p.real_air_wind,
/// _turbulence): the reports' name for the air flown.
std::string realAirName(const FlightCheckParams& p);

/// Real air's two impulses for `model` (realAirParams'): the roll torque and the push on a wing.
struct RealAirImpulses {
  double torque = 0.0;           // N m: 0.5 x weight x half-span
  double torque_duration = 0.5;  // s
  double force = 0.0;            // N: 4 x the weight of the pushed wing's unit
  double force_duration = 0.2;   // s
};
RealAirImpulses realAirImpulses(const CreatureModel& model);

/// An evolution's episodes in real air (evolve --real-air, EpisodeParams::real_air):
/// realAirParams' steady 1 m/s wind from a drawn heading, light turbulence, IMU noise, gyro
/// bias and altimeter noise set in `e`; the impulses are sized per creature (realAirGusts).
void setRealAirEpisodes(EpisodeParams& e);
/// The gusts an episode of `e` (real_air) flies on `model`: `e` with realAirImpulses(model) as
/// its gust torque and push and their durations.
EpisodeParams realAirGusts(EpisodeParams e, const CreatureModel& model);

/// The state of `model` spawned level at the origin, at rest, in a world without air or
/// ground: its links as flapsim poses it before any step.
CreatureState spawnedLevel(const CreatureModel& model);
/// The creature's span: the extent along y of its shapes, posed as spawned level (m).
double creatureSpan(const CreatureModel& model);

/// One start's flight: the episode's result (flipped, lowest up-component, heights, time
/// upright, altitude rms after the settle time, lateral drift, mean bank, the motors' power)
/// and the start it flew from.
struct FlightCheckRun : EpisodeResult {
  EpisodeStart start;
  /// No flip, up-component never below 0.5, final height above the start.
  bool passed(double start_height) const {
    return !flipped && min_upright >= 0.5 && final_height > start_height;
  }
};

/// The episodes flightCheck() flies: its starts are their episodeStarts(). Throws InputError
/// for bad parameters.
EpisodeParams flightCheckEpisodes(const FlightCheckParams& params);

/// Flies `model` under `controller` (the same network on every unit) from `params.starts`
/// starts drawn from `params.seed`. Throws InputError for bad parameters.
std::vector<FlightCheckRun> flightCheck(const CreatureModelPtr& model,
                                        const ControllerSpec& controller,
                                        const FlightCheckParams& params);

/// A start's samples (its FlightCheckRun::trace) as CSV, one row per control update: the time
/// (s), the root's height (m) and up-component, the air's vertical speed at the root (m/s, > 0:
/// rising), then each wing's commanded downstroke and upstroke rates (rad/s), the columns named
/// by `wing_joints` (FlapUnitLayout order). Throws InputError if the run has no trace.
std::string flightTraceCsv(const FlightCheckRun& run, const std::vector<std::string>& wing_joints);

/// The flight_check tool's settings.
struct FlightCheckOptions {
  FlightCheckParams params;
  std::string weights;      // controller weights YAML (required)
  std::string urdf;         // a creature of flap units from a URDF file; empty: make_creature
  int pairs = 1;            // make_creature --pairs
  bool hover = false;       // --hover: the hover creature under HoverController instead, holding
                            // params.altitude (3 m if unset) in a wind of params.wind along +y
  std::string gains;        // --hover: its gains file (flapsim/hover_gains.h); empty: by hand
  std::string write_gains;  // --hover: write the gains flown to this file
  std::string trace_path;   // --trace: params.trace_start's samples as CSV (flightTraceCsv)
};

/// flight_check's flags (flapsim/cli_args.h), over `options`.
CliParser flightCheckCli(FlightCheckOptions& options);

/// flight_check's --gust-torque, --gust-force, --wind and --turbulence given with --real-air
/// (`seen`, the parse of `o`'s table) become real air's sizes in `o`
/// (FlightCheckParams::real_air_torque, _force, _wind, _turbulence).
void takeRealAirSizes(FlightCheckOptions& o, const std::vector<CliSeen>& seen);

/// Empty if every flag `seen` (flightCheckCli's parse) changes what the mode of `options` flies;
/// else a message naming the first that would be ignored: the network's flags (--weights,
/// --starts, --seed, the gusts, the noises, ...) with --hover, the hover's gains without it.
std::string flightCheckUnusedFlag(const FlightCheckOptions& options,
                                  const std::vector<CliSeen>& seen);

/// The same for the flags whose effect hangs on the controller flown: the altimeter's noise
/// without an altitude input, the ground-speed sensor's without ground-speed damping.
std::string flightCheckUnusedSensorFlag(const FlapControllerParams& controller,
                                        const std::vector<CliSeen>& seen);

/// The table flight_check prints: a line per start (start attitude and wind, flipped, lowest
/// up-component, final and lowest height, time upright, altitude error rms after 10 s, lateral
/// drift, mean bank, the motors' mean positive power in W and W/kg and net power, pass or FAIL)
/// and a summary; `failed` gets the number of starts that did not pass.
std::string flightCheckReport(const FlightCheckOptions& options,
                              const std::vector<FlightCheckRun>& runs, int wing_pairs, int& failed);

/// The motors' power over the starts (means) and the figure of merit: the ideal actuator-disk
/// power to hover the creature's weight on `disk_area` (m^2, in air of 1.204 kg/m^3) over the
/// mean positive power.
std::string flightPowerSummary(const std::vector<FlightCheckRun>& runs, double disk_area);

/// The hover controller of flight_check --hover: the gains file's (the hand-designed
/// defaults without one), holding `options.params.altitude` (3 m if unset).
HoverControllerParams hoverCheckController(const FlightCheckOptions& options);

/// The gains file of flight_check --hover --write-gains: hoverCheckController's gains, their
/// source in its header.
std::string hoverCheckGainsFile(const FlightCheckOptions& options);

/// flight_check --hover: flies `model` (the hover creature) under hoverCheckController from
/// `options.altitude` in a side wind of `options.wind`, started `params.max_roll` and
/// `params.max_pitch` tilted, for `params.duration` at `params.step_size`; returns the report
/// (height band, attitude, oscillation per stroke, power, figure of merit after 10 s) and sets
/// `ok` to whether it held the altitude within 0.3 m, upright (up >= 0.9), under 5 cm per
/// stroke, at most 100 W/kg.
std::string hoverCheckReport(const CreatureModelPtr& model, const FlightCheckOptions& options,
                             bool& ok);

/// One held-out start of flight_check --hover --real-air: the flight and what it flew from.
struct HoverCheckRun {
  HoverFlightResult flight;
  EpisodeStart start;
  /// The real-air bar: no flip, up-component above 0.5 and altitude rms under 0.3 m after the
  /// settling time, mean bank under 5 deg.
  bool passed() const;
};

/// flight_check --hover --real-air: flies `model` under hoverCheckController(options) from each
/// of the held-out starts of realAirParams(options.params) (tilted up to --roll and --pitch,
/// wind 1 m/s from a drawn heading, light turbulence, the roll torque and the push on a drawn
/// wing at drawn times, IMU noise, a drawn gyro bias, altimeter noise), holding the altitude
/// (3 m unless given) from it, on `options.params.threads` threads (results do not depend on it).
/// `adjust`, if given, may change each start's flight before it flies (a bench's hook:
/// bench/hover_oracle shortens it and overrides its strokes).
std::vector<HoverCheckRun> hoverRealAirCheck(
    const CreatureModelPtr& model, const FlightCheckOptions& options,
    const std::function<void(const EpisodeStart&, HoverFlightParams&)>& adjust = {});

/// Their table: a line per start and a summary; `failed` gets the starts that did not pass.
std::string hoverRealAirReport(const FlightCheckOptions& options,
                               const std::vector<HoverCheckRun>& runs, int& failed);

}  // namespace flapsim
