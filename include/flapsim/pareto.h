// Multi-objective selection: NSGA-II (Deb, Pratap, Agarwal, Meyarivan 2002), its fast
// non-dominated sort, crowding distance and crowded comparison, and a small real-coded driver
// with the GA's operators (ga.h: BLX-alpha crossover, Gaussian mutation, its Rng). Every
// objective is minimised. Deterministic: ties are broken by index. ROS-free; no clock.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace flapsim {

/// objectives[i][m]: objective m of individual i (minimised).
using ObjectiveTable = std::vector<std::vector<double>>;

/// Pareto rank of every individual: 0 = not dominated by any, 1 = dominated only by rank 0, ...
/// (the fast non-dominated sort). a dominates b if a is no worse in every objective and
/// strictly better in one; equal rows share a rank. Throws std::invalid_argument naming the
/// row and objective if the rows differ in length, are empty, or hold a NaN or infinity.
std::vector<int> paretoRanks(const ObjectiveTable& objectives);

/// Each individual's crowding distance within its front (the individuals of its rank): in each
/// objective the front's extremes get +infinity, the others the gap between their two
/// neighbours divided by the front's range (nothing if the range is zero), summed over the
/// objectives. Sorted with std::stable_sort (equal values: by index). Throws
/// std::invalid_argument for the objectives' errors above or ranks of another size or < 0.
std::vector<double> crowdingDistances(const ObjectiveTable& objectives,
                                      const std::vector<int>& ranks);

/// NSGA-II's crowded comparison made a total order: lower rank, then larger crowding, then
/// lower index. Throws std::invalid_argument if a or b is not an index of both vectors.
bool crowdedBetter(int a, int b, const std::vector<int>& ranks,
                   const std::vector<double>& crowding);

/// The `count` individuals NSGA-II keeps, best first in crowdedBetter order: whole fronts in
/// rank order, the last one that fits only in part cut by crowding distance. Throws
/// std::invalid_argument if count is not in [0, objectives.size()] or for bad objectives.
std::vector<int> nsga2Survivors(const ObjectiveTable& objectives, int count);

struct Nsga2Params {
  int population = 40;          // even, in [4, kMaxPopulation]
  int generations = 100;        // generations after the initial one, <= kMaxGenerations
  double crossover_rate = 0.9;  // probability that a pair of parents is crossed (BLX-alpha)
  double mutation_rate = 0.0;   // probability that a gene is mutated; <= 0: 1 / gene count
  double mutation_sigma = 0.1;  // std. dev. of a mutation, as a fraction of the gene's range
  double blend_alpha = 0.5;     // BLX-alpha crossover
  std::uint64_t seed = 1;
};

/// The last population, in the order nsga2Survivors kept it (best first; after 0 generations,
/// as drawn), its objectives and its Pareto ranks among themselves.
struct Nsga2Result {
  std::vector<std::vector<double>> genes;
  ObjectiveTable objectives;
  std::vector<int> ranks;
};

/// Objective values (minimised) of one genome; the same count for every genome, all finite.
using ObjectivesFunction = std::function<std::vector<double>(const std::vector<double>& genes)>;

/// Empty if valid, else a message naming the bad field (params or bounds).
std::string validateNsga2Params(const Nsga2Params& params, const std::vector<double>& gene_min,
                                const std::vector<double>& gene_max);

/// Objective rows of several genomes at once (the caller may parallelise as it likes): one row
/// per genome, in order, depending on the genome alone.
using BatchObjectivesFunction =
    std::function<ObjectiveTable(const std::vector<std::vector<double>>& genomes)>;

/// NSGA-II a generation at a time, for an evolution that evaluates in batches and keeps
/// checkpoints. Generation 0: uniform in [gene_min, gene_max], or, given initial genes,
/// individual 0 those genes and every other one them with each gene moved by a Gaussian of
/// mutation_sigma x the gene's range (clamped), as the GA seeds (ga.h); evaluated as drawn.
/// Then each generation, pairs of parents drawn by binary crowded tournament, crossed
/// (BLX-alpha, with probability crossover_rate) and mutated gene by gene (Gaussian), clamped to
/// the bounds; the children evaluated in one batch and nsga2Survivors of parents + children
/// kept, in crowded order. Generation g's draws all come from one Rng seeded by
/// mixSeed(seed, g): a run is bit-for-bit reproducible, also across a restore.
class Nsga2 {
 public:
  /// Throws std::invalid_argument for bad params or bounds, no function, or initial genes of
  /// another count than the bounds' or outside them (naming the gene).
  Nsga2(const Nsga2Params& params, std::vector<double> gene_min, std::vector<double> gene_max,
        BatchObjectivesFunction objectives, std::vector<double> initial_genes = {});
  /// Draws and evaluates generation 0. Throws std::runtime_error (naming the generation and
  /// individual) if the function returns another count of rows, a row of another length than
  /// the first, or a value that is not finite.
  void initialize();
  /// The next generation (generation 0 first if there is none yet); throws as initialize().
  void step();
  /// Continues from a saved generation: its individuals in the order they were kept, with
  /// their objectives. Throws std::invalid_argument if the count is not the population, a
  /// genome is not of the bounds' length or outside them, or the objectives are bad.
  void restore(int generation, std::vector<std::vector<double>> genes, ObjectiveTable objectives);
  int generation() const { return generation_; }  // -1 before initialize()
  const std::vector<std::vector<double>>& genes() const { return genes_; }
  const ObjectiveTable& objectives() const { return objectives_; }
  int evaluations() const { return evaluations_; }  // genomes evaluated for the last generation
  const Nsga2Params& params() const { return params_; }

 private:
  void evaluateNew(std::vector<std::vector<double>>& genes, ObjectiveTable& objectives);
  Nsga2Params params_;
  std::vector<double> lo_, hi_, initial_;
  BatchObjectivesFunction fn_;
  int generation_ = -1;
  int evaluations_ = 0;
  std::vector<std::vector<double>> genes_;
  ObjectiveTable objectives_;
};

/// NSGA-II (the class above, unseeded) run to params.generations, each genome evaluated
/// serially, in order. Throws std::invalid_argument for bad params or bounds,
/// std::runtime_error (naming the generation and individual) if the objectives' count changes
/// or a value is not finite.
Nsga2Result runNsga2(const Nsga2Params& params, const std::vector<double>& gene_min,
                     const std::vector<double>& gene_max, const ObjectivesFunction& objectives);

}  // namespace flapsim
