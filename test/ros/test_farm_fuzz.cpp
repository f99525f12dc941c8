// Fuzzing flapsim_worker's service without a master (seeded: the same cases every run): 3,000
// requests mutated from a valid one (the spec's flags and values, the weight count, the
// weights, the episodes). Each is answered with one finite fitness per task within the
// spec's bound, or refused with a short message naming the fault and no fitness; the
// runner cache stays within its bytes.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "flapsim/ga.h"
#include "flapsim_ros/episode_farm.h"

namespace {

using flapsim::Rng;

// Short episodes: an accepted request flies 2 x 200 steps.
const std::vector<std::string> kSpec = {"--preset", "robust", "--episodes", "2",
                                        "--seed",   "5",      "--duration", "0.1"};

// Hostile values of a flag; none makes an accepted episode longer than 0.1 s of 0.5 ms steps.
const std::vector<std::string> kValues = {"nan",
                                          "inf",
                                          "-inf",
                                          "-1",
                                          "0",
                                          "1e9",
                                          "4.3e7",
                                          "10000000",
                                          "10001",
                                          "3x",
                                          "",
                                          " 1",
                                          "0x10",
                                          "1e-7",
                                          "0.001,",
                                          ",",
                                          "paper",
                                          "robust",
                                          "2",
                                          "1000",
                                          "65",
                                          "3000",
                                          "18446744073709551616",
                                          std::string(5000, '7'),
                                          "pressure",
                                          "quasi_steady",
                                          "vacuum",
                                          "on",
                                          "off",
                                          "roll",
                                          "yaw"};
// Flags: the run's, others that must not be in a spec, and none at all.
const std::vector<std::string> kFlags = {"--preset",     "--pairs",
                                         "--episodes",   "--seed",
                                         "--population", "--roll",
                                         "--step-sizes", "--air-model",
                                         "--phase-lock", "--link-axis",
                                         "--gene-range", "--control-period",
                                         "--out",        "--weights",
                                         "--resume",     "--farm",
                                         "--threads",    "--help",
                                         "__name:=w",    "--bogus",
                                         "-n",           ""};

flapsim::EvaluateEpisodes::Request mutate(Rng& rng) {
  flapsim::EvaluateEpisodes::Request req;
  req.spec = kSpec;
  req.weight_count = 12;
  const size_t tasks = 2;
  for (size_t t = 0; t < tasks * 12; ++t) req.weights.push_back(0.3 * std::sin(1.0 + t));
  req.episodes = {0, 1};
  for (int m = 1 + static_cast<int>(rng.index(3)); m > 0; --m) {
    const size_t at = rng.index(req.spec.size());
    switch (rng.index(9)) {
      case 0:  // a value, never the duration's: accepted requests stay short
        if (at < req.spec.size() - 2) req.spec[at] = kValues[rng.index(kValues.size())];
        break;
      case 1:
        if (at < req.spec.size() - 2) req.spec[at] = kFlags[rng.index(kFlags.size())];
        break;
      case 2:
        req.spec.insert(req.spec.begin() + at,
                        {kFlags[rng.index(kFlags.size())], kValues[rng.index(kValues.size())]});
        break;
      case 3:
        if (at < req.spec.size() - 2) req.spec.erase(req.spec.begin() + at);
        break;
      case 4:
        if (req.weights.empty()) break;
        req.weights[rng.index(req.weights.size())] =
            std::vector<double>{std::nan(""), std::numeric_limits<double>::infinity(), 1e308,
                                -1e308, 0.0}[rng.index(5)];
        break;
      case 5:
        req.weight_count = std::vector<std::uint32_t>{0, 1, 11, 13, 4294967295u}[rng.index(5)];
        break;
      case 6:
        if (rng.bernoulli(0.5) && !req.weights.empty()) {
          req.weights.pop_back();
        } else {
          req.weights.push_back(1.0);
        }
        break;
      case 7:
        if (req.episodes.empty()) break;
        req.episodes[rng.index(req.episodes.size())] =
            std::vector<int>{-1, 2, 1000, std::numeric_limits<int>::max(),
                             std::numeric_limits<int>::min()}[rng.index(5)];
        break;
      default:  // many tasks, or none
        if (rng.bernoulli(0.5)) {
          req.episodes.assign(1025, 0);
          req.weights.assign(1025 * 12, 0.0);
        } else {
          req.episodes.clear();
          req.weights.clear();
        }
    }
  }
  return req;
}

TEST(WorkerFuzz, EveryRequestIsAnsweredWithinTheBoundOrRefusedByName) {
  flapsim::RunnerCache cache;
  Rng rng(29);
  int answered = 0, refused = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < 3000; ++k) {
    const flapsim::EvaluateEpisodes::Request req = mutate(rng);
    const flapsim::EvaluateEpisodes::Response res = flapsim_ros::evaluateEpisodes(cache, req);
    ASSERT_LE(cache.bytes(), flapsim::kMaxRunnerCacheBytes) << k;
    if (!res.success) {
      ++refused;
      EXPECT_FALSE(res.message.empty()) << k;
      EXPECT_LT(res.message.size(), 300u) << k << ": " << res.message.substr(0, 300);
      EXPECT_TRUE(res.fitness.empty()) << k;
      continue;
    }
    ++answered;
    ASSERT_EQ(res.fitness.size(), req.episodes.size()) << k;
    const double bound = flapsim::fitnessBound(flapsim::evaluationSpecFromArgs(req.spec));
    for (double f : res.fitness) ASSERT_TRUE(std::isfinite(f) && std::abs(f) <= bound) << k;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("worker fuzz: %d answered, %d refused in %.2f s; cache %zu runners, %zu bytes\n",
              answered, refused, seconds, cache.size(), cache.bytes());
  EXPECT_GT(answered, 0);
  EXPECT_GT(refused, 0);
}

}  // namespace
