// evolve --preset morph --selection nsga2: the NSGA-II generations of a co-evolution, their
// episodes through an EpisodeEvaluator (in process or the farm), history and checkpoints.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "flapsim/episode_evaluator.h"
#include "flapsim/morph_evolution.h"
#include "flapsim/pareto.h"

namespace flapsim {

namespace {

Nsga2Params nsga2Params(const GaParams& ga) {
  Nsga2Params p;
  p.population = ga.population;
  p.generations = ga.generations;
  p.crossover_rate = ga.crossover_rate;
  p.mutation_rate = ga.mutation_rate;
  p.mutation_sigma = ga.mutation_sigma;
  p.blend_alpha = ga.blend_alpha;
  p.seed = ga.seed;
  return p;
}

// The population as individuals (NSGA-II's order) with their fitness at `power_weight`.
std::vector<Individual> individuals(const Nsga2& run, double power_weight) {
  std::vector<Individual> out(run.genes().size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].genes = run.genes()[i];
    out[i].objectives = run.objectives()[i];
    out[i].fitness = morphObjectivesFitness(out[i].objectives, power_weight);
  }
  return out;
}

// The fittest (the first of equals).
size_t fittest(const std::vector<Individual>& pop) {
  size_t best = 0;
  for (size_t i = 1; i < pop.size(); ++i) {
    if (pop[i].fitness > pop[best].fitness) best = i;
  }
  return best;
}

GenerationStats stats(int generation, int evaluations, const std::vector<Individual>& pop) {
  GenerationStats s;
  s.generation = generation;
  s.evaluations = evaluations;
  const size_t best = fittest(pop);
  s.best = s.worst = pop[best].fitness;
  double sum = 0.0;
  for (const Individual& ind : pop) {
    s.worst = std::min(s.worst, ind.fitness);
    sum += ind.fitness;
  }
  s.mean = sum / static_cast<double>(pop.size());
  s.best_genes = pop[best].genes;
  return s;
}

}  // namespace

EvolveResult evolveMorphByNsga2(const EvolveParams& params, const EvaluationSpec& spec,
                                EpisodeEvaluator& evaluator, const EvolveHooks& hooks) {
  if (spec.kind != EvolveKind::kMorph || taskValueCount(spec) != 2) {
    throw std::invalid_argument("evolve: NSGA-II selection is for --preset morph alone");
  }
  const GaParams& ga = params.ga;
  const int episodes = spec.episode.episodes;
  Nsga2 run(
      nsga2Params(ga), std::vector<double>(kMorphGeneCount, ga.gene_min),
      std::vector<double>(kMorphGeneCount, ga.gene_max),
      [&](const std::vector<std::vector<double>>& genomes) {
        return meanEpisodeValues(evaluator, episodes, 2, genomes);  // W/kg, loss
      },
      ga.initial_genes);
  const double weight = spec.morph.power_weight;
  std::vector<GenerationStats> history;
  if (hooks.resume != nullptr) {
    const EvolveCheckpoint& c = *hooks.resume;
    if (c.seed != ga.seed) {
      throw std::invalid_argument("evolve: the checkpoint is of seed " + std::to_string(c.seed) +
                                  ", not " + std::to_string(ga.seed));
    }
    std::vector<std::vector<double>> genes;
    ObjectiveTable objectives;
    for (const Individual& ind : c.population) {
      if (ind.objectives.size() != 2) {
        throw std::invalid_argument(
            "evolve: the checkpoint's individuals have no NSGA-II objectives (an evolution "
            "without --selection nsga2)");
      }
      genes.push_back(ind.genes);
      objectives.push_back(ind.objectives);
    }
    run.restore(c.generation, std::move(genes), std::move(objectives));
    history = c.history;
  }
  auto record = [&] {
    const std::vector<Individual> pop = individuals(run, weight);
    history.push_back(stats(run.generation(), run.evaluations(), pop));
    if (hooks.on_checkpoint) {
      EvolveCheckpoint c;
      c.generation = run.generation();
      c.seed = ga.seed;
      c.population = pop;
      c.history = history;
      hooks.on_checkpoint(c);
    }
    if (hooks.on_generation) hooks.on_generation(history.back());
  };
  if (run.generation() < 0) {
    run.initialize();
    record();
  }
  while (run.generation() < ga.generations) {
    run.step();
    record();
  }
  EvolveResult result;
  result.history = history;
  result.population = individuals(run, weight);
  const Individual& best = result.population[fittest(result.population)];
  result.best_weights = best.genes;
  result.best_fitness = best.fitness;
  return result;
}

}  // namespace flapsim
