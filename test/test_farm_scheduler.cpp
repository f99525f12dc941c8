// The farm's scheduling without ROS (flapsim/farm_scheduler.h), against fake workers: a
// healthy one answers what EpisodeRunner does; others die, answer NaN, inf, 1e308 or the
// wrong count, refuse, or never answer. The evolution stays the in-process one bit for bit,
// every bad worker is dropped and named, and every call thread is joined.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "flapsim/farm_scheduler.h"
#include "flapsim/morph_evolution.h"

namespace flapsim {
namespace {

enum class Behaviour { kHealthy, kDead, kNan, kInf, kHuge, kWrongCount, kRefuse, kSlow };

// Workers of each behaviour, a clock that advances 50 ms at every look, and the log.
class FakeFarm : public FarmLink {
 public:
  explicit FakeFarm(const EvaluationSpec& spec) : runner_(spec) {}
  void add(const std::string& name, Behaviour b) { workers_[name] = b; }
  std::map<std::string, std::string> discover() override {
    std::map<std::string, std::string> up;
    for (const auto& w : workers_) up[w.first] = "1";
    return up;
  }
  WorkerReply call(const std::string& worker, const std::vector<EpisodeTask>& tasks) override {
    ++running_;
    WorkerReply r = answer(workers_.at(worker), tasks);
    std::lock_guard<std::mutex> lock(mutex_);
    events_.push_back("a call to " + worker + " returned");
    --running_;
    return r;
  }
  double now() override { return 0.05 * ticks_++; }
  bool ok() override { return ok_; }
  void info(const std::string&) override {}
  void warn(const std::string& text) override {
    std::lock_guard<std::mutex> lock(mutex_);
    warnings_ += text + "\n";
  }
  // Lets the slow workers' calls return (undelivered, as a dead connection would).
  void release() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      released_ = true;
    }
    released_cv_.notify_all();
  }
  void note(const std::string& event) {
    std::lock_guard<std::mutex> lock(mutex_);
    events_.push_back(event);
  }

  std::atomic<bool> ok_{true};
  std::atomic<int> running_{0};
  std::atomic<bool> slow_entered_{false};
  std::string warnings_;
  std::vector<std::string> events_;

 private:
  WorkerReply answer(Behaviour b, const std::vector<EpisodeTask>& tasks) {
    WorkerReply r;
    r.delivered = b != Behaviour::kDead;
    r.success = b != Behaviour::kRefuse;
    if (b == Behaviour::kRefuse) r.message = "not today";
    if (b == Behaviour::kSlow) {
      slow_entered_ = true;
      std::unique_lock<std::mutex> lock(mutex_);
      released_cv_.wait(lock, [&] { return released_; });
      return WorkerReply{};
    }
    for (const EpisodeTask& t : tasks) {
      std::vector<double> v = runner_.values(t);  // one fitness, or a morph's two objectives
      for (double& f : v) {
        f = b == Behaviour::kNan    ? std::nan("")
            : b == Behaviour::kInf  ? std::numeric_limits<double>::infinity()
            : b == Behaviour::kHuge ? 1e308
                                    : f;
      }
      r.fitness.insert(r.fitness.end(), v.begin(), v.end());
    }
    if (b == Behaviour::kWrongCount) r.fitness.push_back(1.0);
    return r;
  }

  EpisodeRunner runner_;
  std::map<std::string, Behaviour> workers_;
  std::atomic<int> ticks_{0};
  std::mutex mutex_;
  std::condition_variable released_cv_;
  bool released_ = false;
};

EvolveParams tinyRun() {
  EvolveParams p = robustPreset();
  p.ga.population = 4;
  p.ga.generations = 2;
  p.ga.mutation_rate = 0.5;
  p.ga.seed = 3;
  p.episode.duration = 0.2;
  p.episode.episodes = 2;
  return p;
}

FarmParams fastParams() {
  FarmParams fp;
  fp.poll = 0.01;  // s of real time: a look at timeouts every 10 ms when no answer comes
  fp.wait = 2.0;   // s of the fake clock
  return fp;
}

// A tiny co-evolution selected by NSGA-II: its tasks answer two values each.
EvolveParams tinyNsga2Run() {
  EvolveParams p = morphPreset();
  p.morph.nsga2 = true;
  p.ga.population = 4;
  p.ga.generations = 1;
  p.ga.seed = 3;
  p.episode.duration = 0.5;
  p.episode.settle_time = 0.25;
  p.episode.episodes = 2;
  return p;
}

int weightCount(const EvolveParams& p) { return geneCount(p); }

