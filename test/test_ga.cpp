// The real-coded GA: its random numbers, elitism, determinism, convergence on
// a toy problem, and independence from the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "flapsim/ga.h"

namespace flapsim {
namespace {

TEST(Rng, UniformIsTheTop53BitsOfMt19937_64) {
  // The standard fixes mt19937_64's output: the first draw for the default
  // seed 5489 is 14514284786278117030.
  Rng rng(5489);
  EXPECT_EQ(rng.uniform(), static_cast<double>(14514284786278117030ULL >> 11) * 0x1.0p-53);
}

TEST(Rng, DistributionsHaveTheirMoments) {
  Rng rng(42);
  const int n = 200000;
  double su = 0, su2 = 0, sn = 0, sn2 = 0;
  std::vector<int> counts(7, 0);
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    su += u;
    su2 += u * u;
    const double g = rng.normal();
    sn += g;
    sn2 += g * g;
    ++counts[rng.index(7)];
  }
  EXPECT_NEAR(su / n, 0.5, 0.005);
  EXPECT_NEAR(su2 / n - 0.25, 1.0 / 12.0, 0.002);
  EXPECT_NEAR(sn / n, 0.0, 0.01);
  EXPECT_NEAR(sn2 / n, 1.0, 0.01);
  for (int c : counts) EXPECT_NEAR(c, n / 7.0, 0.02 * n / 7.0);
}

TEST(Rng, SameSeedSameStreamAndMixedSeedsDiffer) {
  Rng a(7), b(7);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(a.normal(), b.normal());
  std::set<std::uint64_t> seeds;
  for (std::uint64_t g = 0; g < 50; ++g) {
    for (std::uint64_t i = 0; i < 20; ++i) seeds.insert(mixSeed(1, g, i));
  }
  EXPECT_EQ(seeds.size(), 1000u);
  EXPECT_NE(mixSeed(1, 2, 3), mixSeed(1, 3, 2));
}

// Maximum 0 at `target`.
double sphere(const std::vector<double>& genes, const std::vector<double>& target) {
  double s = 0.0;
  for (size_t i = 0; i < genes.size(); ++i) s -= (genes[i] - target[i]) * (genes[i] - target[i]);
  return s;
}

const std::vector<double> kTarget = {1.5, -2.0, 3.25};

FitnessFunction toyFitness() {
  return [](const std::vector<double>& g, std::uint64_t) { return sphere(g, kTarget); };
}

TEST(GeneticAlgorithm, DefaultsAreThePapers) {
  const GaParams p;
  EXPECT_EQ(p.population, 10);
  EXPECT_EQ(p.generations, 200);
  EXPECT_GE(p.elite_count, 1);
  EXPECT_DOUBLE_EQ(p.crossover_rate, 0.1);
  EXPECT_DOUBLE_EQ(p.mutation_rate, 0.05);
}

// evolve --init: generation 0 holds the given genome unchanged (its fitness, 0 at the optimum
// here, is generation 0's best) and the rest scattered around it; a random generation 0 of the
// same seed misses the optimum; a seed gene outside the gene range is refused by its index.
TEST(GeneticAlgorithm, AnInitialGenomeSeedsGenerationZero) {
  const std::vector<double> target = {1.5, -2.0, 0.25, 3.0};
  auto distance = [&](const std::vector<double>& g, std::uint64_t) {
    double d = 0.0;
    for (size_t k = 0; k < g.size(); ++k) d -= (g[k] - target[k]) * (g[k] - target[k]);
    return d;
  };
  GaParams p;
  p.seed = 3;
  GeneticAlgorithm random(p, 4, distance);
  random.initialize();
  EXPECT_LT(random.best().fitness, -1.0);
  p.initial_genes = target;
  GeneticAlgorithm seeded(p, 4, distance);
  seeded.initialize();
  EXPECT_EQ(seeded.best().fitness, 0.0);
  EXPECT_EQ(seeded.best().genes, target);
  // The others: moved by mutation_sigma x range = 2 per gene (clamped): near, not equal.
  double spread = 0.0;
  for (size_t i = 1; i < seeded.population().size(); ++i) {
    spread += -seeded.population()[i].fitness / (4.0 * (seeded.population().size() - 1));
  }
  EXPECT_GT(spread, 0.5 * 4.0);  // mean square move per gene ~ sigma^2 = 4
  EXPECT_LT(spread, 2.0 * 4.0);
  p.initial_genes = {1.5, -2.0, 11.0, 3.0};
  try {
    GeneticAlgorithm bad(p, 4, distance);
    ADD_FAILURE() << "a seed gene of 11 outside +-10 was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("initial gene 2 (11) is not in [-10, 10]"),
              std::string::npos)
        << e.what();
  }
  p.initial_genes = target;
  EXPECT_THROW(GeneticAlgorithm(p, 5, distance), std::invalid_argument);  // 4 genes for 5
}

