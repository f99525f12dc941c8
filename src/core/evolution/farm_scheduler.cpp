#include "flapsim/farm_scheduler.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace flapsim {

// The state of one evaluate(): the tasks cut into chunks of tasksPerCall(), the chunks not
// yet given out, the calls in flight and the results.
struct FarmScheduler::Batch {
  const std::vector<EpisodeTask>& tasks;
  size_t per_call;
  std::vector<double> out;
  std::vector<char> done;
  std::deque<size_t> pending;
  size_t n_done = 0;
  std::map<int, Call> calls;
  double idle_since = 0.0;

  Batch(const std::vector<EpisodeTask>& t, size_t per, size_t values) : tasks(t), per_call(per) {
    const size_t chunks = (t.size() + per - 1) / per;
    out.assign(t.size() * values, 0.0);
    done.assign(chunks, 0);
    for (size_t c = 0; c < chunks; ++c) pending.push_back(c);
  }
  size_t begin(size_t chunk) const { return chunk * per_call; }
  size_t end(size_t chunk) const { return std::min(tasks.size(), (chunk + 1) * per_call); }
};

FarmScheduler::FarmScheduler(FarmLink& link, const EvaluationSpec& spec, int weight_count,
                             const FarmParams& params)
    : link_(link), spec_(spec), weight_count_(weight_count), params_(params) {
  if (params_.inflight < 1 || params_.batch < 1 || !(params_.timeout > 0.0) ||
      !(params_.wait >= 0.0) || !(params_.rediscover >= 0.0) || !(params_.poll > 0.0)) {
    throw std::invalid_argument(
        "farm: need inflight >= 1, batch >= 1, timeout > 0, wait >= 0, rediscover >= 0, poll > 0");
  }
  const double work = episodeWork(spec_);
  if (work > kMaxCallWork) {
    std::ostringstream msg;
    msg << "farm: an episode of this run is " << work << " steps x wing pairs, over a worker's "
        << "limit of " << kMaxCallWork << " per call: shorten it or evaluate in process";
    throw FarmError(msg.str());
  }
  per_call_ = std::min({params_.batch, kMaxTasksPerCall, static_cast<int>(kMaxCallWork / work)});
  values_ = static_cast<size_t>(taskValueCount(spec_));
  bounds_ = taskValueBounds(spec_);
}

FarmScheduler::~FarmScheduler() { joinAll(); }

void FarmScheduler::joinAll() {
  for (auto& [id, thread] : threads_) thread.join();
  threads_.clear();
}

int FarmScheduler::workersUp() const {
  return static_cast<int>(std::count_if(workers_.begin(), workers_.end(),
                                        [](const auto& w) { return !w.second.dropped; }));
}

void FarmScheduler::look(double now) {
  if (looked_ && now - last_look_ < params_.rediscover) return;
  looked_ = true;
  last_look_ = now;
  for (const auto& [name, identity] : link_.discover()) {
    auto it = workers_.find(name);
    if (it == workers_.end()) {
      workers_[name].identity = identity;
      link_.info("evolve: worker " + name + " joined");
    } else if (it->second.dropped && identity != it->second.identity) {
      it->second = Worker{identity, false, it->second.inflight};  // restarted
      link_.info("evolve: worker " + name + " is back");
    }
  }
}

std::vector<EpisodeTask> FarmScheduler::chunkTasks(const Batch& b, size_t chunk) const {
  std::vector<EpisodeTask> tasks(b.tasks.begin() + b.begin(chunk), b.tasks.begin() + b.end(chunk));
  for (size_t t = 0; t < tasks.size(); ++t) {
    if (static_cast<int>(tasks[t].weights.size()) != weight_count_) {
      throw FarmError("farm: task " + std::to_string(b.begin(chunk) + t) + " has " +
                      std::to_string(tasks[t].weights.size()) + " weights, not " +
                      std::to_string(weight_count_));
    }
  }
  return tasks;
}

void FarmScheduler::handOut(Batch& b, double now) {
  while (!b.pending.empty()) {
    Worker* best = nullptr;
    std::string best_name;
    for (auto& [name, w] : workers_) {  // the least loaded live worker
      if (!w.dropped && w.inflight < params_.inflight && (!best || w.inflight < best->inflight)) {
        best = &w;
        best_name = name;
      }
    }
    if (best == nullptr) return;
    const size_t chunk = b.pending.front();
    std::vector<EpisodeTask> tasks = chunkTasks(b, chunk);
    b.pending.pop_front();
    const int id = next_call_++;
    b.calls[id] = Call{chunk, best_name, now};
    ++best->inflight;
    start(id, best_name, std::move(tasks));
  }
}

void FarmScheduler::start(int id, const std::string& worker, std::vector<EpisodeTask> tasks) {
  threads_[id] = std::thread([this, id, worker, tasks = std::move(tasks)] {
    WorkerReply reply;
    try {
      reply = link_.call(worker, tasks);
    } catch (const std::exception& e) {
      reply = WorkerReply{};
      reply.message = e.what();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      replies_.emplace_back(id, std::move(reply));
    }
    replied_.notify_all();
  });
}