void expectSameBits(const EvolveResult& a, const EvolveResult& b) {
  ASSERT_EQ(a.history.size(), b.history.size());
  for (size_t g = 0; g < a.history.size(); ++g) {
    EXPECT_EQ(a.history[g].best, b.history[g].best) << g;
    EXPECT_EQ(a.history[g].mean, b.history[g].mean) << g;
    EXPECT_EQ(a.history[g].worst, b.history[g].worst) << g;
  }
  EXPECT_EQ(a.best_weights, b.best_weights);
}

// Evolves through a healthy worker and one of `bad` behaviour; returns why `bad` was dropped.
std::string evolveBesideABadWorker(Behaviour bad, FarmParams fp = fastParams(),
                                   const EvolveParams& p = tinyRun()) {
  const EvolveResult in_process = evolveFlapController(p);
  FakeFarm link(evaluationSpec(p));
  link.add("good", Behaviour::kHealthy);
  link.add("bad", bad);
  std::string why;
  {
    FarmScheduler farm(link, evaluationSpec(p), weightCount(p), fp);
    EvolveHooks hooks;
    hooks.evaluator = &farm;
    const EvolveResult on_farm = evolveFlapController(p, hooks);
    link.release();
    expectSameBits(in_process, on_farm);
    EXPECT_EQ(farm.workersUp(), 1);
    EXPECT_EQ(farm.answered().count("bad"), 0u);
    EXPECT_GT(farm.resent(), 0);
    if (farm.dropped().count("bad")) why = farm.dropped().at("bad");
    EXPECT_EQ(farm.dropped().count("good"), 0u);
  }
  EXPECT_NE(link.warnings_.find("worker bad " + why), std::string::npos) << link.warnings_;
  return why;
}

TEST(FarmScheduler, HealthyWorkersGiveTheInProcessBits) {
  const EvolveParams p = tinyRun();
  FakeFarm link(evaluationSpec(p));
  link.add("w1", Behaviour::kHealthy);
  link.add("w2", Behaviour::kHealthy);
  FarmScheduler farm(link, evaluationSpec(p), weightCount(p), fastParams());
  EvolveHooks hooks;
  hooks.evaluator = &farm;
  expectSameBits(evolveFlapController(p), evolveFlapController(p, hooks));
  EXPECT_EQ(farm.answered().size(), 2u);
  EXPECT_TRUE(farm.dropped().empty());
  EXPECT_EQ(farm.resent(), 0);
}

TEST(FarmScheduler, AWorkerThatDiesIsDroppedAndItsTasksGoElsewhere) {
  EXPECT_EQ(evolveBesideABadWorker(Behaviour::kDead), "failed a call");
}

TEST(FarmScheduler, AWorkerAnsweringNanIsDroppedByName) {
  const std::string why = evolveBesideABadWorker(Behaviour::kNan);
  EXPECT_EQ(why.find("answered fitness nan for task"), 0u) << why;
  EXPECT_NE(why.find("not finite"), std::string::npos) << why;
}

TEST(FarmScheduler, AWorkerAnsweringInfOrBeyondTheBoundIsDropped) {
  EXPECT_NE(evolveBesideABadWorker(Behaviour::kInf).find("answered fitness inf"),
            std::string::npos);
  // The bound of tinyRun: 1 m start + 1000 m/s x 0.2 s + a 20 m flip penalty.
  EXPECT_NE(evolveBesideABadWorker(Behaviour::kHuge).find("1e+308 for task"), std::string::npos);
  EXPECT_EQ(fitnessBound(evaluationSpec(tinyRun())), 1.0 + 1000.0 * 0.2 + 20.0);
}

TEST(FarmScheduler, AWorkerAnsweringTheWrongCountIsDropped) {
  EXPECT_NE(evolveBesideABadWorker(Behaviour::kWrongCount).find("answered 2 values for 1 tasks"),
            std::string::npos);
}

// NSGA-II's tasks answer two values each (W/kg, loss): the farm takes both in task order, and
// checks each against its own bound.
TEST(FarmScheduler, TwoValuesPerTaskGiveTheInProcessBitsAndEachValueIsCheckedAgainstItsBound) {
  const EvolveParams p = tinyNsga2Run();
  ASSERT_EQ(taskValueCount(evaluationSpec(p)), 2);
  EXPECT_EQ(taskValueBounds(evaluationSpec(p)),
            (std::vector<double>{kMaxMorphPower, morphFitnessBound(evaluationSpec(p).episode)}));
  FakeFarm link(evaluationSpec(p));
  link.add("w1", Behaviour::kHealthy);
  link.add("w2", Behaviour::kHealthy);
  FarmScheduler farm(link, evaluationSpec(p), weightCount(p), fastParams());
  EvolveHooks hooks;
  hooks.evaluator = &farm;
  const EvolveResult in_process = evolveFlapController(p), on_farm = evolveFlapController(p, hooks);
  expectSameBits(in_process, on_farm);
  ASSERT_EQ(on_farm.population.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(on_farm.population[i].objectives, in_process.population[i].objectives) << i;
  }
  EXPECT_EQ(farm.answered().at("w1") + farm.answered().at("w2"), 4 * 2 + 4 * 2);  // tasks
  const std::string huge = evolveBesideABadWorker(Behaviour::kHuge, fastParams(), p);
  EXPECT_NE(huge.find("answered value 1e+308 for task"), std::string::npos) << huge;
  EXPECT_NE(huge.find("beyond the bound 10000 W/kg"), std::string::npos) << huge;
  const std::string count = evolveBesideABadWorker(Behaviour::kWrongCount, fastParams(), p);
  EXPECT_NE(count.find("answered 3 values for 1 tasks of 2 values"), std::string::npos) << count;
}

