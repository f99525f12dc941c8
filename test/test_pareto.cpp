// NSGA-II (pareto.h): the non-dominated sort, crowding distances and survivors on hand-made
// sets, the input checks, the driver on ZDT1 against its analytic front, and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "flapsim/pareto.h"

namespace flapsim {
namespace {

const double kInf = std::numeric_limits<double>::infinity();

// The message of the std::invalid_argument that f throws ("" if none).
template <typename F>
std::string invalidArgument(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// Two fronts of two objectives and a lone third (crowding by hand in the tests below).
ObjectiveTable twoFronts() {
  return {
      {3, 3},    // 0: front 0, interior
      {0, 10},   // 1: front 0, extreme
      {10, -2},  // 2: front 0, extreme
      {1, 6},    // 3: front 0, interior
      {5, 12},   // 4: front 1, extreme
      {6, 11},   // 5: front 1, interior
      {13, 9},   // 6: front 1, extreme
      {14, 13},  // 7: front 2, alone
  };
}

TEST(ParetoRanks, ThreeFrontsWithADuplicateSharingRankZero) {
  const ObjectiveTable f = {
      {6, 5},  // dominated by all the others, by rank-1 points too: rank 2
      {1, 5},  // front 0
      {3, 4},  // dominated by (2, 3) only: rank 1
      {2, 3},  // front 0
      {5, 2},  // dominated by (4, 1) only: rank 1
      {4, 1},  // front 0
      {2, 3},  // the same as row 3: neither dominates, rank 0
  };
  EXPECT_EQ(paretoRanks(f), (std::vector<int>{2, 0, 1, 0, 1, 0, 0}));
}

TEST(ParetoRanks, OneObjectiveRanksTheDistinctValuesInOrder) {
  EXPECT_EQ(paretoRanks({{3}, {1}, {2}, {1}, {7}}), (std::vector<int>{2, 0, 1, 0, 3}));
  EXPECT_TRUE(paretoRanks({}).empty());
}

TEST(ParetoRanks, ThreeObjectivesAPointWorseInOneOnlyIsDominated) {
  // Row 1 equals row 0 except one objective that is worse; row 2 trades one for another.
  EXPECT_EQ(paretoRanks({{1, 2, 3}, {1, 2, 4}, {0, 2, 5}}), (std::vector<int>{0, 1, 0}));
}

TEST(CrowdingDistances, ExtremesInfiniteInteriorsByHandPerFrontRange) {
  const ObjectiveTable f = twoFronts();
  const std::vector<double> d = crowdingDistances(f, paretoRanks(f));
  ASSERT_EQ(d.size(), 8u);
  for (int i : {1, 2, 4, 6, 7}) EXPECT_EQ(d[i], kInf) << "row " << i;
  // Front 0 spans 10 in f1 (0..10) and 12 in f2 (-2..10).
  EXPECT_NEAR(d[0], (10.0 - 1.0) / 10.0 + (6.0 - -2.0) / 12.0, 1e-15);  // 1.5667
  EXPECT_NEAR(d[3], (3.0 - 0.0) / 10.0 + (10.0 - 3.0) / 12.0, 1e-15);   // 0.8833
  // Front 1's own ranges (8 and 3), not the whole set's (14 and 15): (8/8 + 3/3).
  EXPECT_NEAR(d[5], 2.0, 1e-15);
}

TEST(CrowdingDistances, ZeroRangeAddsNothingAndTiesGoByIndex) {
  // Three equal rows: one front; the first and last index are the extremes.
  const ObjectiveTable f = {{2, 5}, {2, 5}, {2, 5}};
  EXPECT_EQ(crowdingDistances(f, paretoRanks(f)), (std::vector<double>{kInf, 0.0, kInf}));
}

TEST(CrowdedBetter, RankThenCrowdingThenIndex) {
  const std::vector<int> ranks = {1, 0, 0, 0};
  const std::vector<double> crowding = {kInf, 0.5, 0.7, 0.5};
  EXPECT_TRUE(crowdedBetter(1, 0, ranks, crowding));   // rank beats an infinite crowding
  EXPECT_TRUE(crowdedBetter(2, 1, ranks, crowding));   // same rank: more isolated
  EXPECT_TRUE(crowdedBetter(1, 3, ranks, crowding));   // all equal: lower index
  EXPECT_FALSE(crowdedBetter(3, 1, ranks, crowding));  // ... and not the other way
  EXPECT_FALSE(crowdedBetter(2, 2, ranks, crowding));  // irreflexive
  EXPECT_NE(invalidArgument([&] { crowdedBetter(0, 4, ranks, crowding); }).find("index 4"),
            std::string::npos);
}

TEST(Nsga2Survivors, WholeFirstFrontThenTheLastCutByCrowding) {
  const ObjectiveTable f = twoFronts();
  // Front 0 whole (extremes, then 1.57 before 0.88); front 1's extremes, not its middle row 5
  // although its crowding (2.0) is larger than front 0's interiors'.
  EXPECT_EQ(nsga2Survivors(f, 6), (std::vector<int>{1, 2, 0, 3, 4, 6}));
  // Front 1's two extremes are both infinite: the lower index stays.
  EXPECT_EQ(nsga2Survivors(f, 5), (std::vector<int>{1, 2, 0, 3, 4}));
  EXPECT_EQ(nsga2Survivors(f, 8), (std::vector<int>{1, 2, 0, 3, 4, 6, 5, 7}));
  EXPECT_TRUE(nsga2Survivors(f, 0).empty());
}

TEST(ParetoInputChecks, RaggedNanBadRanksAndCountThrowNamingTheCulprit) {
  const std::string ragged = invalidArgument([] { paretoRanks({{1, 2}, {3, 4}, {5}}); });
  EXPECT_NE(ragged.find("row 2 has 1 objectives, row 0 has 2"), std::string::npos) << ragged;
  const std::string empty = invalidArgument([] { paretoRanks({{}}); });
  EXPECT_NE(empty.find("row 0 is empty"), std::string::npos) << empty;
  const double nan = std::nan("");
  const std::string not_finite = invalidArgument([&] { paretoRanks({{1, 2}, {3, 4}, {5, nan}}); });
  EXPECT_NE(not_finite.find("row 2, objective 1 is nan"), std::string::npos) << not_finite;
  const std::string inf = invalidArgument([&] { crowdingDistances({{kInf}}, {0}); });
  EXPECT_NE(inf.find("row 0, objective 0 is inf"), std::string::npos) << inf;
  const std::string ranks = invalidArgument([] { crowdingDistances({{1}, {2}}, {0}); });
  EXPECT_NE(ranks.find("1 ranks for 2 rows"), std::string::npos) << ranks;
  const std::string rank = invalidArgument([] { crowdingDistances({{1}, {2}}, {0, -1}); });
  EXPECT_NE(rank.find("rank -1 of row 1"), std::string::npos) << rank;
  const std::string count = invalidArgument([] { nsga2Survivors({{1}, {2}}, 3); });
  EXPECT_NE(count.find("count 3 is not in [0, 2]"), std::string::npos) << count;
}

// ZDT1 (Zitzler, Deb, Thiele 2000): 10 genes in [0, 1]; the Pareto front is f2 = 1 - sqrt(f1).
std::vector<double> zdt1(const std::vector<double>& x) {
  double sum = 0.0;
  for (size_t i = 1; i < x.size(); ++i) sum += x[i];
  const double g = 1.0 + 9.0 * sum / static_cast<double>(x.size() - 1);
  return {x[0], g * (1.0 - std::sqrt(x[0] / g))};
}

// Distance of (f1, f2) to the analytic front, sampled as (t^2, 1 - t) (spacing <= 2e-4).
double distanceToZdt1Front(const std::vector<double>& f) {
  double best = kInf;
  for (int k = 0; k <= 10000; ++k) {
    const double t = k / 10000.0;
    best = std::min(best, std::hypot(f[0] - t * t, f[1] - (1.0 - t)));
  }
  return best;
}

struct FrontFigures {
  int members = 0;     // rank-0 members
  double gd = 0.0;     // generational distance: mean distance to the analytic front
  double worst = 0.0;  // largest f2 - (1 - sqrt(f1)) of a member
  double f1_min = kInf;
  double f1_max = -kInf;
};

FrontFigures zdt1Front(const Nsga2Result& r) {
  FrontFigures out;
  for (size_t i = 0; i < r.ranks.size(); ++i) {
    if (r.ranks[i] != 0) continue;
    const std::vector<double>& f = r.objectives[i];
    ++out.members;
    out.gd += distanceToZdt1Front(f);
    out.worst = std::max(out.worst, f[1] - (1.0 - std::sqrt(f[0])));
    out.f1_min = std::min(out.f1_min, f[0]);
    out.f1_max = std::max(out.f1_max, f[0]);
  }
  out.gd /= out.members;
  return out;
}

Nsga2Result runZdt1(int generations, std::uint64_t seed) {
  Nsga2Params p;
  p.population = 40;
  p.generations = generations;
  p.seed = seed;
  return runNsga2(p, std::vector<double>(10, 0.0), std::vector<double>(10, 1.0), zdt1);
}

TEST(Nsga2Zdt1, Generation0FrontIsOver10TimesTheMeanDistanceBoundFromTheAnalyticFront) {
  // The bound of the next test is no accident of the problem: a random population misses it.
  EXPECT_GT(zdt1Front(runZdt1(0, 1)).gd, 10 * 0.01);  // measured 2.2
}

TEST(Nsga2Zdt1, After300GenerationsAll40WithinGap0p05MeanDistance0p01F1SpansBelow0p05ToAbove0p95) {
  // Measured (seed 1): 40 rank-0 members, GD 0.0018, worst gap 0.032, f1 from 0 to 1 (the
  // bounds, reached by clamping); seeds 1-10: GD <= 0.0018, worst gap <= 0.050. Broken variants
  // fail: all ranks 0 (GD 3.4), the second objective maximised in the dominance test (GD 9, f1 max
  // 0), no infinite crowding at the extremes (f1 max 0.91).
  const FrontFigures end = zdt1Front(runZdt1(300, 1));
  EXPECT_EQ(end.members, 40);
  EXPECT_LT(end.gd, 0.01);
  EXPECT_LT(end.worst, 0.05);
  EXPECT_LT(end.f1_min, 0.05);
  EXPECT_GT(end.f1_max, 0.95);
}

bool sameBits(const std::vector<std::vector<double>>& a,
              const std::vector<std::vector<double>>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].size() != b[i].size() ||
        std::memcmp(a[i].data(), b[i].data(), a[i].size() * sizeof(double)) != 0) {
      return false;
    }
  }
  return true;
}

