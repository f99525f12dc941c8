// The episode farm over ROS: flapsim_worker serves ~evaluate_episodes
// (flapsim/EvaluateEpisodes) under /flapsim_farm; FarmEvaluator (evolve
// --farm) finds those services in the master's list and spreads an
// evolution's tasks over them. The evaluation itself is the core's
// EpisodeRunner: no ROS in it.
#pragma once

#include <ros/ros.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "flapsim/EvaluateEpisodes.h"
#include "flapsim/FarmProgress.h"
#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/farm_scheduler.h"

namespace flapsim_ros {

/// The farm's namespace and the name of a worker's service in it.
extern const char* const kFarmNamespace;        // "/flapsim_farm"
extern const char* const kEvaluateServiceName;  // "evaluate_episodes"

using flapsim::FarmError;

// ---- Worker --------------------------------------------------------------------------------

/// Empty if a batch of `tasks` tasks of `weight_count` weights, `weights` in all, is within
/// kMaxTasksPerCall and well formed, else why not.
std::string batchFault(std::size_t tasks, std::size_t weights, std::uint32_t weight_count);

/// Answers one request: success and one fitness per task, or success=false and a message
/// naming the fault without evaluating anything: too many tasks (kMaxTasksPerCall), a bad
/// spec (flapsim::checkSpecArgs), a malformed batch, a wrong weight count, too much work
/// (kMaxCallWork), an episode index out of range or a non-finite weight.
flapsim::EvaluateEpisodes::Response evaluateEpisodes(flapsim::RunnerCache& cache,
                                                     const flapsim::EvaluateEpisodes::Request& req);

/// flapsim_worker: ~evaluate_episodes on `~threads` threads (one request per
/// thread at a time; default: the hardware's). A request over the limits of a batch is
/// refused from its serialized bytes, before its arrays are copied.
class EpisodeWorkerNode {
 public:
  EpisodeWorkerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  /// Serves until shutdown.
  void run();
  const std::string& serviceName() const { return service_name_; }

 private:
  /// Answers `req` (null: refused from its bytes, `res` holds why) and logs a refusal.
  void answer(const flapsim::EvaluateEpisodes::Request* req,
              flapsim::EvaluateEpisodes::Response& res);

  ros::NodeHandle nh_, pnh_;
  int threads_ = 1;
  flapsim::RunnerCache cache_;
  ros::ServiceServer server_;
  std::string service_name_;
  std::uint64_t tasks_done_ = 0;
  std::mutex stats_mutex_;
};

// ---- evolve --farm -------------------------------------------------------------------------

struct FarmParams : flapsim::FarmParams {
  std::string ns = "/flapsim_farm";
};

/// Worker services under `ns` in the master's service list (sorted), with
/// their providers' URIs.
std::map<std::string, std::string> findWorkers(const std::string& ns);

/// evolve --farm: a flapsim::FarmScheduler over the flapsim_worker services under params.ns.
/// A call that fails is made once more, 50 ms later, before it counts as failed (a dead
/// worker fails again; a transient failure of the transport does not bury a live one).
/// Before it is destroyed, ros::shutdown() ends the calls still waiting for an answer.
class FarmEvaluator : public flapsim::EpisodeEvaluator {
 public:
  /// Throws flapsim::InputError for a bad spec, FarmError for an episode over a worker's
  /// limit per call.
  FarmEvaluator(const ros::NodeHandle& nh, const std::vector<std::string>& spec, int weight_count,
                const FarmParams& params);
  std::vector<double> evaluate(const std::vector<flapsim::EpisodeTask>& tasks) override {
    return scheduler_.evaluate(tasks);
  }
  int workersUp() const override { return scheduler_.workersUp(); }
  int resent() const { return scheduler_.resent(); }
  const std::map<std::string, int>& answered() const { return scheduler_.answered(); }
  const std::map<std::string, std::string>& dropped() const { return scheduler_.dropped(); }
  int tasksPerCall() const { return scheduler_.tasksPerCall(); }

 private:
  class Link : public flapsim::FarmLink {
   public:
    Link(const ros::NodeHandle& nh, const std::vector<std::string>& spec, int weight_count,
         const std::string& ns)
        : nh_(nh), spec_(spec), weight_count_(weight_count), ns_(ns) {}
    std::map<std::string, std::string> discover() override { return findWorkers(ns_); }
    flapsim::WorkerReply call(const std::string& worker,
                              const std::vector<flapsim::EpisodeTask>& tasks) override;
    double now() override { return ros::WallTime::now().toSec(); }
    bool ok() override { return ros::ok(); }
    void info(const std::string& text) override { ROS_INFO_STREAM(text); }
    void warn(const std::string& text) override { ROS_WARN_STREAM(text); }
    std::string where() const override { return "under " + ns_; }

   private:
    ros::NodeHandle nh_;
    std::vector<std::string> spec_;
    int weight_count_;
    std::string ns_;
  };
  Link link_;  // before scheduler_: it outlives the scheduler's call threads
  flapsim::FarmScheduler scheduler_;
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
