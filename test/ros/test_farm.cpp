// evolve --farm against flapsim_worker nodes (farm.test starts three under
// /flapsim_farm): the evolution is the in-process one bit for bit, with three workers,
// with one killed mid-run and another joining, with one that never answers; a malformed
// batch is refused by name.
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <signal.h>
#include <sys/wait.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

#include "flapsim/evolve_args.h"
#include "flapsim/morph_evolution.h"
#include "flapsim_ros/episode_farm.h"
#include "start_worker.h"
#include "wait_for.h"

namespace {

using flapsim_test::waitFor;

const std::vector<std::string> kSpec = {"--preset",      "robust", "--population", "4",
                                        "--generations", "3",      "--episodes",   "2",
                                        "--duration",    "1",      "--seed",       "11"};
const std::string kNs = "/flapsim_farm";

std::string service(const std::string& worker) { return kNs + "/" + worker + "/evaluate_episodes"; }

bool listed(const std::string& name) { return flapsim_ros::findWorkers(kNs).count(name) > 0; }

void expectSameBits(const flapsim::EvolveResult& a, const flapsim::EvolveResult& b) {
  ASSERT_EQ(a.history.size(), b.history.size());
  for (size_t g = 0; g < a.history.size(); ++g) {
    EXPECT_EQ(a.history[g].best, b.history[g].best) << g;
    EXPECT_EQ(a.history[g].mean, b.history[g].mean) << g;
    EXPECT_EQ(a.history[g].worst, b.history[g].worst) << g;
    EXPECT_EQ(a.history[g].best_genes, b.history[g].best_genes) << g;
  }
  EXPECT_EQ(a.best_weights, b.best_weights);
}

TEST(Farm, ThreeWorkersGiveTheInProcessBits) {
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return flapsim_ros::findWorkers(kNs).size() >= 3; }, 30.0));
  flapsim::EvolveParams p = flapsim::parseEvolveArgs(kSpec).params;
  p.ga.threads = 2;
  const flapsim::EvolveResult in_process = flapsim::evolveFlapController(p);
  flapsim_ros::FarmEvaluator farm(nh, kSpec, flapsim::FlapUnitController::weightCount(p.controller),
                                  flapsim_ros::FarmParams());
  flapsim::EvolveHooks hooks;
  hooks.evaluator = &farm;
  const flapsim::EvolveResult on_farm = flapsim::evolveFlapController(p, hooks);
  expectSameBits(in_process, on_farm);
  EXPECT_EQ(farm.workersUp(), 3);
  EXPECT_EQ(farm.answered().size(), 3u);  // every worker took part
  EXPECT_EQ(farm.resent(), 0);
}

// The evolution of `spec` (2 threads) in process and on the farm's three workers, both results
// and the calls the farm sent again.
struct FarmAndProcess {
  flapsim::EvolveResult in_process, on_farm;
  int resent = 0;
};
FarmAndProcess evolveBothWays(ros::NodeHandle& nh, const std::vector<std::string>& spec) {
  FarmAndProcess r;
  flapsim::EvolveParams p = flapsim::parseEvolveArgs(spec).params;
  p.ga.threads = 2;
  r.in_process = flapsim::evolveFlapController(p);
  flapsim_ros::FarmEvaluator farm(nh, spec, flapsim::geneCount(p), flapsim_ros::FarmParams());
  flapsim::EvolveHooks hooks;
  hooks.evaluator = &farm;
  r.on_farm = flapsim::evolveFlapController(p, hooks);
  r.resent = farm.resent();
  return r;
}