TEST(Nsga2Determinism, SameSeedBitIdenticalAnotherSeedDifferent) {
  const Nsga2Result a = runZdt1(30, 5);
  const Nsga2Result b = runZdt1(30, 5);
  const Nsga2Result c = runZdt1(30, 6);
  EXPECT_TRUE(sameBits(a.genes, b.genes));
  EXPECT_TRUE(sameBits(a.objectives, b.objectives));
  EXPECT_EQ(a.ranks, b.ranks);
  EXPECT_FALSE(sameBits(a.genes, c.genes));
  EXPECT_FALSE(sameBits(a.objectives, c.objectives));
}

TEST(Nsga2Driver, GenesStayInPerGeneBoundsAndReachThemByClamping) {
  // Minimising x0 and -x1: one point, (gene_min[0], gene_max[1]), dominates every other.
  Nsga2Params p;
  p.population = 8;
  p.generations = 200;
  const std::vector<double> lo = {-3.0, 2.0}, hi = {-1.0, 5.0};
  const Nsga2Result r = runNsga2(p, lo, hi, [](const std::vector<double>& x) {
    return std::vector<double>{x[0], -x[1]};
  });
  ASSERT_EQ(r.genes.size(), 8u);
  for (const std::vector<double>& x : r.genes) {
    EXPECT_TRUE(x[0] >= -3.0 && x[0] <= -1.0 && x[1] >= 2.0 && x[1] <= 5.0) << x[0] << " " << x[1];
  }
  EXPECT_EQ(r.genes[0], (std::vector<double>{-3.0, 5.0}));
  EXPECT_EQ(r.ranks[0], 0);
}

