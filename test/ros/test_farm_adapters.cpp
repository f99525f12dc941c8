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

}  // namespace