// evolve --episode-sets 3 (the sets travel in the spec's flags): the workers draw the three
// sets of two episodes and fly generation g's (episodes 2 (g mod 3) and 2 (g mod 3) + 1; a
// worker that drew only two would refuse episode 2 by name) as the process does, bit for bit.
TEST(Farm, EpisodeSetsOnThreeWorkersGiveTheInProcessBits) {
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return flapsim_ros::findWorkers(kNs).size() >= 3; }, 30.0));
  std::vector<std::string> spec = kSpec;
  spec.insert(spec.end(), {"--episode-sets", "3"});
  ASSERT_EQ(flapsim::parseEvolveArgs(spec).params.episode_sets, 3);
  const FarmAndProcess r = evolveBothWays(nh, spec);
  expectSameBits(r.in_process, r.on_farm);
  EXPECT_EQ(r.resent, 0);
}

// The hover controller's evolution (--preset hover: the kind travels in the spec's flags):
// the workers fly its gains as the process does, bit for bit.
TEST(Farm, AHoverEvolutionOnThreeWorkersGivesTheInProcessBits) {
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return flapsim_ros::findWorkers(kNs).size() >= 3; }, 30.0));
  const std::vector<std::string> spec = {
      "--preset",   "hover", "--population", "3",   "--generations", "1", "--episodes", "2",
      "--duration", "1",     "--settle",     "0.5", "--seed",        "5"};
  ASSERT_EQ(flapsim::parseEvolveArgs(spec).params.kind, flapsim::EvolveKind::kHover);
  const FarmAndProcess r = evolveBothWays(nh, spec);
  expectSameBits(r.in_process, r.on_farm);
  EXPECT_EQ(r.on_farm.best_weights.size(), 16u);
  EXPECT_EQ(r.resent, 0);
}

// The body and controller co-evolved (--preset morph: the kind, the mass budget and real air
// travel in the spec's flags): the workers build each genome's body and fly it in real air,
// its impulses sized to that body, as the process does, bit for bit, and the last population
// is the same, so the Pareto front the tool writes from it is the same too.
// The last populations of both ways the same to the bit: genes, fitness and objectives.
void expectSamePopulation(const FarmAndProcess& r) {
  ASSERT_EQ(r.on_farm.population.size(), r.in_process.population.size());
  for (size_t i = 0; i < r.on_farm.population.size(); ++i) {
    EXPECT_EQ(r.on_farm.population[i].genes, r.in_process.population[i].genes) << i;
    EXPECT_EQ(r.on_farm.population[i].fitness, r.in_process.population[i].fitness) << i;
    EXPECT_EQ(r.on_farm.population[i].objectives, r.in_process.population[i].objectives) << i;
  }
}

// A tiny co-evolution's flags on 1000 W/kg motors, with `more`.
std::vector<std::string> morphSpec(const std::vector<std::string>& more) {
  std::vector<std::string> spec = {"--preset",
                                   "morph",
                                   "--population",
                                   "4",
                                   "--episodes",
                                   "2",
                                   "--duration",
                                   "1",
                                   "--settle",
                                   "0.5",
                                   "--seed",
                                   "5",
                                   "--motor-specific-power",
                                   "1000"};
  spec.insert(spec.end(), more.begin(), more.end());
  return spec;
}

TEST(Farm, AMorphEvolutionOnThreeWorkersGivesTheInProcessBits) {
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return flapsim_ros::findWorkers(kNs).size() >= 3; }, 30.0));
  const std::vector<std::string> spec =
      morphSpec({"--generations", "1", "--payload", "0.006", "--real-air"});
  const flapsim::EvolveParams p = flapsim::parseEvolveArgs(spec).params;
  ASSERT_EQ(p.kind, flapsim::EvolveKind::kMorph);
  ASSERT_EQ(p.morph.budget.motor_specific_power, 1000.0);
  ASSERT_TRUE(p.episode.real_air);
  const FarmAndProcess r = evolveBothWays(nh, spec);
  expectSameBits(r.in_process, r.on_farm);
  EXPECT_EQ(r.on_farm.best_weights.size(), 25u);
  expectSamePopulation(r);
  EXPECT_EQ(r.resent, 0);
}

