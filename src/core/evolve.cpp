#include "flapsim/evolve.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "flapsim/make_creature.h"

namespace flapsim {

// ---- Episodes ------------------------------------------------------------------------------

std::string validateEpisodeParams(const EpisodeParams& p) {
  if (!std::isfinite(p.duration) || p.duration <= 0.0) return "duration must be > 0";
  if (!std::isfinite(p.start_height)) return "start_height must be finite";
  if (!std::isfinite(p.min_roll) || !std::isfinite(p.max_roll) || p.min_roll < 0.0 ||
      p.max_roll < p.min_roll) {
    return "need 0 <= min_roll <= max_roll";
  }
  if (!std::isfinite(p.max_pitch) || p.max_pitch < 0.0) return "max_pitch must be >= 0";
  if (p.episodes < 1) return "episodes must be >= 1";
  const std::string w = validateWorldParams(p.world);
  return w.empty() ? "" : "world: " + w;
}

std::vector<EpisodeStart> episodeStarts(const EpisodeParams& p) {
  Rng rng(mixSeed(p.seed, 0x57A27ULL));
  std::vector<EpisodeStart> starts(std::max(p.episodes, 0));
  for (size_t k = 0; k < starts.size(); ++k) {
    const double roll = rng.uniform(p.min_roll, p.max_roll);
    starts[k].roll = k % 2 == 0 ? roll : -roll;
    starts[k].pitch = rng.uniform(-p.max_pitch, p.max_pitch);
  }
  return starts;
}

EpisodeResult runEpisode(const CreatureModelPtr& model, const WingController& controller,
                         double control_period, const EpisodeParams& p, const EpisodeStart& start,
                         bool record_trace) {
  const std::string err = validateEpisodeParams(p);
  if (!err.empty()) throw InputError("episode: " + err);
  const double step = p.world.step_size;
  const double steps_real = control_period / step;
  const int steps = static_cast<int>(std::lround(steps_real));
  if (!(control_period > 0.0) || steps < 1 || std::abs(steps_real - steps) > 1e-9 * steps_real) {
    throw InputError("control period " + std::to_string(control_period) +
                     " s is not a positive multiple of the step " + std::to_string(step) + " s");
  }
  const FlapUnitLayout layout = flapUnitLayout(*model);
  std::vector<int> bodies;
  for (const auto& name : layout.body_links) bodies.push_back(model->findLink(name));

  World world(p.world);
  // As a launch file's pose {xyz: [0, 0, h], rpy: [roll, pitch, 0]} gives it.
  const Pose pose =
      poseFromXyzRpy(Vec3(0.0, 0.0, p.start_height), Vec3(start.roll, start.pitch, 0.0));
  const std::string name = "creature";
  world.spawn(name, model, pose);

  const int samples = static_cast<int>(std::lround(p.duration / control_period));
  EpisodeResult result;
  result.max_height = -std::numeric_limits<double>::infinity();
  double sum = 0.0;
  std::vector<Quat> orientations(bodies.size());
  for (int s = 0; s < samples; ++s) {
    CreatureState state = world.state(name);
    for (size_t u = 0; u < bodies.size(); ++u) {
      orientations[u] = state.link_poses[bodies[u]].orientation;
    }
    const std::vector<StrokeCommand> commands = controller.commands(orientations);
    world.setWingCommands(name, layout.wing_joints, commands);
    world.step(steps);

    const Pose root = world.rootPose(name);
    const double z = root.position.z();
    const double up = (root.orientation * Vec3::UnitZ()).z();
    sum += z;
    result.max_height = std::max(result.max_height, z);
    result.min_upright = std::min(result.min_upright, up);
    result.final_height = z;
    result.final_upright = up;
    if (record_trace) {
      EpisodeSample sample;
      sample.time = (s + 1) * control_period;
      sample.height = z;
      sample.upright = up;
      for (const auto& c : commands) sample.downstroke.push_back(c.downstroke_rate);
      result.trace.push_back(std::move(sample));
    }
  }
  result.fitness = samples > 0 ? sum / samples : 0.0;
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

std::uint64_t evolutionEpisodeSeed(std::uint64_t ga_seed) { return mixSeed(ga_seed, 0xE915ULL); }

EvolveResult evolveFlapController(const EvolveParams& params,
                                  const std::function<void(const GenerationStats&)>& on_gen) {
  const CreatureModelPtr model =
      parseCreatureModel(makeCreatureUrdf(params.pairs, "afc"), "make_creature");
  EpisodeParams episode = params.episode;
  episode.seed = evolutionEpisodeSeed(params.ga.seed);
  std::string err = validateEpisodeParams(episode);
  if (err.empty()) err = validateFlapControllerParams(params.controller);
  if (!err.empty()) throw std::invalid_argument("evolve: " + err);

  // One task per (individual, episode), so that the threads stay busy even
  // when few children are new; the sums run in a fixed order afterwards.
  const FlapControllerParams controller = params.controller;
  const std::vector<EpisodeStart> starts = episodeStarts(episode);
  const int n_starts = static_cast<int>(starts.size());
  const int threads = params.ga.threads;
  auto batch = [&](const std::vector<std::vector<double>>& genomes,
                   const std::vector<std::uint64_t>&) {
    std::vector<AnnWingController> anns;
    for (const auto& g : genomes) anns.emplace_back(FlapUnitController(controller, g));
    const std::vector<double> f =
        parallelMap(static_cast<int>(genomes.size()) * n_starts, threads, [&](int task) {
          return runEpisode(model, anns[task / n_starts], controller.control_period, episode,
                            starts[task % n_starts])
              .fitness;
        });
    std::vector<double> out(genomes.size(), 0.0);
    for (size_t i = 0; i < genomes.size(); ++i) {
      for (int k = 0; k < n_starts; ++k) out[i] += f[i * n_starts + k];
      out[i] /= n_starts;
    }
    return out;
  };
  GeneticAlgorithm ga(params.ga, FlapUnitController::weightCount(controller),
                      BatchFitnessFunction(batch));
  ga.run(on_gen);
  EvolveResult result;
  result.history = ga.history();
  result.best_weights = ga.best().genes;
  result.best_fitness = ga.best().fitness;
  return result;
}

// ---- Files ---------------------------------------------------------------------------------

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
    << "set key top right\n"
    << "set title 'Downstroke rates of the best individual (unit 0)'\n"
    << "set xlabel 'time (s)'\nset ylabel 'downstroke rate (rad/s)'\n"
    << "set xrange [0:" << window << "]\n"
    << "plot '" << dir << "/rates.csv' using 1:5 skip 1 with lines lw 2 title 'right wing', \\\n"
    << "     '' using 1:4 skip 1 with lines lw 2 title 'left wing'\n"
    << "unset output\n";
  return g.str();
}

}  // namespace flapsim
