// The episode farm's scheduling, without ROS: which worker gets which tasks, how many calls
// each has in flight, timeouts, sending a call again elsewhere, dropping (and naming) a
// worker that fails, stalls, refuses or answers values no episode can give, and the results
// in task order. The calls go through an injected FarmLink (the ROS service calls in
// flapsim_ros, fakes in the tests); each runs on a thread of the scheduler's, and every one
// is joined before the scheduler is gone. ROS-free; time comes from the link.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "flapsim/episode_evaluator.h"

namespace flapsim {

/// The farm cannot finish a batch: no worker for `wait` seconds, no worker left after one
/// refused it, or the process shuts down.
class FarmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a worker answered to one call.
struct WorkerReply {
  bool delivered = false;  // the call went through (else the transport failed: worker gone?)
  bool success = false;    // the worker evaluated the tasks (else it refused: `message`)
  std::string message;
  std::vector<double> fitness;  // taskValueCount(spec) values per task, in task order
};

/// The farm's access to its workers, to time and to the log.
class FarmLink {
 public:
  virtual ~FarmLink() = default;
  /// The workers up now: name -> identity (a worker restarted under its name has a new one).
  virtual std::map<std::string, std::string> discover() = 0;
  /// Evaluates `tasks` on `worker`: blocks until it answers or the call fails. Called from
  /// the scheduler's threads, several at a time.
  virtual WorkerReply call(const std::string& worker, const std::vector<EpisodeTask>& tasks) = 0;
  /// Seconds on a monotonic clock.
  virtual double now() = 0;
  /// False once the process shuts down: evaluate() stops with FarmError.
  virtual bool ok() { return true; }
  virtual void info(const std::string& text) = 0;
  virtual void warn(const std::string& text) = 0;
  /// Where the workers are looked for, for messages ("under /flapsim_farm").
  virtual std::string where() const { return ""; }
};

struct FarmParams {
  double timeout = 60.0;    // s: a call unanswered by then goes to another worker
  double wait = 120.0;      // s without any worker before FarmError
  int inflight = 4;         // calls in flight per worker
  int batch = 1;            // tasks per call (fewer if kMaxCallWork needs it)
  double rediscover = 1.0;  // s between looks for workers
  double poll = 0.1;        // s: longest wait for an answer before timeouts are looked at
};

/// Spreads the tasks of an evolution over the workers of `link`: calls of up to
/// tasksPerCall() tasks, at most params.inflight in flight per worker, the least loaded
/// first. A worker whose call fails, times out, is refused, or answers a wrong count or a
/// value that is not finite or beyond its taskValueBounds(spec) is dropped for the run (named in
/// a warning and in dropped()) and its calls go to the others; one that comes back under a
/// new identity is used again. With no worker left, the batch ends (FarmError) at once if
/// one of them refused it, else after params.wait s without a worker. Results are put in task
/// order, so the evolution is the in-process one bit for bit.
class FarmScheduler : public EpisodeEvaluator {
 public:
  /// Throws FarmError if an episode of `spec` alone is over kMaxCallWork, std::invalid_argument
  /// for bad params.
  FarmScheduler(FarmLink& link, const EvaluationSpec& spec, int weight_count,
                const FarmParams& params);
  /// Joins every call thread: waits for the calls still running (the link must end them).
  ~FarmScheduler() override;
  FarmScheduler(const FarmScheduler&) = delete;
  FarmScheduler& operator=(const FarmScheduler&) = delete;

  std::vector<double> evaluate(const std::vector<EpisodeTask>& tasks) override;
  int workersUp() const override;
  /// Tasks per call: params.batch, fewer if kMaxCallWork or kMaxTasksPerCall needs it.
  int tasksPerCall() const { return per_call_; }
  /// Calls sent again after a failure, timeout, refusal or bad answer (over the run).
  int resent() const { return resent_; }
  /// Tasks answered per worker (over the run).
  const std::map<std::string, int>& answered() const { return answered_; }
  /// Workers dropped, with why (over the run; the last reason of each).
  const std::map<std::string, std::string>& dropped() const { return dropped_; }

 private:
  struct Worker {
    std::string identity;
    bool dropped = false;
    int inflight = 0;
  };
  struct Call {
    size_t chunk = 0;
    std::string worker;
    double started = 0.0;
  };
  struct Batch;

  void look(double now);
  void handOut(Batch& b, double now);
  std::vector<EpisodeTask> chunkTasks(const Batch& b, size_t chunk) const;
  void start(int id, const std::string& worker, std::vector<EpisodeTask> tasks);
  void receive(Batch& b, int id, WorkerReply reply);
  std::string badReply(const Batch& b, const Call& call, const WorkerReply& reply) const;
  void drop(Batch& b, const std::string& worker, const std::string& why, bool refused);
  void expire(Batch& b, double now);
  void checkIdle(Batch& b, double now);
  std::deque<std::pair<int, WorkerReply>> waitForReplies();
  void joinAll();

  FarmLink& link_;
  EvaluationSpec spec_;
  int weight_count_;
  FarmParams params_;
  int per_call_ = 1;
  size_t values_ = 1;           // per task: taskValueCount(spec)
  std::vector<double> bounds_;  // taskValueBounds(spec)
  std::map<std::string, Worker> workers_;
  int resent_ = 0;
  std::map<std::string, int> answered_;
  std::map<std::string, std::string> dropped_;
  std::string last_refusal_;
  double last_look_ = 0.0;
  bool looked_ = false;
  double last_wait_warning_ = 0.0;
  int next_call_ = 0;

  std::mutex mutex_;  // guards replies_
  std::condition_variable replied_;
  std::deque<std::pair<int, WorkerReply>> replies_;
  std::map<int, std::thread> threads_;  // one per call still to be joined
};

}  // namespace flapsim