TEST(Farm, AnNsga2MorphEvolutionOnThreeWorkersGivesTheInProcessFrontsBits) {
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return flapsim_ros::findWorkers(kNs).size() >= 3; }, 30.0));
  const std::vector<std::string> spec = morphSpec({"--selection", "nsga2", "--generations", "2"});
  const flapsim::EvolveParams p = flapsim::parseEvolveArgs(spec).params;
  ASSERT_TRUE(p.morph.nsga2);
  const FarmAndProcess r = evolveBothWays(nh, spec);
  expectSameBits(r.in_process, r.on_farm);
  expectSamePopulation(r);
  // Two objectives per individual came back through the service: the W/kg of a flight (0 for
  // one that flips before its settling time, as a 51 g body does here), and a loss, the fitness
  // their combination at the spec's power weight.
  int flew = 0;
  for (const flapsim::Individual& ind : r.on_farm.population) {
    ASSERT_EQ(ind.objectives.size(), 2u);
    EXPECT_GE(ind.objectives[0], 0.0);
    flew += ind.objectives[0] > 0.0;
    EXPECT_LT(ind.objectives[0], flapsim::kMaxMorphPower);
    EXPECT_EQ(ind.fitness, flapsim::morphObjectivesFitness(ind.objectives, p.morph.power_weight));
  }
  EXPECT_GT(flew, 0);
  EXPECT_EQ(r.resent, 0);
}

TEST(Farm, AWorkerKilledMidRunAndOneJoiningGiveTheSameBits) {
  ros::NodeHandle nh;
  const flapsim::EvolveParams p = flapsim::parseEvolveArgs(kSpec).params;
  const flapsim::EvolveResult in_process = flapsim::evolveFlapController(p);

  const pid_t victim = startWorker(kNs, "victim");
  ASSERT_GT(victim, 0);
  ASSERT_TRUE(waitFor([] { return listed(service("victim")); }, 30.0));
  flapsim_ros::FarmParams fp;
  fp.rediscover = 0.0;  // look at the master before every hand-out
  flapsim_ros::FarmEvaluator farm(nh, kSpec, flapsim::FlapUnitController::weightCount(p.controller),
                                  fp);
  pid_t newcomer = -1;
  flapsim::EvolveHooks hooks;
  hooks.evaluator = &farm;
  hooks.on_generation = [&](const flapsim::GenerationStats& g) {
    if (g.generation != 1) return;
    // Killed without a word: the master still lists its service.
    kill(victim, SIGKILL);
    waitpid(victim, nullptr, 0);
    newcomer = startWorker(kNs, "newcomer");
    ASSERT_TRUE(waitFor([] { return listed(service("newcomer")); }, 30.0));
  };
  const flapsim::EvolveResult on_farm = flapsim::evolveFlapController(p, hooks);
  if (newcomer > 0) {
    kill(newcomer, SIGTERM);
    waitpid(newcomer, nullptr, 0);
  }
  expectSameBits(in_process, on_farm);
  ASSERT_EQ(farm.answered().count(service("victim")), 1u);  // it worked before it died
  EXPECT_GT(farm.resent(), 0);                              // its calls were sent again
  EXPECT_GT(farm.answered().count(service("newcomer")), 0u);
  EXPECT_EQ(farm.workersUp(), 4);  // the three and the newcomer
}

