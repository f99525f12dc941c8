// Evolution of the flap-unit balance controller: the flight episode and its
// fitness (headless, in process, on a World), the GA run, and the files an
// evolution writes (weights YAML, CSVs, a gnuplot script). ROS-free; no clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/body_genome.h"
#include "flapsim/controller_file.h"
#include "flapsim/creature_model.h"
#include "flapsim/ga.h"
#include "flapsim/make_creature.h"
#include "flapsim/sensors.h"
#include "flapsim/step_accuracy.h"
#include "flapsim/world.h"

namespace flapsim {

class EpisodeEvaluator;
struct EvaluationSpec;

/// One flight. The creature starts at its root body at (0, 0, start_height),
/// rolled and pitched by the episode's start angles and turning at its start
/// rate;
/// every control period the controller reads the unit bodies' orientations
/// and sets the wing strokes, the world advances one control period, and the
/// root body's height z is sampled. Samples are taken at t = P, 2P, ..., T
/// (P = control period, T = duration).
///
/// Fitness ("accumulated height") = the mean of those samples, in metres,
/// averaged over the episodes of an evaluation. A creature that climbs
/// scores high; one that tumbles falls (open sky by default: no ground) and
/// scores below its start height.
///
/// Why no ground by default: a creature bouncing along the ground would score
/// by accident. Episodes run in parallel threads, each in a World of its own;
/// the results do not depend on the thread count, with or without ground.
struct EpisodeParams {
  EpisodeParams() { world.ground = false; }