TEST(GeneticAlgorithm, ElitismNeverLetsTheBestFall) {
  for (bool reuse : {true, false}) {
    GaParams p;
    p.seed = 3;
    p.reuse_fitness_of_copies = reuse;
    GeneticAlgorithm ga(p, 3, toyFitness());
    ga.run();
    ASSERT_EQ(ga.history().size(), 201u);
    for (size_t g = 1; g < ga.history().size(); ++g) {
      ASSERT_GE(ga.history()[g].best, ga.history()[g - 1].best) << "generation " << g;
      ASSERT_GE(ga.history()[g].best,
                ga.history()[g].mean - 1e-12 * std::abs(ga.history()[g].mean));
    }
    EXPECT_GT(ga.history().back().best, ga.history().front().best);  // and it does improve
    // The reported best is the best genome's true fitness.
    EXPECT_EQ(ga.best().fitness, sphere(ga.best().genes, kTarget));
  }
}

TEST(GeneticAlgorithm, ConvergesOnAToyProblemWithAKnownOptimum) {
  // A random genome in [-5, 5]^3 is ~5.5 from the target on average.
  int close = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    GaParams p;
    p.seed = seed;
    p.gene_min = -5.0;
    p.gene_max = 5.0;
    GeneticAlgorithm ga(p, 3, toyFitness());
    ga.run();
    const double distance = std::sqrt(-ga.best().fitness);
    EXPECT_LT(distance, 0.2) << "seed " << seed;
    if (distance < 0.1) ++close;
    for (double g : ga.best().genes) {
      EXPECT_GE(g, p.gene_min);
      EXPECT_LE(g, p.gene_max);
    }
  }
  EXPECT_GE(close, 4);
}

TEST(GeneticAlgorithm, SameSeedSameResultOtherSeedOtherResult) {
  auto run = [](std::uint64_t seed) {
    GaParams p;
    p.seed = seed;
    p.generations = 50;
    GeneticAlgorithm ga(p, 3, toyFitness());
    ga.run();
    return ga.history();
  };
  const auto a = run(11), b = run(11), c = run(12);
  ASSERT_EQ(a.size(), b.size());
  for (size_t g = 0; g < a.size(); ++g) {
    EXPECT_EQ(a[g].best, b[g].best);
    EXPECT_EQ(a[g].mean, b[g].mean);
    EXPECT_EQ(a[g].best_genes, b[g].best_genes);
  }
  EXPECT_NE(a.back().best_genes, c.back().best_genes);
}

TEST(GeneticAlgorithm, ThreadCountDoesNotChangeResults) {
  // A noisy fitness that uses its evaluation seed, so any mix-up of which
  // individual got which evaluation would show.
  const FitnessFunction noisy = [](const std::vector<double>& g, std::uint64_t eval_seed) {
    Rng rng(eval_seed);
    return sphere(g, kTarget) + 0.1 * rng.normal();
  };
  auto run = [&](int threads) {
    GaParams p;
    p.seed = 5;
    p.generations = 40;
    p.threads = threads;
    p.reuse_fitness_of_copies = false;
    GeneticAlgorithm ga(p, 3, noisy);
    ga.run();
    return ga.history();
  };
  const auto one = run(1), two = run(2), four = run(4);
  for (const auto* other : {&two, &four}) {
    ASSERT_EQ(one.size(), other->size());
    for (size_t g = 0; g < one.size(); ++g) {
      EXPECT_EQ(one[g].best, (*other)[g].best) << "generation " << g;
      EXPECT_EQ(one[g].mean, (*other)[g].mean) << "generation " << g;
      EXPECT_EQ(one[g].best_genes, (*other)[g].best_genes) << "generation " << g;
    }
  }
}