std::deque<std::pair<int, WorkerReply>> FarmScheduler::waitForReplies() {
  std::deque<std::pair<int, WorkerReply>> replies;
  std::unique_lock<std::mutex> lock(mutex_);
  replied_.wait_for(lock, std::chrono::duration<double>(params_.poll),
                    [&] { return !replies_.empty(); });
  replies.swap(replies_);
  return replies;
}

std::string FarmScheduler::badReply(const Batch& b, const Call& call,
                                    const WorkerReply& reply) const {
  const size_t tasks = b.end(call.chunk) - b.begin(call.chunk), expected = tasks * values_;
  if (!reply.delivered) {
    return "failed a call" + (reply.message.empty() ? "" : " (" + reply.message + ")");
  }
  if (!reply.success) return "refused a call: " + reply.message;
  if (reply.fitness.size() != expected) {
    return "answered " + std::to_string(reply.fitness.size()) + " values for " +
           std::to_string(tasks) + " tasks" +
           (values_ == 1 ? "" : " of " + std::to_string(values_) + " values");
  }
  for (size_t k = 0; k < expected; ++k) {
    const double f = reply.fitness[k], bound = bounds_[k % values_];
    if (!std::isfinite(f) || std::abs(f) > bound) {
      std::ostringstream msg;
      msg << "answered " << (values_ == 1 ? "fitness " : "value ") << f << " for task "
          << b.begin(call.chunk) + k / values_ << ", "
          << (std::isfinite(f) ? "beyond the bound " : "not finite; the bound is ") << bound
          << (values_ == 1       ? " m of an episode"
              : k % values_ == 0 ? " W/kg"
                                 : " m of loss");
      return msg.str();
    }
  }
  return "";
}

void FarmScheduler::receive(Batch& b, int id, WorkerReply reply) {
  auto thread = threads_.find(id);
  if (thread != threads_.end()) {
    thread->second.join();  // its last act was to post this reply
    threads_.erase(thread);
  }
  auto it = b.calls.find(id);
  if (it == b.calls.end()) return;  // abandoned after a timeout, or of an earlier batch
  const Call call = it->second;
  const std::string bad = badReply(b, call, reply);
  if (!bad.empty()) {
    drop(b, call.worker, bad, reply.delivered && !reply.success);
    return;
  }
  b.calls.erase(it);
  workers_[call.worker].inflight = std::max(0, workers_[call.worker].inflight - 1);
  if (b.done[call.chunk]) return;
  std::copy(reply.fitness.begin(), reply.fitness.end(),
            b.out.begin() + static_cast<long>(b.begin(call.chunk) * values_));
  b.done[call.chunk] = 1;
  ++b.n_done;
  answered_[call.worker] += static_cast<int>(reply.fitness.size() / values_);
}

void FarmScheduler::drop(Batch& b, const std::string& name, const std::string& why, bool refused) {
  Worker& w = workers_[name];
  if (!w.dropped) link_.warn("evolve: worker " + name + " " + why + "; its tasks go elsewhere");
  w.dropped = true;
  dropped_[name] = why;
  if (refused) last_refusal_ = "worker " + name + " " + why;
  for (auto it = b.calls.begin(); it != b.calls.end();) {
    if (it->second.worker != name) {
      ++it;
      continue;
    }
    if (!b.done[it->second.chunk]) b.pending.push_front(it->second.chunk);
    w.inflight = std::max(0, w.inflight - 1);
    it = b.calls.erase(it);
    ++resent_;
  }
}

void FarmScheduler::expire(Batch& b, double now) {
  std::vector<std::string> stalled;
  for (const auto& [id, call] : b.calls) {
    if (now - call.started > params_.timeout) stalled.push_back(call.worker);
  }
  std::ostringstream why;
  why << "did not answer within " << params_.timeout << " s";
  for (const auto& name : stalled) drop(b, name, why.str(), false);
}

void FarmScheduler::checkIdle(Batch& b, double now) {
  if (!b.calls.empty() || workersUp() > 0) {
    b.idle_since = now;
    return;
  }
  // No worker left and one of them refused: the batch is one workers refuse, not one that
  // waits for workers.
  if (!last_refusal_.empty()) {
    throw FarmError("farm: no worker left, and " + last_refusal_ + " (the others failed)");
  }
  if (now - b.idle_since > params_.wait) {
    std::ostringstream msg;
    msg << "farm: no flapsim_worker " << link_.where() << " for " << params_.wait << " s";
    throw FarmError(msg.str());
  }
  if (now - last_wait_warning_ >= 10.0) {
    link_.warn("evolve: waiting for workers " + link_.where());
    last_wait_warning_ = now;
  }
}

std::vector<double> FarmScheduler::evaluate(const std::vector<EpisodeTask>& tasks) {
  Batch b(tasks, static_cast<size_t>(per_call_), values_);
  for (auto& [name, w] : workers_) w.inflight = 0;  // calls of an earlier batch are not waited on
  b.idle_since = link_.now();
  last_wait_warning_ = b.idle_since;
  while (b.n_done < b.done.size()) {
    if (!link_.ok()) throw FarmError("farm: shutting down");
    const double now = link_.now();
    look(now);
    handOut(b, now);
    checkIdle(b, now);
    for (auto& [id, reply] : waitForReplies()) receive(b, id, std::move(reply));
    expire(b, link_.now());
  }
  return b.out;
}

}  // namespace flapsim
