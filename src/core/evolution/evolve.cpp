#include "flapsim/evolve.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "flapsim/control_loop.h"
#include "flapsim/episode_evaluator.h"
#include "flapsim/make_creature.h"

namespace flapsim {

// ---- Episodes ------------------------------------------------------------------------------

namespace {

// "<name> must be in [lo, hi]" unless lo <= x <= hi (NaN is outside).
std::string range(const char* name, double x, double lo, double hi, const char* unit = "") {
  if (x >= lo && x <= hi) return "";
  std::ostringstream msg;
  msg << name << " must be in [" << lo << ", " << hi << "]" << unit;
  return msg.str();
}

}  // namespace

std::string validateEpisodeParams(const EpisodeParams& p) {
  const std::string w = validateWorldParams(p.world);
  if (!w.empty()) return "world: " + w;
  if (!(p.duration > 0.0 && p.duration <= kMaxEpisodeDuration)) {
    return "duration must be in (0, " + std::to_string(static_cast<int>(kMaxEpisodeDuration)) +
           "] s";
  }
  if (p.episodes < 1 || p.episodes > kMaxEpisodes) {
    return "episodes must be in [1, " + std::to_string(kMaxEpisodes) + "]";
  }
  if (!(p.min_roll >= 0.0 && p.max_roll >= p.min_roll && p.max_roll <= M_PI)) {
    return "need 0 <= min_roll <= max_roll <= pi";
  }
  for (const std::string& err :
       {range("start_height", p.start_height, -kMaxPosition, kMaxPosition, " m"),
        range("max_pitch", p.max_pitch, 0.0, M_PI, " rad"),
        range("max_start_rate", p.max_start_rate, 0.0, kMaxStartRate, " rad/s"),
        range("max_gust", p.max_gust, 0.0, kMaxGust, " m/s"),
        range("input_noise", p.input_noise, 0.0, kMaxInputNoise, " rad"),
        range("flip_penalty", p.flip_penalty, 0.0, kMaxFlipPenalty, " m")}) {
    if (!err.empty()) return err;
  }
  if (p.step_sizes.size() > static_cast<size_t>(kMaxStepSizes)) {
    return "step_sizes: more than " + std::to_string(kMaxStepSizes);
  }
  std::vector<double> steps = p.step_sizes;
  if (steps.empty()) steps.push_back(p.world.step_size);
  for (double dt : steps) {
    WorldParams step_only;
    step_only.step_size = dt;
    const std::string err = validateWorldParams(step_only);
    if (!err.empty()) return "step_sizes: " + err;
    if (p.duration / dt > kMaxEpisodeSteps) {
      std::ostringstream msg;
      msg << "duration / step size = " << p.duration / dt << " steps, over the limit of "
          << kMaxEpisodeSteps << " per episode";
      return msg.str();
    }
  }
  return "";
}

std::vector<EpisodeStart> episodeStarts(const EpisodeParams& p) {
  Rng rng(mixSeed(p.seed, 0x57A27ULL));
  std::vector<EpisodeStart> starts(std::max(p.episodes, 0));
  for (size_t k = 0; k < starts.size(); ++k) {
    const double roll = rng.uniform(p.min_roll, p.max_roll);
    starts[k].roll = k % 2 == 0 ? roll : -roll;
    starts[k].pitch = rng.uniform(-p.max_pitch, p.max_pitch);
  }
  // The robust draws come from streams of their own, so the paper's starts stay the same.
  Rng robust(mixSeed(p.seed, 0x20B057ULL));
  for (EpisodeStart& s : starts) {
    for (int a = 0; a < 3; ++a) s.rate[a] = robust.uniform(-p.max_start_rate, p.max_start_rate);
    const double heading = robust.uniform(0.0, 2.0 * M_PI);
    const double speed = robust.uniform(0.0, p.max_gust);
    s.gust = Vec3(speed * std::cos(heading), speed * std::sin(heading), 0.0);
    s.gust_time = robust.uniform(0.0, 0.5 * p.duration);
    if (!p.step_sizes.empty()) s.step_size = p.step_sizes[robust.index(p.step_sizes.size())];
    s.noise_seed = robust.next();
  }
  return starts;
}

namespace {

// The unit bodies' attitudes as the controller senses them: each tilted by a small random
// rotation (normal, `noise` rad per axis) when `noise` > 0.
void senseAttitudes(const CreatureState& state, const std::vector<int>& bodies, double noise,
                    Rng& rng, std::vector<Quat>& out) {
  for (size_t u = 0; u < bodies.size(); ++u) {
    out[u] = state.link_poses[bodies[u]].orientation;
    if (noise > 0.0) {
      const Vec3 tilt(noise * rng.normal(), noise * rng.normal(), 0.0);
      out[u] = Quat(Eigen::AngleAxisd(
                   tilt.norm(), tilt.norm() > 0.0 ? Vec3(tilt.normalized()) : Vec3::UnitX())) *
               out[u];
    }
  }
}

// One sample of the root's height z and up-component `up` into the result's extremes.
void addSample(EpisodeResult& r, double z, double up) {
  r.min_upright = std::min(r.min_upright, up);
  r.min_height = std::min(r.min_height, z);
  r.max_height = std::max(r.max_height, z);
  r.final_height = z;
  r.final_upright = up;
}

}  // namespace

EpisodeResult runEpisode(const CreatureModelPtr& model, const WingController& controller,
                         double control_period, const EpisodeParams& p, const EpisodeStart& start,
                         bool record_trace) {
  const std::string err = validateEpisodeParams(p);
  if (!err.empty()) throw InputError("episode: " + err);
  WorldParams world_params = p.world;
  if (start.step_size > 0.0) world_params.step_size = start.step_size;
  const ControlLoop loop(control_period, world_params.step_size);
  const FlapUnitLayout layout = flapUnitLayout(*model);
  std::vector<int> bodies;
  for (const auto& name : layout.body_links) bodies.push_back(model->findLink(name));

  World world(world_params);
  // As a launch file's pose {xyz: [0, 0, h], rpy: [roll, pitch, 0]} gives it.
  const Pose pose =
      poseFromXyzRpy(Vec3(0.0, 0.0, p.start_height), Vec3(start.roll, start.pitch, 0.0));
  const std::string name = "creature";
  Twist twist;
  twist.angular = start.rate;
  world.spawn(name, model, pose, twist);

  const std::int64_t samples = loop.periodsIn(p.duration);
  const double gust_sample = std::floor(start.gust_time / control_period);
  Rng noise(start.noise_seed);
  EpisodeResult result;
  result.max_height = -std::numeric_limits<double>::infinity();
  result.min_height = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  std::vector<Quat> orientations(bodies.size());
  for (std::int64_t s = 0; s < samples; ++s) {
    if (static_cast<double>(s) == gust_sample && start.gust.squaredNorm() > 0.0) {
      AirParams air = world.params().air;
      air.wind += start.gust;
      world.setAirParams(air);
    }
    senseAttitudes(world.state(name), bodies, p.input_noise, noise, orientations);
    const std::vector<StrokeCommand> commands = controller.commands(orientations);
    world.setWingCommands(name, layout.wing_joints, commands);
    world.step(loop.stepsPerPeriod());

    const Pose root = world.rootPose(name);
    const double z = root.position.z();
    const double up = (root.orientation * Vec3::UnitZ()).z();
    if (p.flip_penalty > 0.0 && up < 0.0) {
      // Upside down: the rest of the flight scores the height here less the penalty.
      result.flipped = true;
      sum += static_cast<double>(samples - s) * (z - p.flip_penalty);
      addSample(result, z, up);
      break;
    }
    result.flipped = result.flipped || up < 0.0;
    if (up >= 0.5) result.upright_fraction += 1.0;
    sum += z;
    addSample(result, z, up);
    if (record_trace) {
      EpisodeSample sample;
      sample.time = static_cast<double>(s + 1) * control_period;
      sample.height = z;
      sample.upright = up;
      for (const auto& c : commands) sample.downstroke.push_back(c.downstroke_rate);
      result.trace.push_back(std::move(sample));
    }
  }
  result.fitness = samples > 0 ? sum / static_cast<double>(samples) : 0.0;
  if (samples > 0) result.upright_fraction /= static_cast<double>(samples);
  const CreaturePower power = world.power(name);
  result.positive_power = power.meanPositivePower();
  result.net_power = power.time > 0.0 ? power.totalWork() / power.time : 0.0;
  result.mass = power.mass;
  return result;
}

double flapFitness(const CreatureModelPtr& model, const FlapControllerParams& controller,
                   const std::vector<double>& weights, const EpisodeParams& params) {
  const AnnWingController ann(FlapUnitController(controller, weights));
  const std::vector<EpisodeStart> starts = episodeStarts(params);
  double sum = 0.0;
  for (const auto& start : starts) {
    sum += runEpisode(model, ann, controller.control_period, params, start).fitness;
  }
  return sum / static_cast<double>(starts.size());
}

EvolveParams paperPreset(int pairs) {
  EvolveParams p;  // the defaults are the paper's
  p.pairs = pairs;
  return p;
}

EvolveParams robustPreset(int pairs) {
  EvolveParams p;
  p.pairs = pairs;
  p.ga.population = 16;
  p.ga.generations = 40;
  p.controller.phase_lock = true;
  EpisodeParams& e = p.episode;
  e.duration = 15.0;
  e.min_roll = 0.0;
  e.max_roll = 0.35;
  e.max_pitch = 0.35;
  e.max_start_rate = 1.0;
  e.max_gust = 1.0;
  e.input_noise = 0.02;
  e.step_sizes = {0.001, 0.0005};
  e.flip_penalty = 20.0;
  e.episodes = 8;
  return p;
}

std::uint64_t evolutionEpisodeSeed(std::uint64_t ga_seed) { return mixSeed(ga_seed, 0xE915ULL); }

EvaluationSpec evaluationSpec(const EvolveParams& params) {
  EvaluationSpec spec;
  spec.pairs = params.pairs;
  spec.unit = params.unit;
  spec.controller = params.controller;
  spec.episode = params.episode;
  spec.episode.seed = evolutionEpisodeSeed(params.ga.seed);
  std::string err = validateEpisodeParams(spec.episode);
  if (err.empty()) err = validateFlapControllerParams(spec.controller);
  if (!err.empty()) throw std::invalid_argument("evolve: " + err);
  return spec;
}

EvolveResult evolveFlapController(const EvolveParams& params,
                                  const std::function<void(const GenerationStats&)>& on_gen) {
  EvolveHooks hooks;
  hooks.on_generation = on_gen;
  return evolveFlapController(params, hooks);
}

EvolveResult evolveFlapController(const EvolveParams& params, const EvolveHooks& hooks) {
  const EvaluationSpec spec = evaluationSpec(params);
  std::unique_ptr<EpisodeEvaluator> own;
  EpisodeEvaluator* evaluator = hooks.evaluator;
  if (evaluator == nullptr) {
    own = std::make_unique<InProcessEvaluator>(spec, params.ga.threads);
    evaluator = own.get();
  }
  // One task per (individual, episode), so that the workers stay busy even
  // when few children are new; the sums run in a fixed order afterwards.
  const int n_starts = spec.episode.episodes;
  auto batch = [&](const std::vector<std::vector<double>>& genomes,
                   const std::vector<std::uint64_t>&) {
    std::vector<EpisodeTask> tasks;
    tasks.reserve(genomes.size() * n_starts);
    for (const auto& g : genomes) {
      for (int k = 0; k < n_starts; ++k) tasks.push_back(EpisodeTask{g, k});
    }
    const std::vector<double> f = evaluator->evaluate(tasks);
    if (f.size() != tasks.size()) {
      throw std::runtime_error("evolve: the evaluator returned " + std::to_string(f.size()) +
                               " values for " + std::to_string(tasks.size()) + " tasks");
    }
    std::vector<double> out(genomes.size(), 0.0);
    for (size_t i = 0; i < genomes.size(); ++i) {
      for (int k = 0; k < n_starts; ++k) out[i] += f[i * n_starts + k];
      out[i] /= n_starts;
    }
    return out;
  };
  GeneticAlgorithm ga(params.ga, FlapUnitController::weightCount(params.controller),
                      BatchFitnessFunction(batch));
  if (hooks.resume != nullptr) {
    if (hooks.resume->seed != params.ga.seed) {
      throw std::invalid_argument("evolve: the checkpoint is of seed " +
                                  std::to_string(hooks.resume->seed) + ", not " +
                                  std::to_string(params.ga.seed));
    }
    ga.restore(hooks.resume->generation, hooks.resume->population, hooks.resume->history);
  }
  ga.run([&](const GenerationStats& g) {
    if (hooks.on_checkpoint) {
      EvolveCheckpoint c;
      c.generation = ga.generation();
      c.seed = params.ga.seed;
      c.population = ga.population();
      c.history = ga.history();
      hooks.on_checkpoint(c);
    }
    if (hooks.on_generation) hooks.on_generation(g);
  });
  EvolveResult result;
  result.history = ga.history();
  result.best_weights = ga.best().genes;
  result.best_fitness = ga.best().fitness;
  return result;
}

// ---- Files ---------------------------------------------------------------------------------

std::string fitnessCsv(const std::vector<GenerationStats>& history) {
  std::ostringstream out;
  out << std::setprecision(10) << "generation,best,mean,worst\n";
  for (const auto& g : history) {
    out << g.generation << "," << g.best << "," << g.mean << "," << g.worst << "\n";
  }
  return out.str();
}

std::string ratesCsv(const std::vector<EpisodeSample>& trace, int unit) {
  std::ostringstream out;
  out << std::setprecision(10) << "time,height,upright,left_downstroke,right_downstroke\n";
  for (const auto& s : trace) {
    const size_t i = 2 * static_cast<size_t>(unit);
    if (s.downstroke.size() < i + 2) throw std::invalid_argument("ratesCsv: no such unit");
    out << s.time << "," << s.height << "," << s.upright << "," << s.downstroke[i] << ","
        << s.downstroke[i + 1] << "\n";
  }
  return out.str();
}

std::string gnuplotScript(const std::string& dir, double window) {
  std::ostringstream g;
  g << "set datafile separator ','\n"
    << "set terminal pngcairo size 800,500 font 'sans,11'\n"
    << "set grid\n"
    << "set key bottom right\n"
    << "set output '" << dir << "/fitness.png'\n"
    << "set title 'Fitness (mean height of the root body, m) per generation'\n"
    << "set xlabel 'generation'\nset ylabel 'fitness (m)'\n"
    << "plot '" << dir << "/fitness.csv' using 1:2 skip 1 with lines lw 2 title 'best', \\\n"
    << "     '' using 1:3 skip 1 with lines lw 1 title 'mean'\n"
    << "set output '" << dir << "/rates.png'\n"
    << "set key bottom right box opaque\n"
    << "set yrange [*:*] writeback\n"
    << "set title 'Downstroke rates of the best individual (unit 0)'\n"
    << "set xlabel 'time (s)'\nset ylabel 'downstroke rate (rad/s)'\n"
    << "set xrange [0:" << window << "]\n"
    << "plot '" << dir << "/rates.csv' using 1:5 skip 1 with lines lw 2 title 'right wing', \\\n"
    << "     '' using 1:4 skip 1 with lines lw 2 title 'left wing'\n"
    << "unset output\n";
  return g.str();
}

}  // namespace flapsim