// With reevaluate_every_generation, a fitness that changes with the generation (here: less the
// generation being evaluated, as generation() gives it during the call) is that generation's
// for every individual, the elite's too; without, the elite keeps an older one.
TEST(GeneticAlgorithm, AskedToEveryIndividualIsEvaluatedAnewInEachGeneration) {
  for (bool anew : {true, false}) {
    GaParams p;
    p.generations = 10;
    p.reevaluate_every_generation = anew;
    const GeneticAlgorithm* ga_running = nullptr;
    GeneticAlgorithm ga(p, 3, [&](const std::vector<double>& g, std::uint64_t) {
      return sphere(g, kTarget) - ga_running->generation();
    });
    ga_running = &ga;
    int stale = 0;
    ga.run([&](const GenerationStats& s) {
      if (anew) {
        EXPECT_EQ(s.evaluations, p.population) << "generation " << s.generation;
      }
      for (const Individual& ind : ga.population()) {
        stale += ind.fitness != sphere(ind.genes, kTarget) - s.generation;
      }
    });
    if (anew) {
      EXPECT_EQ(stale, 0);
    } else {
      EXPECT_GE(stale, 10);  // the elite, at least, in each generation after the first
    }
  }
}

TEST(GeneticAlgorithm, OnlyChangedChildrenAreEvaluated) {
  int calls = 0;  // single thread: no race
  GaParams p;
  p.generations = 30;
  GeneticAlgorithm ga(p, 3, [&](const std::vector<double>& g, std::uint64_t) {
    ++calls;
    return sphere(g, kTarget);
  });
  int reported = 0;
  ga.run([&](const GenerationStats& s) { reported += s.evaluations; });
  EXPECT_EQ(calls, reported);
  EXPECT_EQ(ga.history().front().evaluations, 10);
  // Each child is changed with probability ~ 0.1 + 0.9 * (1 - 0.95^3) = 0.23.
  EXPECT_LT(calls, 10 + 30 * 9 / 2);
  EXPECT_GT(calls, 10 + 30 * 9 / 20);
}

TEST(GeneticAlgorithm, BadParametersAndFitnessAreRefused) {
  GaParams p;
  p.population = 1;
  EXPECT_THROW(GeneticAlgorithm(p, 3, toyFitness()), std::invalid_argument);
  p = GaParams();
  p.elite_count = 10;
  EXPECT_THROW(GeneticAlgorithm(p, 3, toyFitness()), std::invalid_argument);
  p = GaParams();
  p.mutation_rate = 1.5;
  EXPECT_THROW(GeneticAlgorithm(p, 3, toyFitness()), std::invalid_argument);
  EXPECT_THROW(GeneticAlgorithm(GaParams(), 0, toyFitness()), std::invalid_argument);
  GeneticAlgorithm nan(GaParams(), 2,
                       [](const std::vector<double>&, std::uint64_t) { return std::nan(""); });
  EXPECT_THROW(nan.initialize(), std::runtime_error);
  GeneticAlgorithm inf(GaParams(), 2, [](const std::vector<double>&, std::uint64_t) {
    return std::numeric_limits<double>::infinity();
  });
  EXPECT_THROW(inf.initialize(), std::runtime_error);
  p = GaParams();
  p.population = kMaxPopulation + 1;
  EXPECT_THROW(GeneticAlgorithm(p, 3, toyFitness()), std::invalid_argument);
  p = GaParams();
  p.generations = kMaxGenerations + 1;
  EXPECT_THROW(GeneticAlgorithm(p, 3, toyFitness()), std::invalid_argument);
}

TEST(ParallelMap, ResultsInIndexOrderAndErrorsRethrown) {
  const auto out = parallelMap(100, 3, [](int i) { return i * 0.5; });
  ASSERT_EQ(out.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(out[i], i * 0.5);
  EXPECT_THROW(parallelMap(10, 2,
                           [](int i) -> double {
                             if (i == 7) throw std::logic_error("seven");
                             return i;
                           }),
               std::logic_error);
}

}  // namespace
}  // namespace flapsim
