// The episode farm over ROS: flapsim_worker serves ~evaluate_episodes
// (flapsim/EvaluateEpisodes) under /flapsim_farm; FarmEvaluator (evolve
// --farm) finds those services in the master's list and spreads an
// evolution's tasks over them. The evaluation itself is the core's
// EpisodeRunner: no ROS in it.
#pragma once

#include <ros/ros.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "flapsim/EvaluateEpisodes.h"
#include "flapsim/FarmProgress.h"
#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"

namespace flapsim_ros {

/// The farm's namespace and the name of a worker's service in it.
extern const char* const kFarmNamespace;        // "/flapsim_farm"
extern const char* const kEvaluateServiceName;  // "evaluate_episodes"

/// The farm cannot finish a batch: no worker for farm_wait seconds, or a
/// worker refused a task (bad spec, malformed task), which another worker
/// would refuse too.
class FarmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ---- Worker --------------------------------------------------------------------------------

/// Runners of the specs seen recently (a worker serves one evolution at a
/// time, usually; a few are kept).
class RunnerCache {
 public:
  /// Throws flapsim::InputError for a bad spec.
  std::shared_ptr<const flapsim::EpisodeRunner> get(const std::vector<std::string>& spec);

 private:
  std::mutex mutex_;
  std::map<std::vector<std::string>, std::shared_ptr<const flapsim::EpisodeRunner>> runners_;
};

/// Answers one request: success and one fitness per task, or success=false
/// and a message naming the fault (bad spec, malformed batch, wrong weight
/// count, episode index) without evaluating anything.
flapsim::EvaluateEpisodes::Response evaluateEpisodes(RunnerCache& cache,
                                                     const flapsim::EvaluateEpisodes::Request& req);

/// flapsim_worker: ~evaluate_episodes on `~threads` threads (one request per
/// thread at a time; default: the hardware's).
class EpisodeWorkerNode {
 public:
  EpisodeWorkerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  /// Serves until shutdown.
  void run();
  const std::string& serviceName() const { return service_name_; }

 private:
  bool onEvaluate(flapsim::EvaluateEpisodes::Request& req,
                  flapsim::EvaluateEpisodes::Response& res);

  ros::NodeHandle nh_, pnh_;
  int threads_ = 1;
  RunnerCache cache_;
  ros::ServiceServer server_;
  std::string service_name_;
  std::uint64_t tasks_done_ = 0;
  std::mutex stats_mutex_;
};

// ---- evolve --farm -------------------------------------------------------------------------

struct FarmParams {
  std::string ns = "/flapsim_farm";
  double timeout = 60.0;    // s: a call unanswered by then goes to another worker
  double wait = 120.0;      // s without any worker before FarmError
  int inflight = 4;         // calls in flight per worker
  int batch = 1;            // tasks per call
  double rediscover = 1.0;  // s between looks at the master's service list
};

/// Worker services under `ns` in the master's service list (sorted), with
/// their providers' URIs.
std::map<std::string, std::string> findWorkers(const std::string& ns);

/// Sends the tasks of an evolution to the workers under params.ns, several
/// calls in flight per worker; a call that fails twice in a row (worker died)
/// or times out is sent to another worker, and workers that appear are used from the next
/// look at the master on. Results are put in task order, so the evolution is
/// the same bit for bit as in process.
class FarmEvaluator : public flapsim::EpisodeEvaluator {
 public:
  FarmEvaluator(const ros::NodeHandle& nh, const std::vector<std::string>& spec, int weight_count,
                const FarmParams& params);
  std::vector<double> evaluate(const std::vector<flapsim::EpisodeTask>& tasks) override;
  int workersUp() const override;
  /// Calls that failed or timed out and were sent again (over the run).
  int resent() const { return resent_; }
  /// Tasks answered per worker service (over the run).
  const std::map<std::string, int>& answered() const { return answered_; }

 private:
  struct Worker {
    std::string uri;
    bool dead = false;
    int inflight = 0;
  };
  void refreshWorkers();

  ros::NodeHandle nh_;
  std::vector<std::string> spec_;
  int weight_count_;
  FarmParams params_;
  std::map<std::string, Worker> workers_;
  int resent_ = 0;
  std::map<std::string, int> answered_;
};

/// Publishes FarmProgress on <ns>/progress (latched: the last line).
class ProgressPublisher {
 public:
  ProgressPublisher(ros::NodeHandle& nh, const std::string& ns);
  void publish(const flapsim::FarmProgress& msg) { pub_.publish(msg); }

 private:
  ros::Publisher pub_;
};

}  // namespace flapsim_ros