TEST(Farm, AMalformedBatchIsRefusedByName) {
  ros::NodeHandle nh;
  ASSERT_TRUE(waitFor([] { return listed(service("worker_1")); }, 30.0));
  ros::ServiceClient client = nh.serviceClient<flapsim::EvaluateEpisodes>(service("worker_1"));
  flapsim::EvaluateEpisodes srv;
  srv.request.spec = kSpec;
  srv.request.weight_count = 3;
  srv.request.weights = {1.0, 2.0, 3.0};
  srv.request.episodes = {0};
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("wrong weight count"), std::string::npos)
      << srv.response.message;
  EXPECT_TRUE(srv.response.fitness.empty());
  // Refused from the request's bytes, before its arrays are copied (issue 27: 1e7 weights).
  srv.request.weight_count = 12;
  srv.request.weights.assign(12 * 1025, 0.0);
  srv.request.episodes.assign(1025, 0);
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_EQ(srv.response.message, "too many tasks: 1025, over the limit of 1024 per call");
  srv.request.weights.pop_back();
  srv.request.episodes.assign(2, 0);
  ASSERT_TRUE(client.call(srv));
  EXPECT_EQ(srv.response.message, "malformed batch: 12299 weights for 2 tasks of 12");
  // A hover task: 16 genes, each within +-1.
  srv.request.spec = {"--preset", "hover", "--duration", "1", "--settle", "0.5"};
  srv.request.weight_count = 13;
  srv.request.weights.assign(13, 0.0);
  srv.request.episodes = {0};
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("13 weights, the controller has 16"), std::string::npos)
      << srv.response.message;
  srv.request.weight_count = 16;
  srv.request.weights.assign(16, 0.0);
  srv.request.weights[3] = 2.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("gene 3 (height_gain) is not a number in [-1, 1]"),
            std::string::npos)
      << srv.response.message;
  srv.request.spec = {"--preset", "hover", "--hidden", "4"};
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("--hidden: not a flag of --preset hover"), std::string::npos)
      << srv.response.message;
  // Through the farm: a batch that every worker refuses ends the run.
  flapsim_ros::FarmEvaluator farm(nh, kSpec, 3, flapsim_ros::FarmParams());
  EXPECT_THROW(farm.evaluate({flapsim::EpisodeTask{{1.0, 2.0, 3.0}, 0}}), flapsim_ros::FarmError);
}

// A worker that takes calls and never answers until released: its calls time out and go
// to the others; it is dropped.
TEST(Farm, AWorkerThatStallsIsTimedOutAndTheBitsStayTheSame) {
  ros::NodeHandle nh;
  ros::CallbackQueue queue;
  ros::NodeHandle stall_nh(kNs + "/a_staller");
  stall_nh.setCallbackQueue(&queue);
  std::mutex mutex;
  std::condition_variable released_cv;
  bool released = false;
  std::atomic<int> calls{0};
  ros::ServiceServer staller = stall_nh.advertiseService<flapsim::EvaluateEpisodes::Request,
                                                         flapsim::EvaluateEpisodes::Response>(
      "evaluate_episodes",
      [&](flapsim::EvaluateEpisodes::Request&, flapsim::EvaluateEpisodes::Response& res) {
        ++calls;
        std::unique_lock<std::mutex> lock(mutex);
        released_cv.wait(lock, [&] { return released; });
        res.success = false;
        res.message = "released";
        return true;
      });
  ros::AsyncSpinner spinner(2, &queue);
  spinner.start();
  ASSERT_TRUE(waitFor([] { return listed(service("a_staller")); }, 30.0));

  const flapsim::EvolveParams p = flapsim::parseEvolveArgs(kSpec).params;
  const flapsim::EvolveResult in_process = flapsim::evolveFlapController(p);
  flapsim_ros::FarmParams fp;
  fp.timeout = 2.0;  // the others answer a one-task call in about 10 ms
  flapsim_ros::FarmEvaluator farm(nh, kSpec, flapsim::FlapUnitController::weightCount(p.controller),
                                  fp);
  flapsim::EvolveHooks hooks;
  hooks.evaluator = &farm;
  const flapsim::EvolveResult on_farm = flapsim::evolveFlapController(p, hooks);
  {
    std::lock_guard<std::mutex> lock(mutex);
    released = true;
  }
  released_cv.notify_all();
  spinner.stop();
  expectSameBits(in_process, on_farm);
  EXPECT_GT(calls.load(), 0);                                  // it was given work
  EXPECT_EQ(farm.answered().count(service("a_staller")), 0u);  // and answered none
  EXPECT_GT(farm.resent(), 0);
  EXPECT_EQ(farm.workersUp(), 3);  // the launch file's three; the staller was dropped
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_farm");
  return RUN_ALL_TESTS();
}