TEST(Nsga2Driver, BadParamsBoundsAndObjectivesThrowNamingTheField) {
  const std::vector<double> lo = {0.0, 0.0}, hi = {1.0, 1.0};
  auto message = [&](Nsga2Params p, std::vector<double> min, std::vector<double> max) {
    return invalidArgument([&] { runNsga2(p, min, max, zdt1); });
  };
  Nsga2Params odd;
  odd.population = 41;
  EXPECT_NE(message(odd, lo, hi).find("population must be even"), std::string::npos);
  Nsga2Params negative;
  negative.generations = -1;
  EXPECT_NE(message(negative, lo, hi).find("generations"), std::string::npos);
  EXPECT_NE(message({}, {0.0}, hi).find("gene_min has 1 genes, gene_max 2"), std::string::npos);
  EXPECT_NE(message({}, lo, {1.0, 0.0}).find("gene 1:"), std::string::npos);
  EXPECT_NE(message({}, lo, {1.0, std::nan("")}).find("gene 1:"), std::string::npos);
  std::string runtime;
  try {
    runNsga2({}, lo, hi, [](const std::vector<double>& x) {
      return std::vector<double>{x[0], x[0] > 0.5 ? std::nan("") : 0.0};
    });
  } catch (const std::runtime_error& e) {
    runtime = e.what();
  }
  EXPECT_NE(runtime.find("generation 0, individual "), std::string::npos) << runtime;
  EXPECT_NE(runtime.find("objective 1 is nan"), std::string::npos) << runtime;
}