TEST(FarmScheduler, ARefusingWorkerIsDroppedAndABatchNoWorkerIsLeftForEndsAtOnce) {
  EXPECT_EQ(evolveBesideABadWorker(Behaviour::kRefuse), "refused a call: not today");
  const EvolveParams p = tinyRun();
  FakeFarm link(evaluationSpec(p));
  link.add("r1", Behaviour::kRefuse);
  link.add("r2", Behaviour::kRefuse);
  FarmScheduler farm(link, evaluationSpec(p), weightCount(p), fastParams());
  try {
    farm.evaluate({EpisodeTask{std::vector<double>(weightCount(p), 0.1), 0}});
    FAIL() << "a batch every worker refuses was evaluated";
  } catch (const FarmError& e) {
    EXPECT_NE(std::string(e.what()).find("no worker left, and worker r"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("not today"), std::string::npos) << e.what();
  }
}

TEST(FarmScheduler, AWorkerThatNeverAnswersIsTimedOut) {
  FarmParams fp = fastParams();
  fp.timeout = 0.5;  // s of the fake clock
  EXPECT_EQ(evolveBesideABadWorker(Behaviour::kSlow, fp), "did not answer within 0.5 s");
}

TEST(FarmScheduler, NoWorkerEndsTheBatchAfterTheWait) {
  const EvolveParams p = tinyRun();
  FakeFarm link(evaluationSpec(p));
  FarmScheduler farm(link, evaluationSpec(p), weightCount(p), fastParams());
  EXPECT_THROW(farm.evaluate({EpisodeTask{std::vector<double>(weightCount(p), 0.1), 0}}),
               FarmError);
}

// Shut down while a call waits for its answer: evaluate() ends with FarmError and the
// scheduler's destructor waits for the call (the link ends it, as ros::shutdown() does)
// instead of leaving its thread running.
TEST(FarmScheduler, ACallStillRunningIsJoinedBeforeTheSchedulerIsGone) {
  const EvolveParams p = tinyRun();
  FakeFarm link(evaluationSpec(p));
  link.add("slow", Behaviour::kSlow);
  auto farm =
      std::make_unique<FarmScheduler>(link, evaluationSpec(p), weightCount(p), fastParams());
  std::thread shutdown([&] {
    while (!link.slow_entered_) std::this_thread::yield();
    link.ok_ = false;
  });
  EXPECT_THROW(farm->evaluate({EpisodeTask{std::vector<double>(weightCount(p), 0.1), 0}}),
               FarmError);
  shutdown.join();
  EXPECT_EQ(link.running_, 1);  // still waiting for its answer
  std::thread release([&] { link.release(); });
  farm.reset();
  link.note("the scheduler is gone");
  release.join();
  ASSERT_EQ(link.events_.size(), 2u);
  EXPECT_EQ(link.events_[0], "a call to slow returned");
  EXPECT_EQ(link.running_, 0);
}

TEST(FarmScheduler, CallsAreCutToTheWorkersLimitAndAnEpisodeBeyondItIsRefused) {
  EvolveParams p = robustPreset();  // 20 s episodes at 0.5 ms: 40,000 steps of one pair
  FakeFarm link(evaluationSpec(p));
  FarmParams fp;
  fp.batch = 1000;
  EXPECT_EQ(FarmScheduler(link, evaluationSpec(p), weightCount(p), fp).tasksPerCall(),
            static_cast<int>(kMaxCallWork / 40000));
  fp.batch = 8;
  EXPECT_EQ(FarmScheduler(link, evaluationSpec(p), weightCount(p), fp).tasksPerCall(), 8);
  p.pairs = 12;
  p.episode.duration = 100.0;  // 200,000 steps of 12 pairs
  EXPECT_THROW(FarmScheduler(link, evaluationSpec(p), weightCount(p), fp), FarmError);
}

}  // namespace
}  // namespace flapsim
