// flapsim_worker's answer to a request, without a master: one fitness per task, the
// EpisodeRunner's, or a refusal naming the fault.
#include <gtest/gtest.h>

#include "flapsim_ros/episode_farm.h"

namespace {

const std::vector<std::string> kSpec = {"--preset",   "paper", "--episodes", "2",
                                        "--duration", "0.4",   "--seed",     "4"};

flapsim::EvaluateEpisodes::Request request(int weight_count, std::vector<int> episodes) {
  flapsim::EvaluateEpisodes::Request req;
  req.spec = kSpec;
  req.weight_count = weight_count;
  for (size_t t = 0; t < episodes.size(); ++t) {
    for (int w = 0; w < weight_count; ++w) req.weights.push_back(0.1 * w - 0.3 * t);
  }
  req.episodes = episodes;
  return req;
}

TEST(Worker, ABatchGetsTheRunnersFitnessPerTaskInOrder) {
  flapsim::RunnerCache cache;
  const flapsim::EpisodeRunner runner(flapsim::evaluationSpecFromArgs(kSpec));
  const int n = runner.weightCount();
  const auto req = request(n, {1, 0, 1});
  const auto res = flapsim_ros::evaluateEpisodes(cache, req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.fitness.size(), 3u);
  for (size_t t = 0; t < 3; ++t) {
    const std::vector<double> w(req.weights.begin() + t * n, req.weights.begin() + (t + 1) * n);
    EXPECT_EQ(res.fitness[t], runner.evaluate(flapsim::EpisodeTask{w, req.episodes[t]})) << t;
  }
  EXPECT_NE(res.fitness[0], res.fitness[2]);  // other weights, same episode
}

TEST(Worker, BadRequestsAreRefusedNamingTheFault) {
  flapsim::RunnerCache cache;
  const int n = flapsim::EpisodeRunner(flapsim::evaluationSpecFromArgs(kSpec)).weightCount();
  auto expectRefused = [&](const flapsim::EvaluateEpisodes::Request& req, const std::string& why) {
    const auto res = flapsim_ros::evaluateEpisodes(cache, req);
    EXPECT_FALSE(res.success);
    EXPECT_TRUE(res.fitness.empty());
    EXPECT_NE(res.message.find(why), std::string::npos) << res.message;
  };
  auto bad_spec = request(n, {0});
  bad_spec.spec = {"--preset", "fast"};
  expectRefused(bad_spec, "bad spec: --preset: 'fast' is not one of robust, paper");
  auto short_batch = request(n, {0, 1});
  short_batch.weights.pop_back();
  expectRefused(short_batch, "malformed batch");
  expectRefused(request(n + 1, {0}), "wrong weight count");
  expectRefused(request(n, {0, 2}), "malformed task 1: episode 2 is not in [0, 2)");
}

// The reliability campaign's calls (issue 27, cases 1, 2 and 5): each refused by name before
// any episode is flown, nothing built for a refused spec.
TEST(Worker, TheCampaignsCallsAreRefusedBeforeAnyWork) {
  flapsim::RunnerCache cache;
  auto call = [&](std::vector<std::string> spec, size_t tasks, int episode = 0) {
    flapsim::EvaluateEpisodes::Request req;
    req.spec = std::move(spec);
    req.weight_count = 33;  // the robust preset's network
    req.weights.assign(33 * tasks, 0.0);
    req.episodes.assign(tasks, episode);
    return flapsim_ros::evaluateEpisodes(cache, req);
  };
  auto expectRefused = [&](const flapsim::EvaluateEpisodes::Response& res, const std::string& why) {
    EXPECT_FALSE(res.success);
    EXPECT_EQ(res.message.find(why), 0u) << res.message;
  };
  // 1: a spec of 10^7 episodes (860 MB of starts, kept in the cache).
  expectRefused(call({"--preset", "robust", "--episodes", "10000000"}, 1, -1),
                "bad spec: --episodes: 10000000 is not in [1, 1000]");
  // 2: 833,333 tasks in one call; 2e7 steps an episode; 4.3e7 s; 3,000 wing pairs.
  expectRefused(call({"--preset", "robust"}, 833333), "too many tasks: 833333, over the limit");
  expectRefused(call({"--preset", "robust", "--step-sizes", "0.000001"}, 1),
                "bad spec: evolve: duration / step size = 2e+07 steps, over the limit of 1e+07");
  expectRefused(call({"--preset", "robust", "--duration", "4.3e7"}, 1),
                "bad spec: --duration: 4.3e7 is not in (0, 10000]");
  expectRefused(call({"--preset", "robust", "--pairs", "3000"}, 1),
                "bad spec: --pairs: 3000 is not in [1, 64]");
  // Within every limit of a spec, but 1024 robust episodes of 10,000 steps in one call (20 s
  // at the smaller of the unit's accurate step sizes, 4 and 2 ms).
  expectRefused(call({"--preset", "robust"}, 1024),
                "too much work: 1024 tasks of 10000 steps x wing pairs, over the limit of 2e+06");
  // 5: 10^9 s episodes, whose sample count overflowed an int (fitness 0).
  expectRefused(call({"--preset", "robust", "--duration", "1e9"}, 1),
                "bad spec: --duration: 1e9 is not in (0, 10000]");
  // A 16 MiB argument: refused without echoing it.
  const auto huge = call({"--preset", std::string(16 << 20, 'r')}, 1);
  expectRefused(huge, "bad spec: spec: 2 arguments of 16777224 bytes, over the limit");
  EXPECT_LT(huge.message.size(), 200u);
  // Only the valid robust spec's runner was built (a few kB); none of the refused specs'.
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_LT(cache.bytes(), 16u << 10);
}

TEST(Worker, TheRunnerCacheIsBoundedInBytes) {
  const auto spec = [](int seed) {
    return std::vector<std::string>{"--preset", "robust", "--episodes",
                                    "1000",     "--seed", std::to_string(seed)};
  };
  flapsim::RunnerCache probe;
  const size_t one = probe.get(spec(0)) ? probe.bytes() : 0;
  ASSERT_GT(one, 1000u * sizeof(flapsim::EpisodeStart));  // the starts are counted
  flapsim::RunnerCache cache(3 * one);
  for (int seed = 0; seed < 10; ++seed) {
    const auto runner = cache.get(spec(seed));
    EXPECT_EQ(runner->spec().episode.episodes, 1000);
    EXPECT_LE(cache.bytes(), 3 * one);
  }
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_EQ(cache.bytes(), 3 * one);
  // The most recently used stay: seed 9's runner is the one cached.
  EXPECT_EQ(cache.get(spec(9)), cache.get(spec(9)));
}

}  // namespace