// ZDT1 through the batch class (one call per generation's new genomes).
BatchObjectivesFunction zdt1Batch(int* calls) {
  return [calls](const std::vector<std::vector<double>>& genomes) {
    ++*calls;
    ObjectiveTable rows;
    for (const auto& g : genomes) rows.push_back(zdt1(g));
    return rows;
  };
}

// The class a generation at a time is runNsga2 to the bit, one batch per generation (the
// children alone after generation 0); restored from generation 10's survivors it ends at
// generation 20 as the uninterrupted run.
TEST(Nsga2Class, StepByStepItIsRunNsga2AndARestoreAtGeneration10EndsAsTheWholeRun) {
  Nsga2Params p;
  p.population = 40;
  p.generations = 20;
  p.seed = 7;
  const std::vector<double> lo(10, 0.0), hi(10, 1.0);
  int calls = 0;
  Nsga2 whole(p, lo, hi, zdt1Batch(&calls));
  std::vector<std::vector<double>> genes_10;
  ObjectiveTable objectives_10;
  for (int g = 0; g <= 20; ++g) {
    whole.step();
    EXPECT_EQ(whole.generation(), g);
    EXPECT_EQ(whole.evaluations(), 40);  // generation 0's 40, then 40 children each
    if (g == 10) genes_10 = whole.genes(), objectives_10 = whole.objectives();
  }
  EXPECT_EQ(calls, 21);
  const Nsga2Result reference = runNsga2(p, lo, hi, zdt1);
  EXPECT_EQ(whole.genes(), reference.genes);
  EXPECT_EQ(whole.objectives(), reference.objectives);
  Nsga2 resumed(p, lo, hi, zdt1Batch(&calls));
  resumed.restore(10, genes_10, objectives_10);
  while (resumed.generation() < 20) resumed.step();
  EXPECT_EQ(resumed.genes(), whole.genes());
  EXPECT_EQ(resumed.objectives(), whole.objectives());
}

