#include "flapsim/pareto.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "flapsim/ga.h"

namespace flapsim {

namespace {

// Throws std::invalid_argument naming the first row that is ragged, empty or not finite.
void checkObjectives(const ObjectiveTable& f, const char* who) {
  for (size_t i = 0; i < f.size(); ++i) {
    std::ostringstream msg;
    msg << who << ": objective row " << i;
    if (f[i].empty()) throw std::invalid_argument(msg.str() + " is empty");
    if (f[i].size() != f[0].size()) {
      msg << " has " << f[i].size() << " objectives, row 0 has " << f[0].size();
      throw std::invalid_argument(msg.str());
    }
    for (size_t m = 0; m < f[i].size(); ++m) {
      if (!std::isfinite(f[i][m])) {
        msg << ", objective " << m << " is " << f[i][m] << " (not finite)";
        throw std::invalid_argument(msg.str());
      }
    }
  }
}

bool dominates(const std::vector<double>& a, const std::vector<double>& b) {
  bool strictly = false;
  for (size_t m = 0; m < a.size(); ++m) {
    if (a[m] > b[m]) return false;
    if (a[m] < b[m]) strictly = true;
  }
  return strictly;
}

}  // namespace

std::vector<int> paretoRanks(const ObjectiveTable& objectives) {
  checkObjectives(objectives, "paretoRanks");
  const int n = static_cast<int>(objectives.size());
  std::vector<std::vector<int>> dominated(n);  // dominated[p]: whom p dominates
  std::vector<int> dominators(n, 0);           // how many dominate p
  std::vector<int> rank(n, -1);
  std::vector<int> front;
  for (int p = 0; p < n; ++p) {
    for (int q = p + 1; q < n; ++q) {
      if (dominates(objectives[p], objectives[q])) {
        dominated[p].push_back(q);
        ++dominators[q];
      } else if (dominates(objectives[q], objectives[p])) {
        dominated[q].push_back(p);
        ++dominators[p];
      }
    }
  }
  for (int p = 0; p < n; ++p) {
    if (dominators[p] == 0) front.push_back(p);
  }
  for (int r = 0; !front.empty(); ++r) {
    std::vector<int> next;
    for (int p : front) {
      rank[p] = r;
      for (int q : dominated[p]) {
        if (--dominators[q] == 0) next.push_back(q);
      }
    }
    std::sort(next.begin(), next.end());
    front = std::move(next);
  }
  return rank;
}

std::vector<double> crowdingDistances(const ObjectiveTable& objectives,
                                      const std::vector<int>& ranks) {
  checkObjectives(objectives, "crowdingDistances");
  if (ranks.size() != objectives.size()) {
    throw std::invalid_argument("crowdingDistances: " + std::to_string(ranks.size()) +
                                " ranks for " + std::to_string(objectives.size()) + " rows");
  }
  std::vector<std::vector<int>> fronts;
  for (size_t i = 0; i < ranks.size(); ++i) {
    if (ranks[i] < 0 || static_cast<size_t>(ranks[i]) >= ranks.size()) {
      throw std::invalid_argument("crowdingDistances: rank " + std::to_string(ranks[i]) +
                                  " of row " + std::to_string(i) + " is not in [0, rows)");
    }
    if (fronts.size() <= static_cast<size_t>(ranks[i])) fronts.resize(ranks[i] + 1);
    fronts[ranks[i]].push_back(static_cast<int>(i));  // in index order
  }
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> crowding(objectives.size(), 0.0);
  const size_t objective_count = objectives.empty() ? 0 : objectives[0].size();
  for (std::vector<int>& front : fronts) {
    if (front.empty()) continue;
    for (size_t m = 0; m < objective_count; ++m) {
      // Halved values: a gap between finite doubles cannot overflow to infinity.
      auto f = [&](int i) { return 0.5 * objectives[i][m]; };
      std::vector<int> order = front;
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return f(a) < f(b); });
      crowding[order.front()] = crowding[order.back()] = inf;
      const double range = f(order.back()) - f(order.front());
      if (range <= 0.0) continue;
      for (size_t k = 1; k + 1 < order.size(); ++k) {
        crowding[order[k]] += (f(order[k + 1]) - f(order[k - 1])) / range;
      }
    }
  }
  return crowding;
}