  double duration = 30.0;     // s
  double start_height = 1.0;  // m, root body
  // Perturbation of the start attitude: |roll| uniform in [min_roll,
  // max_roll] with the sign alternating between episodes (+, -, +, ...),
  // pitch uniform in [-max_pitch, max_pitch]. A perfectly level start is
  // unrealistically easy: with no perturbation a symmetric creature under a
  // symmetric stroke never rolls.
  double min_roll = 0.035;  // rad (2 deg)
  double max_roll = 0.087;  // rad (5 deg)
  double max_pitch = 0.035;
  /// The first episode starts as a scenario does: level, at rest, in still air, holding its
  /// start height (the other episodes' draws unchanged).
  bool first_start_level = false;
  // Robust flight (all off in the paper's preset): each episode draws its own.
  double max_start_rate = 0.0;  // rad/s: start angular velocity, uniform per axis
  double max_gust = 0.0;        // m/s: a horizontal wind step of up to this speed
  /// m/s: a steady horizontal wind from t = 0, its speed uniform in [min_wind, max_wind],
  /// from a heading uniform in [0, 2 pi).
  double min_wind = 0.0;
  double max_wind = 0.0;
  /// The controller's sensors (flapsim/sensors.h): the root's IMU (seeded noise per
  /// episode), exact joint encoders, the altimeter's noise (m) and the ground-speed sensor's.
  ImuNoise imu_noise;
  /// rad/s: a constant bias of the gyro per episode, its size uniform in [0, gyro_bias], its
  /// direction uniform (drawn from a stream of its own).
  double gyro_bias = 0.0;
  double altitude_noise = 0.0;
  /// m/s: the ground-speed sensor's noise (FlapSensing::velocity, each of its axes), read
  /// only by a controller with ground-speed damping.
  double velocity_noise = 0.0;
  /// Gusts, each once per episode at a time uniform in [gust_window_start,
  /// gust_window_end] x duration (drawn apart): a roll torque of gust_torque N m about the
  /// root body's x axis (as it points then), its sign drawn, for gust_torque_duration s; and
  /// a vertical force of gust_force N (> 0: up) at the centre of mass of link gust_link
  /// for gust_force_duration s; gust_link empty: a wing drawn per episode (any unit's, left
  /// or right), pushed up or down (drawn). 0: no such gust.
  double gust_torque = 0.0;
  double gust_torque_duration = 0.5;
  double gust_force = 0.0;
  double gust_force_duration = 0.2;
  std::string gust_link;
  double gust_window_start = 0.1;
  double gust_window_end = 0.6;
  /// Real air's impulses sized to the creature each episode flies, as flight_check --real-air
  /// sizes them (realAirImpulses: a roll torque of 0.5 x weight x half-span for 0.5 s, a push
  /// of 4 x the pushed wing's unit's weight for 0.2 s, on a drawn wing) in place of gust_torque
  /// and gust_force; with the episode's gyro bias and altimeter noise. The hover and morph
  /// presets' episodes (evolve --real-air, which also sets real air's wind, turbulence and
  /// noise: realAirEpisodes), whose bodies differ from one individual to the next.
  bool real_air = false;
  /// With real_air: whether its roll torque and its push act (evolve --real-air --gust-torque 0,
  /// --gust-force 0 take them away; their sizes follow each body).
  bool real_air_torque = true;
  bool real_air_push = true;
  /// Altitude hold: each episode draws a setpoint uniform in [min_altitude, max_altitude]
  /// (m, the root link frame's height), the controller is asked to hold it
  /// (FlapSensing::setpoint), and a sample scores -|height - setpoint| - tilt_weight (1 -
  /// up-component) instead of the height. Off: the controller climbs, a sample scores its
  /// height (the paper's accumulated height).
  bool altitude_hold = false;
  double min_altitude = 5.0;
  double max_altitude = 5.0;
  double tilt_weight = 1.0;  // m per unit of (1 - up-component)
  /// With altitude hold: an episode whose lowest up-component after settle_time falls below
  /// upright_floor scores upright_floor_weight m less per unit below it (flight_check's bar:
  /// 0.5). The mean of the samples hardly sees a dip of a second; the bar fails on it.
  /// 0: off.
  double upright_floor = 0.0;
  double upright_floor_weight = 0.0;  // m per unit of up-component
  /// With altitude hold: an episode whose altitude rms after settle_time exceeds
  /// altitude_rms_ceiling (m) scores altitude_rms_weight m less per m over it (flight_check's
  /// bar: 0.3 m). The mean error weighs every sample alike; the bar fails on the episode's
  /// rms. 0: off.
  double altitude_rms_ceiling = 0.0;
  double altitude_rms_weight = 0.0;  // m per m of rms over the ceiling
  /// The altitude error's rms is taken over the samples after this (s).
  double settle_time = 10.0;
  std::vector<double> step_sizes;  // s: drawn per episode (empty: world.step_size)
  // The body's up axis below the horizon ends the episode: every sample left
  // scores the score at the flip less this (m). 0: flips are not detected
  // (the paper's accumulated height).
  double flip_penalty = 0.0;
  /// The root link frame below this height (m) ends the episode as a flip does, with the
  /// same penalty: the sky of an episode has no ground, but every scenario has one at 0, and
  /// a creature that sinks below it would have crashed there (a climb back from under it
  /// scored what no real flight can). Needs flip_penalty > 0; -inf: off (the paper's).
  double crash_height = -std::numeric_limits<double>::infinity();
  int episodes = 8;        // per fitness evaluation
  std::uint64_t seed = 1;  // draws the start attitudes
  WorldParams world;       // ground off (see above)
};

/// Limits of an episode (doc/reliability.md): they bound the work and memory that an
/// evolution, a farm call or a checkpoint can ask for.
constexpr int kMaxEpisodes = 1000;           // episodes per evaluation
constexpr double kMaxEpisodeDuration = 1e4;  // s
constexpr double kMaxEpisodeSteps = 1e7;     // world steps of one episode (duration / step)
constexpr int kMaxStepSizes = 16;            // step sizes to draw from
constexpr double kMaxStartRate = 1e3;        // rad/s, max_start_rate
constexpr double kMaxGust = 1e3;             // m/s, max_gust (the wind's limit)
constexpr double kMaxFlipPenalty = 1e6;      // m

/// Empty if valid, else a message naming the bad field.
std::string validateEpisodeParams(const EpisodeParams& params);

struct EpisodeStart {
  double roll = 0.0;               // rad about body x; > 0 = right wing low
  double pitch = 0.0;              // rad about body y; > 0 = nose down
  Vec3 rate = Vec3::Zero();        // rad/s, world frame
  Vec3 gust = Vec3::Zero();        // m/s, horizontal wind step from gust_time on
  double gust_time = 0.0;          // s
  Vec3 wind = Vec3::Zero();        // m/s, steady from t = 0
  double torque_time = 0.0;        // s: the roll torque gust starts
  double torque_sign = 1.0;        // +1: a torque along +x of the body (rolls it right wing down)
  double force_time = 0.0;         // s: the push on a wing starts
  double force_sign = 1.0;         // +1: as EpisodeParams::gust_force says
  std::string force_link;          // the link pushed
  std::optional<double> altitude;  // m: the setpoint (altitude hold)
  double step_size = 0.0;          // s; 0: the world's
  std::uint64_t noise_seed = 0;
  Vec3 gyro_bias = Vec3::Zero();  // rad/s, added to the gyro's reading
};

/// A start at `roll` and `pitch` (rad), everything else still.
EpisodeStart attitudeStart(double roll, double pitch);

/// The gusts of `start` due at control update `update` (of `control_period`; a gust is due at
/// the update whose period holds its time), applied to `creature` in `world`: its horizontal
/// wind step, the roll torque about the root's x axis as it points then and the vertical push
/// on its link's centre of mass, with `params`' sizes and durations (none if 0). runEpisode's,
/// and flyHover's with HoverFlightParams::gusts.
void applyEpisodeGusts(World& world, const std::string& creature, const CreatureModel& model,
                       const EpisodeParams& params, const EpisodeStart& start, std::int64_t update,
                       double control_period);

/// The turbulence an episode from `start` flies in: `base` (the episodes' air) with a
/// realisation of its own (its seed mixed with the start's noise seed) and, if it is on, its
/// intensities and scales at `height` (within the model's range).
TurbulenceParams episodeTurbulence(const TurbulenceParams& base, const EpisodeStart& start,
                                   double height);

/// The `episodes` start attitudes drawn from `params.seed` (deterministic). `model` names
/// the wings a push may be drawn on (needed only with gust_force and no gust_link).
std::vector<EpisodeStart> episodeStarts(const EpisodeParams& params,
                                        const CreatureModel* model = nullptr);

struct EpisodeSample {
  double time = 0.0;
  double height = 0.0;             // root body z
  double upright = 0.0;            // root body z axis . world z (1 = level)
  Pose root;                       // the root link's pose
  std::vector<double> downstroke;  // commanded rates, FlapUnitLayout wing order
  std::vector<double> upstroke;    // commanded rates, the same order
  Vec3 air = Vec3::Zero();         // the air's velocity at the root's COM (World::airVelocity)
};

struct EpisodeResult {
  double fitness = 0.0;  // mean sample score (after a flip: less the penalty)
  bool flipped = false;  // the root's up axis went below the horizon
  bool crashed = false;  // the root went below EpisodeParams::crash_height
  double min_height = 0.0;
  double final_height = 0.0;  // at t = T
  double max_height = 0.0;
  double min_upright = 1.0;          // over all samples
  double min_upright_settled = 1.0;  // over the samples after settle_time
  double final_upright = 1.0;
  double upright_fraction = 0.0;  // of the samples with the up axis within 60 deg of vertical
  /// m: rms of height - setpoint over the samples after settle_time (NaN without a setpoint
  /// or such samples).
  double altitude_rms = std::numeric_limits<double>::quiet_NaN();
  double lateral_drift = 0.0;  // m: the root's horizontal distance from its start at t = T
  /// rad: the mean over the samples of the root's bank, asin(world_up . body_left) (> 0:
  /// right wing low).
  double mean_bank = 0.0;
  /// The motors' mechanical power over the episode (World::power): the mean of the steps'
  /// positive work and the mean net work per second (W), and the creature's mass (kg).
  double positive_power = 0.0;
  double net_power = 0.0;
  double mass = 0.0;
  std::vector<EpisodeSample> trace;  // one per sample if asked for
};

/// Runs one episode of `model` (a chain of flap units, see FlapUnitLayout)
/// under `controller`, updated every `control_period` seconds (a positive
/// multiple of the world step, InputError otherwise).
EpisodeResult runEpisode(const CreatureModelPtr& model, const WingController& controller,
                         double control_period, const EpisodeParams& params,
                         const EpisodeStart& start, bool record_trace = false);

/// Fitness of network weights: mean of runEpisode() fitness over
/// episodeStarts(params). Deterministic.
double flapFitness(const CreatureModelPtr& model, const FlapControllerParams& controller,
                   const std::vector<double>& weights, const EpisodeParams& params);

/// Largest creature an evolution flies: units (wing pairs) of makeCreatureUrdf.
constexpr int kMaxEvolvePairs = 64;

/// What a co-evolution of body and controller (kMorph) needs beyond the hover preset's.
struct MorphParams {
  MassBudget budget;  // what the bodies' masses are made of
  /// m per 100 W/kg: the fitness's power term (the hover preset's 0.5; capped at 10 m).
  double power_weight = 0.5;
  /// Selection by NSGA-II (flapsim/pareto.h) over two objectives, the mean W/kg and the mean
  /// loss (flapsim/morph_front.h), instead of the GA's by the scalar fitness: each episode
  /// then answers both (taskValueCount).
  bool nsga2 = false;
};

/// What an evolution evolves: the flap-unit network (the paper's; evolve's robust and paper
/// presets), the hover controller's gains (evolve --preset hover, flapsim/hover_evolution.h),
/// or those gains and the hover creature's body together (evolve --preset morph,
/// flapsim/morph_evolution.h).
enum class EvolveKind { kFlap, kHover, kMorph };

/// Everything an evolution needs.
struct EvolveParams {
  EvolveKind kind = EvolveKind::kFlap;
  int pairs = 1;  // the creature: makeCreatureUrdf(pairs, "afc", unit)
  FlapUnitParams unit;
  GaParams ga;
  FlapControllerParams controller;
  EpisodeParams episode;  // episode.seed is set from ga.seed by evolveFlapController
  /// Fly the episodes at the creature's accurate step sizes (evolutionStepChoice) instead of
  /// episode.step_sizes, with the turn substep chosen with them unless turn_substep_given;
  /// parseEvolveArgs finds them once and hands the numbers on.
  bool auto_step_sizes = false;
  bool turn_substep_given = false;  // episode.world.turn_substep was set (evolve --turn-substep)
  MorphParams morph;  // kMorph: the bodies' mass budget and the fitness's power weight
  /// Sets of episode.episodes episodes drawn (evolve --episode-sets): generation g is evaluated
  /// on set g mod episode_sets, every individual anew (GaParams::reevaluate_every_generation),
  /// so that no fixed set of episodes is learnt by heart; at the end the last generation flies
  /// every set, and its best over all of them is the result's best. Set 0 is the episodes of a
  /// run with 1 (the draws run on), so 1 is the one fixed set of before.
  int episode_sets = 1;
};

/// The paper's settings (sec. IV.A): 10 individuals, elitism, rank selection,
/// crossover 0.1, mutation 0.05, 200 generations, fitness = accumulated height
/// over 8 episodes of 30 s from small rolled starts (2-5 deg), its network
/// (no phase lock), one step size, no flip detection.
EvolveParams paperPreset(int pairs = 1);

/// Robust flight (evolve's default): the paper's GA operators on 32 individuals for 100
/// generations; the extended network (mirror, gyro and altitude inputs, 4 hidden, phase_lock);
/// 12 episodes of 20 s, each drawing its start roll and pitch (up to +-30 deg), start angular
/// velocity (up to 1 rad/s per axis), a steady wind (0-2 m/s, any heading), a 0.05 N m roll
/// torque and a 1 N push on a wing at drawn times, IMU noise (0.1 rad, 0.1 rad/s), altimeter
/// noise (0.05 m), an altitude setpoint (2-8 m) and step size (1 or 0.5 ms; evolve's default
/// is auto_step_sizes: afc_1 and the chains 2 or 1 ms); a sample scores
/// -|height - setpoint| - (1 - up-component), a flip ends the episode at that score less 20 m.
EvolveParams robustPreset(int pairs = 1);

struct EvolveResult {
  std::vector<GenerationStats> history;
  std::vector<double> best_weights;
  double best_fitness = 0.0;
  /// The last generation's, best first (--selection nsga2: in NSGA-II's crowded order, the
  /// front first, each with its objectives).
  std::vector<Individual> population;
};

/// The state of an evolution after a generation: enough to continue it bit
/// for bit. The GA draws generation g from a generator seeded by (ga.seed, g),
/// so (seed, generation) is its whole random state.
struct EvolveCheckpoint {
  int generation = 0;
  std::uint64_t seed = 0;
  std::vector<Individual> population;  // best first (NSGA-II: crowded order, with objectives)
  std::vector<GenerationStats> history;
  std::vector<std::string> args;  // the evolve flags of the run (for --resume)
};

/// Limits of a checkpoint: genes of an individual (the weights of the widest network of
/// kMaxHidden neurons: 6 inputs, 2 outputs) and the file's size.
constexpr int kMaxGenes = 9 * kMaxHidden + 2;
constexpr std::size_t kMaxCheckpointBytes = 64u << 20;
constexpr int kMaxObjectives = 8;  // NSGA-II objectives of an individual in a checkpoint

/// Text form (every double as a C99 hex float, so it reads back bit for bit).
std::string checkpointToText(const EvolveCheckpoint& checkpoint);
/// Throws InputError naming the line at fault: a missing or unexpected word, a count or
/// generation out of its range (kMaxPopulation, kMaxGenes, kMaxSpecArgs, kMaxGenerations;
/// the history one entry per generation, numbered), a number that is not finite.
EvolveCheckpoint checkpointFromText(const std::string& text);
/// Reads a checkpoint file (a regular file of at most kMaxCheckpointBytes) and checks that
/// its `args` are only flags that define an evolution (checkSpecArgs: no output path, no
/// farm or resume setting). Throws InputError naming the file.
EvolveCheckpoint readCheckpointFile(const std::string& path);
/// Writes `path` through a temporary file renamed over it (a crash leaves the old one).
void writeCheckpointFile(const std::string& path, const EvolveCheckpoint& checkpoint);

struct EvolveHooks {
  std::function<void(const GenerationStats&)> on_generation;
  std::function<void(const EvolveCheckpoint&)> on_checkpoint;  // after each generation
  EpisodeEvaluator* evaluator = nullptr;     // null: in process on ga.threads threads
  const EvolveCheckpoint* resume = nullptr;  // continue from here (same params)
};

/// The genes of an individual of `params`' evolution: the flap-unit network's weights or the
/// hover controller's kHoverGeneCount gains.
int geneCount(const EvolveParams& params);

/// The task spec of an evolution: episode.seed = evolutionEpisodeSeed(ga.seed).
/// Throws std::invalid_argument for bad episode or controller parameters.
EvaluationSpec evaluationSpec(const EvolveParams& params);
/// The step sizes and the turn substep the episodes fly at: episode.step_sizes and
/// episode.world.turn_substep, or with auto_step_sizes the creature's cheapest accurate ones
/// (flapsim/step_accuracy.h: accurateStepChoice, at the middle of the controller's downstroke
/// rates; the turn substep given if turn_substep_given).
StepChoice evolutionStepChoice(const EvolveParams& params);

/// Runs the GA on the flap-unit network of a `pairs`-unit creature (params.kind kHover: on
/// the hover controller's gains, each episode runHoverEpisode, flapsim/hover_evolution.h); the
/// fitness is flapFitness with episode.seed = mixSeed(ga.seed, 0xE915) (the
/// same start attitudes for every individual of the run, so the fitness is a
/// function of the weights alone): one task per (individual, episode) through
/// the evaluator, each individual's fitness summed over its episodes in
/// episode order, so any evaluator gives the same bits. Calls `on_generation`
/// after each generation.
EvolveResult evolveFlapController(
    const EvolveParams& params,
    const std::function<void(const GenerationStats&)>& on_generation = {});
EvolveResult evolveFlapController(const EvolveParams& params, const EvolveHooks& hooks);

/// The episode start-attitude seed used by evolveFlapController for `ga_seed`.
std::uint64_t evolutionEpisodeSeed(std::uint64_t ga_seed);

// ---- Files (the weights YAML is in flapsim/controller_file.h) -------------------------------

/// CSV: generation,best,mean,worst.
std::string fitnessCsv(const std::vector<GenerationStats>& history);
/// CSV: time,height,upright,left_downstroke,right_downstroke (of unit `unit`).
std::string ratesCsv(const std::vector<EpisodeSample>& trace, int unit = 0);
/// gnuplot commands drawing fitness.png (paper Fig. 8) and rates.png (Fig. 7)
/// into `out_dir` from the two CSVs there (fitness.csv, rates.csv); without `rates`, only
/// fitness.png.
std::string gnuplotScript(const std::string& out_dir, double rates_window = 5.0, bool rates = true);

}  // namespace flapsim
