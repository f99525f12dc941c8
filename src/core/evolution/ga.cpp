#include "flapsim/ga.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace flapsim {

// ---- Rng -----------------------------------------------------------------------------------

double Rng::uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

std::uint64_t Rng::index(std::uint64_t n) {
  if (n == 0) throw std::invalid_argument("Rng::index needs n >= 1");
  // Largest multiple of n that fits: draws at or above it are rejected.
  const std::uint64_t limit =
      std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % n;
  std::uint64_t x;
  do {
    x = engine_();
  } while (x >= limit);
  return x % n;
}

double Rng::normal() {
  double u1;
  do {
    u1 = uniform();
  } while (u1 <= 0.0);
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

namespace {
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
}  // namespace

std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return splitmix64(splitmix64(splitmix64(a) ^ b) ^ c);
}

// ---- parallelMap ---------------------------------------------------------------------------

std::vector<double> parallelMap(int count, int threads, const std::function<double(int)>& f) {
  std::vector<double> out(std::max(count, 0));
  std::vector<std::exception_ptr> errors(out.size());
  std::atomic<int> next{0};
  auto worker = [&]() {
    for (int i = next++; i < count; i = next++) {
      try {
        out[i] = f(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const int n = std::max(1, std::min(threads, count));
  if (n == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int t = 0; t < n; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  for (auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return out;
}

// ---- GeneticAlgorithm ----------------------------------------------------------------------

std::string validateGaParams(const GaParams& p) {
  if (p.population < 2 || p.population > kMaxPopulation) {
    return "population must be in [2, " + std::to_string(kMaxPopulation) + "]";
  }
  if (p.generations < 0 || p.generations > kMaxGenerations) {
    return "generations must be in [0, " + std::to_string(kMaxGenerations) + "]";
  }
  if (p.elite_count < 0 || p.elite_count >= p.population) {
    return "elite_count must be in [0, population)";
  }
  auto prob = [](double x) { return std::isfinite(x) && x >= 0.0 && x <= 1.0; };
  if (!prob(p.crossover_rate)) return "crossover_rate must be in [0, 1]";
  if (!prob(p.mutation_rate)) return "mutation_rate must be in [0, 1]";
  if (!std::isfinite(p.mutation_sigma) || p.mutation_sigma < 0.0) {
    return "mutation_sigma must be >= 0";
  }
  if (!std::isfinite(p.blend_alpha) || p.blend_alpha < 0.0) return "blend_alpha must be >= 0";
  if (!std::isfinite(p.gene_min) || !std::isfinite(p.gene_max) || p.gene_max <= p.gene_min) {
    return "gene_min < gene_max required";
  }
  if (p.threads < 1) return "threads must be >= 1";
  for (size_t i = 0; i < p.initial_genes.size(); ++i) {
    const double g = p.initial_genes[i];
    if (!(g >= p.gene_min && g <= p.gene_max)) {
      std::ostringstream msg;
      msg << "initial gene " << i << " (" << g << ") is not in [" << p.gene_min << ", "
          << p.gene_max << "]";
      return msg.str();
    }
  }
  return "";
}

GeneticAlgorithm::GeneticAlgorithm(const GaParams& params, int gene_count,
                                   BatchFitnessFunction fitness)
    : params_(params), gene_count_(gene_count), fitness_(std::move(fitness)) {
  const std::string err = validateGaParams(params);
  if (!err.empty()) throw std::invalid_argument("GA: " + err);
  if (gene_count < 1) throw std::invalid_argument("GA: gene_count must be >= 1");
  if (!params.initial_genes.empty() &&
      params.initial_genes.size() != static_cast<size_t>(gene_count)) {
    throw std::invalid_argument("GA: " + std::to_string(params.initial_genes.size()) +
                                " initial genes for a genome of " + std::to_string(gene_count));
  }
  if (!fitness_) throw std::invalid_argument("GA: no fitness function");
}

namespace {
BatchFitnessFunction batchOf(FitnessFunction fitness, int threads) {
  if (!fitness) return {};
  return [threads, fitness](const std::vector<std::vector<double>>& genomes,
                            const std::vector<std::uint64_t>& seeds) {
    return parallelMap(static_cast<int>(genomes.size()), threads,
                       [&](int i) { return fitness(genomes[i], seeds[i]); });
  };
}
}  // namespace

GeneticAlgorithm::GeneticAlgorithm(const GaParams& params, int gene_count, FitnessFunction fitness)
    : GeneticAlgorithm(params, gene_count, batchOf(std::move(fitness), params.threads)) {}

void GeneticAlgorithm::evaluate(std::vector<Individual>& pop, const std::vector<int>& which) {
  const std::uint64_t gen = static_cast<std::uint64_t>(generation_);
  std::vector<std::vector<double>> genomes;
  std::vector<std::uint64_t> seeds;
  for (int i : which) {
    genomes.push_back(pop[i].genes);
    seeds.push_back(mixSeed(params_.seed, gen, static_cast<std::uint64_t>(i)));
  }
  const std::vector<double> f = fitness_(genomes, seeds);
  if (f.size() != which.size()) {
    throw std::runtime_error("GA: the batch fitness returned " + std::to_string(f.size()) +
                             " values for " + std::to_string(which.size()) + " genomes");
  }
  for (size_t k = 0; k < which.size(); ++k) {
    if (!std::isfinite(f[k])) {
      throw std::runtime_error("GA: fitness of individual " + std::to_string(which[k]) +
                               " in generation " + std::to_string(generation_) + " is " +
                               (std::isnan(f[k]) ? "NaN" : "infinite"));
    }
    pop[which[k]].fitness = f[k];
  }
}

void GeneticAlgorithm::sortAndRecord(int evaluations) {
  // Stable: equal fitness keeps the earlier index first (elites stay ahead).
  std::stable_sort(population_.begin(), population_.end(),
                   [](const Individual& a, const Individual& b) { return a.fitness > b.fitness; });
  GenerationStats s;
  s.generation = generation_;
  s.best = population_.front().fitness;
  s.worst = population_.back().fitness;
  double sum = 0.0;
  for (const auto& ind : population_) sum += ind.fitness;
  s.mean = sum / static_cast<double>(population_.size());
  s.evaluations = evaluations;
  s.best_genes = population_.front().genes;
  history_.push_back(std::move(s));
}

void GeneticAlgorithm::initialize() {
  generation_ = 0;
  history_.clear();
  Rng rng(mixSeed(params_.seed, 0, ~0ULL));
  population_.assign(params_.population, Individual());
  const std::vector<double>& seed = params_.initial_genes;
  const double sigma = params_.mutation_sigma * (params_.gene_max - params_.gene_min);
  for (size_t i = 0; i < population_.size(); ++i) {
    std::vector<double>& genes = population_[i].genes;
    genes.resize(gene_count_);
    for (int k = 0; k < gene_count_; ++k) {
      if (seed.empty()) {
        genes[k] = rng.uniform(params_.gene_min, params_.gene_max);
      } else {
        const double moved = i == 0 ? seed[k] : seed[k] + sigma * rng.normal();
        genes[k] = std::clamp(moved, params_.gene_min, params_.gene_max);
      }
    }
  }
  std::vector<int> all(population_.size());
  std::iota(all.begin(), all.end(), 0);
  evaluate(population_, all);
  sortAndRecord(static_cast<int>(all.size()));
}

void GeneticAlgorithm::step() {
  if (generation_ < 0) {
    initialize();
    return;
  }
  ++generation_;
  Rng rng(mixSeed(params_.seed, static_cast<std::uint64_t>(generation_), ~0ULL));
  const int n = params_.population;
  const double range = params_.gene_max - params_.gene_min;

  // Linear rank selection over the sorted population: weight n - rank.
  const double total = 0.5 * n * (n + 1);
  auto select = [&]() -> const Individual& {
    double r = rng.uniform() * total;
    for (int i = 0; i < n; ++i) {
      r -= n - i;
      if (r < 0.0) return population_[i];
    }
    return population_.back();
  };
  auto clamp = [&](double g) { return std::min(params_.gene_max, std::max(params_.gene_min, g)); };

  std::vector<Individual> next(population_.begin(), population_.begin() + params_.elite_count);
  std::vector<int> fresh;
  while (static_cast<int>(next.size()) < n) {
    Individual a = select();
    Individual b = select();
    bool changed[2] = {false, false};
    if (rng.bernoulli(params_.crossover_rate)) {
      changed[0] = changed[1] = true;
      for (int g = 0; g < gene_count_; ++g) {
        const double lo = std::min(a.genes[g], b.genes[g]);
        const double hi = std::max(a.genes[g], b.genes[g]);
        const double ext = params_.blend_alpha * (hi - lo);
        a.genes[g] = clamp(rng.uniform(lo - ext, hi + ext));
        b.genes[g] = clamp(rng.uniform(lo - ext, hi + ext));
      }
    }
    Individual* children[2] = {&a, &b};
    for (int c = 0; c < 2 && static_cast<int>(next.size()) < n; ++c) {
      for (double& g : children[c]->genes) {
        if (rng.bernoulli(params_.mutation_rate)) {
          g = clamp(g + params_.mutation_sigma * range * rng.normal());
          changed[c] = true;
        }
      }
      if (changed[c] || !params_.reuse_fitness_of_copies) {
        fresh.push_back(static_cast<int>(next.size()));
      }
      next.push_back(std::move(*children[c]));
    }
  }
  if (params_.reevaluate_every_generation) {
    fresh.resize(next.size());
    std::iota(fresh.begin(), fresh.end(), 0);
  }
  evaluate(next, fresh);
  population_ = std::move(next);
  sortAndRecord(static_cast<int>(fresh.size()));
}

namespace {

// Empty if `population` (best first) and `history` can be the state of a run of `p` with
// `genes` genes after `generation`, else what is wrong.
std::string checkState(const GaParams& p, int genes, int generation,
                       const std::vector<Individual>& population,
                       const std::vector<GenerationStats>& history) {
  if (generation < 0 || generation > p.generations) {
    return "generation " + std::to_string(generation) + " is not in [0, " +
           std::to_string(p.generations) + "]";
  }
  if (static_cast<int>(population.size()) != p.population) {
    return std::to_string(population.size()) + " individuals, the population is " +
           std::to_string(p.population);
  }
  for (size_t i = 0; i < population.size(); ++i) {
    const Individual& ind = population[i];
    if (static_cast<int>(ind.genes.size()) != genes) {
      return "an individual has " + std::to_string(ind.genes.size()) + " genes, expected " +
             std::to_string(genes);
    }
    if (!std::isfinite(ind.fitness)) return "individual " + std::to_string(i) + ": fitness";
    if (i > 0 && ind.fitness > population[i - 1].fitness) {
      return "the population is not sorted best first (individual " + std::to_string(i) + ")";
    }
    for (double g : ind.genes) {
      if (!(g >= p.gene_min && g <= p.gene_max)) {
        return "individual " + std::to_string(i) + " has a gene outside [gene_min, gene_max]";
      }
    }
  }
  if (static_cast<int>(history.size()) != generation + 1) {
    return "the history has " + std::to_string(history.size()) + " generations, expected " +
           std::to_string(generation + 1);
  }
  for (size_t g = 0; g < history.size(); ++g) {
    const GenerationStats& h = history[g];
    if (h.generation != static_cast<int>(g) || !std::isfinite(h.best) || !std::isfinite(h.mean) ||
        !std::isfinite(h.worst)) {
      return "history entry " + std::to_string(g) + " is not generation " + std::to_string(g) +
             " with finite values";
    }
  }
  if (history.back().best != population.front().fitness) {
    return "the history's last best is not the best individual's fitness";
  }
  return "";
}

}  // namespace

void GeneticAlgorithm::restore(int generation, std::vector<Individual> population,
                               std::vector<GenerationStats> history) {
  const std::string err = checkState(params_, gene_count_, generation, population, history);
  if (!err.empty()) throw std::invalid_argument("GA restore: " + err);
  generation_ = generation;
  population_ = std::move(population);
  history_ = std::move(history);
}

void GeneticAlgorithm::run(const std::function<void(const GenerationStats&)>& on_generation) {
  if (generation_ < 0) {
    initialize();
    if (on_generation) on_generation(history_.back());
  }
  while (generation_ < params_.generations) {
    step();
    if (on_generation) on_generation(history_.back());
  }
}

}  // namespace flapsim