bool crowdedBetter(int a, int b, const std::vector<int>& ranks,
                   const std::vector<double>& crowding) {
  const int n = static_cast<int>(std::min(ranks.size(), crowding.size()));
  if (a < 0 || a >= n || b < 0 || b >= n) {
    throw std::invalid_argument("crowdedBetter: index " + std::to_string(a < 0 || a >= n ? a : b) +
                                " is not in [0, " + std::to_string(n) + ")");
  }
  if (ranks[a] != ranks[b]) return ranks[a] < ranks[b];
  if (crowding[a] != crowding[b]) return crowding[a] > crowding[b];
  return a < b;
}

std::vector<int> nsga2Survivors(const ObjectiveTable& objectives, int count) {
  if (count < 0 || static_cast<size_t>(count) > objectives.size()) {
    throw std::invalid_argument("nsga2Survivors: count " + std::to_string(count) +
                                " is not in [0, " + std::to_string(objectives.size()) + "]");
  }
  const std::vector<int> ranks = paretoRanks(objectives);
  const std::vector<double> crowding = crowdingDistances(objectives, ranks);
  std::vector<int> order(objectives.size());
  std::iota(order.begin(), order.end(), 0);
  // A total order: the first `count` are whole fronts, then the last front's most isolated.
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return crowdedBetter(a, b, ranks, crowding); });
  order.resize(count);
  return order;
}

// ---- The driver ----------------------------------------------------------------------------

std::string validateNsga2Params(const Nsga2Params& p, const std::vector<double>& gene_min,
                                const std::vector<double>& gene_max) {
  if (p.population < 4 || p.population > kMaxPopulation || p.population % 2 != 0) {
    return "population must be even and in [4, " + std::to_string(kMaxPopulation) + "]";
  }
  if (p.generations < 0 || p.generations > kMaxGenerations) {
    return "generations must be in [0, " + std::to_string(kMaxGenerations) + "]";
  }
  if (!(p.crossover_rate >= 0.0 && p.crossover_rate <= 1.0)) {
    return "crossover_rate must be in [0, 1]";
  }
  if (!(p.mutation_rate <= 1.0)) return "mutation_rate must be <= 1 (<= 0: 1 / gene count)";
  if (!std::isfinite(p.mutation_sigma) || p.mutation_sigma < 0.0) {
    return "mutation_sigma must be >= 0";
  }
  if (!std::isfinite(p.blend_alpha) || p.blend_alpha < 0.0) return "blend_alpha must be >= 0";
  if (gene_min.empty()) return "gene_min must name at least one gene";
  if (gene_min.size() != gene_max.size()) {
    return "gene_min has " + std::to_string(gene_min.size()) + " genes, gene_max " +
           std::to_string(gene_max.size());
  }
  for (size_t k = 0; k < gene_min.size(); ++k) {
    if (!std::isfinite(gene_min[k]) || !std::isfinite(gene_max[k]) || gene_min[k] >= gene_max[k]) {
      std::ostringstream msg;
      msg << "gene " << k << ": gene_min (" << gene_min[k] << ") < gene_max (" << gene_max[k]
          << "), both finite, required";
      return msg.str();
    }
  }
  return "";
}

namespace {

// The GA's operators (ga.cpp) with per-gene bounds.
class Variation {
 public:
  Variation(const Nsga2Params& p, const std::vector<double>& lo, const std::vector<double>& hi)
      : p_(p), lo_(lo), hi_(hi) {
    mutation_rate_ = p.mutation_rate > 0.0 ? p.mutation_rate : 1.0 / static_cast<double>(lo.size());
  }
  double clamp(double g, size_t k) const { return std::min(hi_[k], std::max(lo_[k], g)); }
  void blend(std::vector<double>& a, std::vector<double>& b, Rng& rng) const {
    for (size_t k = 0; k < a.size(); ++k) {
      const double lo = std::min(a[k], b[k]);
      const double hi = std::max(a[k], b[k]);
      const double ext = p_.blend_alpha * (hi - lo);
      a[k] = clamp(rng.uniform(lo - ext, hi + ext), k);
      b[k] = clamp(rng.uniform(lo - ext, hi + ext), k);
    }
  }
  void mutate(std::vector<double>& genes, Rng& rng) const {
    for (size_t k = 0; k < genes.size(); ++k) {
      if (rng.bernoulli(mutation_rate_)) {
        genes[k] = clamp(genes[k] + p_.mutation_sigma * (hi_[k] - lo_[k]) * rng.normal(), k);
      }
    }
  }

