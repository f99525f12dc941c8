// Fuzzing the readers of the files an evolution writes and a controller reads (seeded: the
// same cases every run, a failure replays): 3,000 mutants of a checkpoint and 3,000 of a
// weights YAML. Each is refused with a named error (the line, or the file and key) or read
// into values within every limit, which the GA and the network then take.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"

namespace flapsim {
namespace {

constexpr int kCases = 3000;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string join(const std::vector<std::string>& ls) {
  std::string out;
  for (const auto& l : ls) out += l + "\n";
  return out;
}

// Values that have broken readers: not numbers, not finite, wrapping, huge, empty, long.
const std::vector<std::string> kHostile = {"nan",        "-nan",
                                           "inf",        "-inf",
                                           "1e308",      "-1e308",
                                           "1e-320",     "0x1p+1024",
                                           "4294967298", "-1",
                                           "0",          "1",
                                           "2",          "3x",
                                           "",           "  ",
                                           "0x",         "9223372036854775808",
                                           "1e9",        "a",
                                           "[",          "{",
                                           "]",          "}",
                                           ":",          "- ",
                                           "'",          "\"",
                                           "&a",         "*a",
                                           "!!binary",   "#",
                                           "\t",         std::string(5000, '9'),
                                           "true"};

// One mutation of `text`, drawn from `rng`: a token replaced by a hostile value or another
// token, a line dropped, duplicated or swapped, the text cut, or bytes inserted.
std::string mutate(const std::string& text, Rng& rng) {
  std::vector<std::string> ls = lines(text);
  if (ls.empty()) return text;
  const size_t l = rng.index(ls.size());
  switch (rng.index(7)) {
    case 0:
    case 1: {  // a token of a line
      std::vector<std::string> tokens;
      std::istringstream in(ls[l]);
      for (std::string t; in >> t;) tokens.push_back(t);
      if (tokens.empty()) break;
      tokens[rng.index(tokens.size())] = kHostile[rng.index(kHostile.size())];
      std::string joined;
      for (const auto& t : tokens) joined += (joined.empty() ? "" : " ") + t;
      ls[l] = joined;
      break;
    }
    case 2:
      ls.erase(ls.begin() + l);
      break;
    case 3:
      ls.insert(ls.begin() + l, ls[l]);
      break;
    case 4:
      std::swap(ls[l], ls[rng.index(ls.size())]);
      break;
    case 5:
      return text.substr(0, rng.index(text.size() + 1));
    default: {
      std::string t = text;
      const std::string junk = kHostile[rng.index(kHostile.size())];
      return t.insert(rng.index(t.size() + 1), junk);
    }
  }
  return join(ls);
}

std::string mutant(const std::string& text, Rng& rng) {
  std::string t = text;
  for (int m = 1 + static_cast<int>(rng.index(3)); m > 0; --m) t = mutate(t, rng);
  return t;
}

EvolveParams tinyRun() {
  EvolveParams p = robustPreset();
  p.ga.population = 4;
  p.ga.generations = 2;
  p.ga.seed = 9;
  p.episode.duration = 0.1;
  p.episode.episodes = 2;
  return p;
}

TEST(FileFuzz, CheckpointMutantsAreRefusedByLineOrWithinEveryLimit) {
  const EvolveParams p = tinyRun();
  std::string base;
  EvolveHooks hooks;
  hooks.on_checkpoint = [&](EvolveCheckpoint c) {
    c.args = {"--preset", "robust", "--seed", "9"};
    base = checkpointToText(c);
  };
  evolveFlapController(p, hooks);
  Rng rng(27);
  int refused = 0, read = 0, restored = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < kCases; ++k) {
    const std::string text = mutant(base, rng);
    EvolveCheckpoint c;
    try {
      c = checkpointFromText(text);
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("checkpoint line ", 0), 0u) << "case " << k << ": " << msg;
      EXPECT_LT(msg.size(), 200u) << "case " << k;
      ++refused;
      continue;
    }
    ++read;
    ASSERT_GE(c.population.size(), 2u) << k;
    ASSERT_LE(c.population.size(), static_cast<size_t>(kMaxPopulation)) << k;
    ASSERT_EQ(c.history.size(), static_cast<size_t>(c.generation) + 1) << k;
    for (const auto& ind : c.population) {
      ASSERT_TRUE(std::isfinite(ind.fitness)) << k;
      for (double g : ind.genes) ASSERT_TRUE(std::isfinite(g)) << k;
    }
    for (const auto& h : c.history) {
      ASSERT_TRUE(std::isfinite(h.best) && std::isfinite(h.mean) && std::isfinite(h.worst)) << k;
    }
    // What the GA makes of it: taken, or refused by name.
    GeneticAlgorithm ga(p.ga, 12, [](const std::vector<double>&, std::uint64_t) { return 0.0; });
    try {
      ga.restore(c.generation, c.population, c.history);
      ++restored;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("GA restore: ", 0), 0u) << k << ": " << e.what();
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("checkpoint fuzz: %d refused, %d read (%d restored) in %.2f s\n", refused, read,
              restored, seconds);
  EXPECT_GT(refused, 0);
  EXPECT_GT(read, 0);
}

TEST(FileFuzz, WeightsYamlMutantsAreRefusedByNameOrAWorkingNetwork) {
  ControllerSpec spec;
  spec.params.phase_lock = true;
  for (int i = 0; i < 12; ++i) spec.weights.push_back(0.37 * i - 2.0);
  const std::string base = controllerToYaml(spec, "fuzz", {{"seed", "1"}});
  Rng rng(28);
  int refused = 0, read = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < kCases; ++k) {
    const std::string text = k == 0 ? std::string(20000, '[') : mutant(base, rng);
    ControllerSpec got;
    try {
      got = controllerFromYaml(text, "fuzz.yaml");
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("controller YAML fuzz.yaml: ", 0), 0u) << "case " << k << ": " << msg;
      EXPECT_LT(msg.size(), 300u) << "case " << k << ": " << msg.substr(0, 300);
      ++refused;
      continue;
    }
    ++read;
    ASSERT_EQ(validateFlapControllerParams(got.params), "") << k;
    for (double w : got.weights) ASSERT_TRUE(std::isfinite(w)) << k;
    const FlapUnitController net(got.params, got.weights);  // takes them as they are
    for (double r : net.rates({0.1, -0.2})) ASSERT_TRUE(std::isfinite(r)) << k;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("weights fuzz: %d refused, %d read in %.2f s\n", refused, read, seconds);
  EXPECT_GT(refused, 0);
  EXPECT_GT(read, 0);
}

}  // namespace
}  // namespace flapsim
