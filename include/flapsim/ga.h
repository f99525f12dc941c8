// A real-coded genetic algorithm (the paper's RCGA, sec. IV.A) with a seeded,
// library-independent random generator and thread-count-independent parallel
// fitness evaluation. ROS-free; no clock.
#pragma once

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace flapsim {

/// std::mt19937_64 with its own distributions (the standard library's
/// distributions differ between implementations; these do not).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  std::uint64_t next() { return engine_(); }
  /// Uniform in [0, 1): the top 53 bits of one draw.
  double uniform();
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n >= 1 (rejection sampling, no modulo bias).
  std::uint64_t index(std::uint64_t n);
  /// Standard normal (Box-Muller, one value per two uniforms).
  double normal();
  bool bernoulli(double p) { return uniform() < p; }

 private:
  std::mt19937_64 engine_;
};

/// A well-mixed 64-bit seed for stream (a, b, c) of a run (splitmix64 chain).
std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b = 0, std::uint64_t c = 0);

/// Parameters; defaults are the paper's (population 10, elitism, rank
/// selection, crossover 0.1, mutation 0.05, 200 generations).
struct GaParams {
  int population = 10;
  int generations = 200;        // generations after the initial one
  int elite_count = 1;          // best individuals copied unchanged (elitism)
  double crossover_rate = 0.1;  // probability that a pair of parents is crossed
  double mutation_rate = 0.05;  // probability that a gene is mutated
  double mutation_sigma = 0.1;  // std. dev. of a mutation, as a fraction of the gene range
  double blend_alpha = 0.5;     // BLX-alpha crossover
  double gene_min = -10.0;      // initial range and bounds of every gene
  double gene_max = 10.0;
  std::uint64_t seed = 1;
  int threads = 1;  // fitness evaluations in parallel; results do not depend on it
  // A child that is an unchanged copy of a parent (no crossover, no
  // mutation) inherits the parent's fitness instead of being re-evaluated.
  // Right only for a fitness that depends on the genes alone.
  bool reuse_fitness_of_copies = true;
  // Every individual, the elites and copies too, is evaluated anew in each generation: for a
  // fitness that changes from one generation to the next (evolve --episode-sets), so that a
  // generation's individuals are ranked on the same episodes. Overrides the above.
  bool reevaluate_every_generation = false;
  /// Seeds generation 0 (empty: all random in [gene_min, gene_max]): individual 0 is these
  /// genes, each other one these genes with every gene moved by a Gaussian of
  /// mutation_sigma x the gene range (clamped). Each gene within [gene_min, gene_max].
  std::vector<double> initial_genes;
};

/// Limits of a GA run (doc/reliability.md).
constexpr int kMaxPopulation = 1000;
constexpr int kMaxGenerations = 100000;

/// Empty if valid, else a message naming the bad field.
std::string validateGaParams(const GaParams& params);

struct Individual {
  std::vector<double> genes;
  double fitness = 0.0;
  std::vector<double> objectives;  // NSGA-II's (evolve --selection nsga2), else empty
};

struct GenerationStats {
  int generation = 0;  // 0 = the random initial population
  double best = 0.0;
  double mean = 0.0;
  double worst = 0.0;
  int evaluations = 0;  // fitness evaluations run for this generation
  std::vector<double> best_genes;
};

/// Fitness to maximise. Called concurrently from several threads: it must
/// be thread-safe and depend only on its arguments. `eval_seed` =
/// mixSeed(seed, generation, index) for stochastic fitness functions.
using FitnessFunction =
    std::function<double(const std::vector<double>& genes, std::uint64_t eval_seed)>;

/// Fitness of several genomes at once (the caller may parallelise as it
/// likes, e.g. over episodes); must return one value per genome, in order,
/// and depend only on its arguments.
using BatchFitnessFunction = std::function<std::vector<double>(
    const std::vector<std::vector<double>>& genomes, const std::vector<std::uint64_t>& eval_seeds)>;

/// Generation g + 1 from generation g: the `elite_count` best are kept with
/// their fitness (not re-evaluated, unless reevaluate_every_generation); the others are children of
/// two parents drawn by linear rank selection (weight population - rank), crossed with BLX-alpha
/// with probability crossover_rate, then mutated gene by gene (Gaussian, clamped to [gene_min,
/// gene_max]). Each generation's random stream is seeded by mixSeed(seed, generation); fitness
/// evaluations run in parallel and write to their own slot, so results are bit-identical for any
/// thread count.
class GeneticAlgorithm {
 public:
  /// Throws std::invalid_argument for bad params or gene_count < 1.
  GeneticAlgorithm(const GaParams& params, int gene_count, FitnessFunction fitness);
  /// The same with a batch fitness (params.threads is then not used by the GA).
  GeneticAlgorithm(const GaParams& params, int gene_count, BatchFitnessFunction fitness);

  /// Creates and evaluates generation 0; called by step() if needed.
  void initialize();
  /// Advances one generation (initializes first if needed).
  void step();
  /// Runs until `generations` generations after the initial one, calling
  /// `on_generation` after each one (including generation 0).
  void run(const std::function<void(const GenerationStats&)>& on_generation = {});

  /// Continues from a saved state: the population (best first) and history
  /// after `generation`. Throws std::invalid_argument if they do not fit the
  /// params (population size, gene count, history length).
  void restore(int generation, std::vector<Individual> population,
               std::vector<GenerationStats> history);

  /// The last generation made; during a fitness call, the generation being evaluated.
  int generation() const { return generation_; }
  /// Current population, best first.
  const std::vector<Individual>& population() const { return population_; }
  const Individual& best() const { return population_.front(); }
  const std::vector<GenerationStats>& history() const { return history_; }
  const GaParams& params() const { return params_; }

 private:
  void evaluate(std::vector<Individual>& individuals, const std::vector<int>& which);
  void sortAndRecord(int evaluations);

  GaParams params_;
  int gene_count_;
  BatchFitnessFunction fitness_;
  int generation_ = -1;
  std::vector<Individual> population_;
  std::vector<GenerationStats> history_;
};

/// Runs fitness(i) for i in [0, count) on `threads` threads (1 = inline) and
/// returns the results in index order. Rethrows the first exception (by index).
std::vector<double> parallelMap(int count, int threads, const std::function<double(int)>& fitness);

}  // namespace flapsim