 private:
  const Nsga2Params& p_;
  const std::vector<double>& lo_;
  const std::vector<double>& hi_;
  double mutation_rate_;
};

}  // namespace

Nsga2::Nsga2(const Nsga2Params& params, std::vector<double> gene_min, std::vector<double> gene_max,
             BatchObjectivesFunction objectives, std::vector<double> initial_genes)
    : params_(params),
      lo_(std::move(gene_min)),
      hi_(std::move(gene_max)),
      initial_(std::move(initial_genes)),
      fn_(std::move(objectives)) {
  const std::string err = validateNsga2Params(params_, lo_, hi_);
  if (!err.empty()) throw std::invalid_argument("NSGA-II: " + err);
  if (!fn_) throw std::invalid_argument("NSGA-II: no objectives function");
  if (!initial_.empty() && initial_.size() != lo_.size()) {
    throw std::invalid_argument("NSGA-II: " + std::to_string(initial_.size()) +
                                " initial genes for bounds of " + std::to_string(lo_.size()));
  }
  for (size_t k = 0; k < initial_.size(); ++k) {
    if (!(initial_[k] >= lo_[k] && initial_[k] <= hi_[k])) {
      std::ostringstream msg;
      msg << "NSGA-II: initial gene " << k << " (" << initial_[k] << ") is not in [" << lo_[k]
          << ", " << hi_[k] << "]";
      throw std::invalid_argument(msg.str());
    }
  }
}

// Evaluates the genomes that have no objectives yet, in one batch.
void Nsga2::evaluateNew(std::vector<std::vector<double>>& genes, ObjectiveTable& objectives) {
  const size_t first = objectives.size();
  const std::vector<std::vector<double>> fresh(genes.begin() + static_cast<long>(first),
                                               genes.end());
  ObjectiveTable rows = fn_(fresh);
  const int generation = generation_ + 1;
  if (rows.size() != fresh.size()) {
    throw std::runtime_error("NSGA-II: generation " + std::to_string(generation) + ": " +
                             std::to_string(rows.size()) + " objective rows for " +
                             std::to_string(fresh.size()) + " genomes");
  }
  for (size_t j = 0; j < rows.size(); ++j) {
    const std::vector<double>& f = rows[j];
    std::ostringstream where;
    where << "NSGA-II: generation " << generation << ", individual " << first + j << ": ";
    if (f.empty()) throw std::runtime_error(where.str() + "no objectives");
    const size_t count = objectives.empty() ? rows[0].size() : objectives[0].size();
    if (f.size() != count) {
      where << f.size() << " objectives, the first genome had " << count;
      throw std::runtime_error(where.str());
    }
    for (size_t m = 0; m < f.size(); ++m) {
      if (!std::isfinite(f[m])) {
        where << "objective " << m << " is " << f[m];
        throw std::runtime_error(where.str());
      }
    }
  }
  for (std::vector<double>& f : rows) objectives.push_back(std::move(f));
  evaluations_ = static_cast<int>(fresh.size());
}

void Nsga2::initialize() {
  const size_t n = static_cast<size_t>(params_.population);
  Rng rng(mixSeed(params_.seed, 0));
  std::vector<std::vector<double>> genes;
  for (size_t i = 0; i < n; ++i) {
    std::vector<double> g(lo_.size());
    for (size_t k = 0; k < g.size(); ++k) {
      if (initial_.empty()) {
        g[k] = rng.uniform(lo_[k], hi_[k]);
      } else {
        const double sigma = params_.mutation_sigma * (hi_[k] - lo_[k]);
        g[k] =
            std::clamp(i == 0 ? initial_[k] : initial_[k] + sigma * rng.normal(), lo_[k], hi_[k]);
      }
    }
    genes.push_back(std::move(g));
  }
  ObjectiveTable objectives;
  evaluateNew(genes, objectives);
  genes_ = std::move(genes);
  objectives_ = std::move(objectives);
  generation_ = 0;
}