// Seeded, generation 0 is the initial genes first and the others about them: each gene moved
// by a Gaussian of mutation_sigma x its range, so the moves' rms is that sigma (0.1 of the
// range; 39 x 10 draws: within 15 %), clamped to the bounds.
TEST(Nsga2Class, ASeededGeneration0IsTheSeedThenItMovedByMutationSigmaOfTheRange) {
  Nsga2Params p;
  p.population = 40;
  p.mutation_sigma = 0.1;
  int calls = 0;
  std::vector<double> seed(10, 0.5);  // genes 0-4 in [0, 1], 5-9 in [-2, 2], 5 sigma inside
  std::vector<double> lo10(10, 0.0), hi10(10, 1.0);
  for (size_t k = 5; k < 10; ++k) lo10[k] = -2.0, hi10[k] = 2.0, seed[k] = 0.0;
  Nsga2 run(p, lo10, hi10, zdt1Batch(&calls), seed);
  run.initialize();
  ASSERT_EQ(run.genes().size(), 40u);
  EXPECT_EQ(run.genes()[0], seed);
  double sum[2] = {0.0, 0.0};
  for (size_t i = 1; i < 40; ++i) {
    for (size_t k = 0; k < 10; ++k) {
      const double g = run.genes()[i][k];
      ASSERT_TRUE(g >= lo10[k] && g <= hi10[k]) << i << " " << k;
      const double move = (g - seed[k]) / (hi10[k] - lo10[k]);
      sum[k < 5 ? 0 : 1] += move * move;
    }
  }
  for (double s2 : sum) EXPECT_NEAR(std::sqrt(s2 / (39 * 5)), 0.1, 0.015);
  auto refusal = [&](std::vector<double> initial) {
    try {
      Nsga2(p, lo10, hi10, zdt1Batch(&calls), std::move(initial));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal(std::vector<double>(3, 0.5)), "NSGA-II: 3 initial genes for bounds of 10");
  std::vector<double> outside = seed;
  outside[7] = 2.5;
  EXPECT_EQ(refusal(outside), "NSGA-II: initial gene 7 (2.5) is not in [-2, 2]");
}

// A batch that answers another count of rows, or a restore that does not fit, is refused.
TEST(Nsga2Class, ABatchOfTheWrongCountAndARestoreThatDoesNotFitAreRefusedByName) {
  Nsga2Params p;
  p.population = 4;
  const std::vector<double> lo(2, 0.0), hi(2, 1.0);
  Nsga2 short_batch(p, lo, hi, [](const std::vector<std::vector<double>>& g) {
    return ObjectiveTable(g.size() - 1, std::vector<double>{0.0, 0.0});
  });
  try {
    short_batch.initialize();
    ADD_FAILURE() << "accepted 3 rows for 4 genomes";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "NSGA-II: generation 0: 3 objective rows for 4 genomes");
  }
  int calls = 0;
  Nsga2 run(p, lo, hi, zdt1Batch(&calls));
  const std::vector<std::vector<double>> genes(4, {0.5, 0.5});
  EXPECT_THROW(run.restore(3, genes, ObjectiveTable(3, {1.0, 1.0})), std::invalid_argument);
  EXPECT_THROW(run.restore(3, std::vector<std::vector<double>>(4, {0.5, 1.5}),
                           ObjectiveTable(4, {1.0, 1.0})),
               std::invalid_argument);
  EXPECT_THROW(run.restore(3, genes, ObjectiveTable(4, {1.0, std::nan("")})),
               std::invalid_argument);
  EXPECT_EQ(run.generation(), -1);  // nothing taken
  run.restore(3, genes, ObjectiveTable(4, {1.0, 1.0}));
  EXPECT_EQ(run.generation(), 3);
}

}  // namespace
}  // namespace flapsim
