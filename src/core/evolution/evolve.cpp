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
#include "flapsim/hover_evolution.h"
#include "flapsim/make_creature.h"
#include "flapsim/morph_evolution.h"
#include "flapsim/step_accuracy.h"

namespace flapsim {

double flapFitness(const CreatureModelPtr& model, const FlapControllerParams& controller,
                   const std::vector<double>& weights, const EpisodeParams& params) {
  const AnnWingController ann(FlapUnitController(controller, weights));
  const std::vector<EpisodeStart> starts = episodeStarts(params, model.get());
  double sum = 0.0;
  for (const auto& start : starts) {
    sum += runEpisode(model, ann, controller.control_period, params, start).fitness;
  }
  return sum / static_cast<double>(starts.size());
}

EvolveParams paperPreset(int pairs) {
  EvolveParams p;  // the defaults are the paper's
  p.pairs = pairs;
  p.unit.body_com_drop = 0.0;  // the paper's unit (Fig. 5): no ballast
  return p;
}

EvolveParams robustPreset(int pairs) {
  EvolveParams p;
  p.pairs = pairs;
  p.ga.population = 32;
  p.ga.generations = 100;
  FlapControllerParams& c = p.controller;
  c.network = FlapNetwork::kMirror;
  c.rate_inputs = true;
  c.altitude_input = true;
  c.hidden = 4;
  c.phase_lock = true;
  EpisodeParams& e = p.episode;
  e.duration = 20.0;
  e.min_roll = 0.0;
  e.max_roll = 0.52;
  e.max_pitch = 0.52;
  e.max_start_rate = 1.0;
  e.max_wind = 2.0;
  e.imu_noise.orientation = 0.1;
  e.imu_noise.angular_velocity = 0.1;
  e.altitude_noise = 0.05;
  e.gust_torque = 0.05;
  e.gust_force = 1.0;
  e.altitude_hold = true;
  e.min_altitude = 2.0;
  e.max_altitude = 8.0;
  e.step_sizes = {0.001, 0.0005};  // evolve's default: auto_step_sizes
  e.flip_penalty = 20.0;
  e.crash_height = 0.0;
  e.episodes = 12;
  return p;
}

std::uint64_t evolutionEpisodeSeed(std::uint64_t ga_seed) { return mixSeed(ga_seed, 0xE915ULL); }

int geneCount(const EvolveParams& params) {
  return hoverKind(params.kind) ? hoverKindGeneCount(params.kind)
                                : FlapUnitController::weightCount(params.controller);
}

StepChoice evolutionStepChoice(const EvolveParams& params) {
  if (!params.auto_step_sizes || hoverKind(params.kind)) {
    return {params.episode.step_sizes, params.episode.world.turn_substep};
  }
  const FlapControllerParams& c = params.controller;
  const StrokeCommand stroke{0.5 * (c.min_downstroke_rate + c.max_downstroke_rate), c.upstroke_rate,
                             c.amplitude};
  const CreatureModelPtr model =
      parseCreatureModel(makeCreatureUrdf(params.pairs, "afc", params.unit), "make_creature");
  // In the episodes' air made steady: the check compares integrators, not gusts.
  WorldParams still = params.episode.world;
  still.air.turbulence = TurbulenceParams();
  still.air.gust = DiscreteGust();
  return accurateStepChoice(model, stroke, still,
                            params.turn_substep_given ? still.turn_substep : -1.0);
}

EvaluationSpec evaluationSpec(const EvolveParams& params) {
  EvaluationSpec spec;
  spec.kind = params.kind;
  spec.pairs = params.pairs;
  spec.unit = params.unit;
  spec.controller = params.controller;
  spec.episode = params.episode;
  spec.morph = params.morph;
  const StepChoice steps = evolutionStepChoice(params);
  spec.episode.step_sizes = steps.step_sizes;
  spec.episode.world.turn_substep = steps.turn_substep;
  spec.episode.seed = evolutionEpisodeSeed(params.ga.seed);
  if (params.episode_sets < 1) throw std::invalid_argument("--episode-sets must be >= 1");
  if (params.episode_sets > 1 && params.kind == EvolveKind::kMorph && params.morph.nsga2) {
    throw std::invalid_argument("--episode-sets " + std::to_string(params.episode_sets) +
                                " is for the elitist GA, not --selection nsga2");
  }
  if (params.episode.episodes > kMaxEpisodes / params.episode_sets) {
    throw std::invalid_argument("--episodes " + std::to_string(params.episode.episodes) +
                                " x --episode-sets " + std::to_string(params.episode_sets) +
                                " is over " + std::to_string(kMaxEpisodes) + " episodes");
  }
  spec.episode.episodes = params.episode.episodes * params.episode_sets;  // every set's
  const std::string err = validateEvaluationSpec(spec);
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
  if (params.kind == EvolveKind::kMorph && params.morph.nsga2) {
    return evolveMorphByNsga2(params, spec, *evaluator, hooks);
  }
  // One task per (individual, episode), so that the workers stay busy even
  // when few children are new; the sums run in a fixed order afterwards.
  const int episodes = params.episode.episodes;
  GaParams ga_params = params.ga;
  ga_params.reevaluate_every_generation = params.episode_sets > 1;
  // Each genome's mean fitness over `count` episodes from episode `first`.
  auto meanFitness = [&](const std::vector<std::vector<double>>& genomes, int count, int first) {
    std::vector<double> out;
    for (const auto& means : meanEpisodeValues(*evaluator, count, 1, genomes, first)) {
      out.push_back(means[0]);
    }
    return out;
  };
  const GeneticAlgorithm* running = nullptr;  // the generation evaluated picks the set
  auto batch = [&](const std::vector<std::vector<double>>& genomes,
                   const std::vector<std::uint64_t>&) {
    return meanFitness(genomes, episodes, (running->generation() % params.episode_sets) * episodes);
  };
  GeneticAlgorithm ga(ga_params, geneCount(params), BatchFitnessFunction(batch));
  running = &ga;
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
  result.population = ga.population();
  if (params.episode_sets > 1) {
    // The last generation ranked on one set; the best over every set is the one written.
    std::vector<std::vector<double>> genomes;
    for (const Individual& ind : result.population) genomes.push_back(ind.genes);
    const std::vector<double> means = meanFitness(genomes, spec.episode.episodes, 0);
    const auto best = std::max_element(means.begin(), means.end()) - means.begin();
    result.best_weights = genomes[best];
    result.best_fitness = means[best];
  }
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

std::string gnuplotScript(const std::string& dir, double window, bool rates) {
  std::ostringstream g;
  g << "set datafile separator ','\n"
    << "set terminal pngcairo size 800,500 font 'sans,11'\n"
    << "set grid\n"
    << "set key bottom right\n"
    << "set output '" << dir << "/fitness.png'\n"
    << "set title '"
    << (rates ? "Fitness (mean height of the root body, m)" : "Fitness (hover gains, m)")
    << " per generation'\n"
    << "set xlabel 'generation'\nset ylabel 'fitness (m)'\n"
    << "plot '" << dir << "/fitness.csv' using 1:2 skip 1 with lines lw 2 title 'best', \\\n"
    << "     '' using 1:3 skip 1 with lines lw 1 title 'mean'\n";
  if (!rates) {
    g << "unset output\n";
    return g.str();
  }
  g << "set output '" << dir << "/rates.png'\n"
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