void Nsga2::step() {
  if (generation_ < 0) {
    initialize();
    return;
  }
  const int g = generation_ + 1;
  const size_t n = static_cast<size_t>(params_.population);
  const Variation variation(params_, lo_, hi_);
  Rng rng(mixSeed(params_.seed, static_cast<std::uint64_t>(g)));
  const std::vector<int> ranks = paretoRanks(objectives_);
  const std::vector<double> crowding = crowdingDistances(objectives_, ranks);
  auto tournament = [&]() -> const std::vector<double>& {
    const int a = static_cast<int>(rng.index(n));
    const int b = static_cast<int>(rng.index(n));
    return genes_[crowdedBetter(a, b, ranks, crowding) ? a : b];
  };
  std::vector<std::vector<double>> all = genes_;  // parents, then their children
  ObjectiveTable all_objectives = objectives_;
  while (all.size() < 2 * n) {
    std::vector<double> a = tournament();
    std::vector<double> b = tournament();
    if (rng.bernoulli(params_.crossover_rate)) variation.blend(a, b, rng);
    variation.mutate(a, rng);
    variation.mutate(b, rng);
    all.push_back(std::move(a));
    all.push_back(std::move(b));
  }
  evaluateNew(all, all_objectives);
  std::vector<std::vector<double>> next;
  ObjectiveTable next_objectives;
  for (int i : nsga2Survivors(all_objectives, static_cast<int>(n))) {
    next.push_back(std::move(all[i]));
    next_objectives.push_back(std::move(all_objectives[i]));
  }
  genes_ = std::move(next);
  objectives_ = std::move(next_objectives);
  generation_ = g;
}

void Nsga2::restore(int generation, std::vector<std::vector<double>> genes,
                    ObjectiveTable objectives) {
  if (generation < 0 || generation > kMaxGenerations) {
    throw std::invalid_argument("NSGA-II restore: generation " + std::to_string(generation) +
                                " is not in [0, " + std::to_string(kMaxGenerations) + "]");
  }
  if (genes.size() != static_cast<size_t>(params_.population) ||
      objectives.size() != genes.size()) {
    throw std::invalid_argument("NSGA-II restore: " + std::to_string(genes.size()) +
                                " genomes and " + std::to_string(objectives.size()) +
                                " objective rows for a population of " +
                                std::to_string(params_.population));
  }
  checkObjectives(objectives, "NSGA-II restore");
  for (size_t i = 0; i < genes.size(); ++i) {
    bool inside = genes[i].size() == lo_.size();
    for (size_t k = 0; inside && k < lo_.size(); ++k) {
      inside = genes[i][k] >= lo_[k] && genes[i][k] <= hi_[k];
    }
    if (!inside) {
      throw std::invalid_argument("NSGA-II restore: genome " + std::to_string(i) +
                                  " is not of the bounds' length or is outside them");
    }
  }
  genes_ = std::move(genes);
  objectives_ = std::move(objectives);
  generation_ = generation;
  evaluations_ = 0;
}

Nsga2Result runNsga2(const Nsga2Params& params, const std::vector<double>& gene_min,
                     const std::vector<double>& gene_max, const ObjectivesFunction& objectives) {
  if (!objectives) throw std::invalid_argument("NSGA-II: no objectives function");
  Nsga2 run(params, gene_min, gene_max, [&objectives](const std::vector<std::vector<double>>& g) {
    ObjectiveTable rows;
    for (const std::vector<double>& genes : g) rows.push_back(objectives(genes));
    return rows;
  });
  run.initialize();
  while (run.generation() < params.generations) run.step();
  Nsga2Result result;
  result.ranks = paretoRanks(run.objectives());
  result.genes = run.genes();
  result.objectives = run.objectives();
  return result;
}

}  // namespace flapsim
