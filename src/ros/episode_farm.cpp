#include "flapsim_ros/episode_farm.h"

#include <ros/master.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <thread>

namespace flapsim_ros {

const char* const kFarmNamespace = "/flapsim_farm";
const char* const kEvaluateServiceName = "evaluate_episodes";

// ---- Worker --------------------------------------------------------------------------------

std::shared_ptr<const flapsim::EpisodeRunner> RunnerCache::get(
    const std::vector<std::string>& spec) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = runners_.find(spec);
    if (it != runners_.end()) return it->second;
  }
  // Built outside the lock (parses a URDF); two threads may build the same one.
  auto runner =
      std::make_shared<const flapsim::EpisodeRunner>(flapsim::evaluationSpecFromArgs(spec));
  std::lock_guard<std::mutex> lock(mutex_);
  if (runners_.size() >= 4) runners_.clear();
  return runners_.emplace(spec, runner).first->second;
}

flapsim::EvaluateEpisodes::Response evaluateEpisodes(
    RunnerCache& cache, const flapsim::EvaluateEpisodes::Request& req) {
  flapsim::EvaluateEpisodes::Response res;
  res.success = false;
  std::shared_ptr<const flapsim::EpisodeRunner> runner;
  try {
    runner = cache.get(req.spec);
  } catch (const std::exception& e) {
    res.message = std::string("bad spec: ") + e.what();
    return res;
  }
  const size_t n = req.episodes.size();
  if (req.weights.size() != static_cast<size_t>(req.weight_count) * n) {
    res.message = "malformed batch: " + std::to_string(req.weights.size()) + " weights for " +
                  std::to_string(n) + " tasks of " + std::to_string(req.weight_count);
    return res;
  }
  if (static_cast<int>(req.weight_count) != runner->weightCount()) {
    res.message = "wrong weight count: tasks have " + std::to_string(req.weight_count) +
                  " weights, the controller has " + std::to_string(runner->weightCount());
    return res;
  }
  std::vector<flapsim::EpisodeTask> tasks(n);
  for (size_t i = 0; i < n; ++i) {
    tasks[i].weights.assign(req.weights.begin() + i * req.weight_count,
                            req.weights.begin() + (i + 1) * req.weight_count);
    tasks[i].episode = req.episodes[i];
    const std::string err = runner->check(tasks[i]);
    if (!err.empty()) {
      res.message = "malformed task " + std::to_string(i) + ": " + err;
      return res;
    }
  }
  try {
    for (const auto& t : tasks) res.fitness.push_back(runner->evaluate(t));
  } catch (const std::exception& e) {
    res.fitness.clear();
    res.message = std::string("episode failed: ") + e.what();
    return res;
  }
  res.success = true;
  return res;
}

EpisodeWorkerNode::EpisodeWorkerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : nh_(nh), pnh_(pnh) {
  threads_ = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  pnh_.param("threads", threads_, threads_);
  if (threads_ < 1) throw std::invalid_argument("~threads must be >= 1");
  server_ = pnh_.advertiseService(kEvaluateServiceName, &EpisodeWorkerNode::onEvaluate, this);
  service_name_ = server_.getService();
  if (service_name_.rfind(std::string(kFarmNamespace) + "/", 0) != 0) {
    ROS_WARN_STREAM("flapsim_worker: " << service_name_ << " is not under " << kFarmNamespace
                                       << ": evolve --farm will not find it (start with __ns:="
                                       << kFarmNamespace << ")");
  }
  ROS_INFO_STREAM("flapsim_worker: serving " << service_name_ << " on " << threads_
                                             << " thread(s)");
}

bool EpisodeWorkerNode::onEvaluate(flapsim::EvaluateEpisodes::Request& req,
                                   flapsim::EvaluateEpisodes::Response& res) {
  res = evaluateEpisodes(cache_, req);
  if (!res.success) {
    ROS_WARN_STREAM_THROTTLE(5.0, "flapsim_worker: refused a batch: " << res.message);
  } else {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    tasks_done_ += res.fitness.size();
  }
  return true;
}

void EpisodeWorkerNode::run() {
  ros::AsyncSpinner spinner(threads_);
  spinner.start();
  ros::waitForShutdown();
}

// ---- evolve --farm -------------------------------------------------------------------------

std::map<std::string, std::string> findWorkers(const std::string& ns) {
  std::map<std::string, std::string> out;
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  if (!ros::master::execute("getSystemState", args, result, payload, false)) return out;
  if (payload.getType() != XmlRpc::XmlRpcValue::TypeArray || payload.size() < 3) return out;
  XmlRpc::XmlRpcValue& services = payload[2];
  const std::string prefix = ns + "/";
  const std::string suffix = std::string("/") + kEvaluateServiceName;
  for (int i = 0; i < services.size(); ++i) {
    const std::string name = services[i][0];
    if (name.rfind(prefix, 0) != 0 || name.size() < suffix.size() ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    std::string uri;
    XmlRpc::XmlRpcValue call_args, call_result, call_payload;
    call_args[0] = ros::this_node::getName();
    call_args[1] = name;
    if (ros::master::execute("lookupService", call_args, call_result, call_payload, false)) {
      uri = static_cast<std::string>(call_payload);
    }
    out[name] = uri;
  }
  return out;
}

FarmEvaluator::FarmEvaluator(const ros::NodeHandle& nh, const std::vector<std::string>& spec,
                             int weight_count, const FarmParams& params)
    : nh_(nh), spec_(spec), weight_count_(weight_count), params_(params) {
  if (params_.inflight < 1 || params_.batch < 1 || !(params_.timeout > 0.0)) {
    throw std::invalid_argument("farm: need inflight >= 1, batch >= 1, timeout > 0");
  }
}

int FarmEvaluator::workersUp() const {
  return static_cast<int>(std::count_if(workers_.begin(), workers_.end(),
                                        [](const auto& w) { return !w.second.dead; }));
}

void FarmEvaluator::refreshWorkers() {
  for (const auto& [name, uri] : findWorkers(params_.ns)) {
    auto it = workers_.find(name);
    if (it == workers_.end()) {
      workers_[name].uri = uri;
      ROS_INFO_STREAM("evolve: worker " << name << " joined");
    } else if (it->second.dead && uri != it->second.uri) {
      // Restarted under the same name: a new provider.
      it->second = Worker{uri, false, it->second.inflight};
      ROS_INFO_STREAM("evolve: worker " << name << " is back");
    }
  }
}

namespace {

struct Answer {
  int call = 0;
  bool ok = false;  // the call went through (else: transport failure)
  flapsim::EvaluateEpisodes::Response response;
};

struct Mailbox {
  std::mutex mutex;
  std::condition_variable cv;
  std::deque<Answer> answers;
};

}  // namespace

std::vector<double> FarmEvaluator::evaluate(const std::vector<flapsim::EpisodeTask>& tasks) {
  const size_t n_chunks = (tasks.size() + params_.batch - 1) / params_.batch;
  std::vector<double> out(tasks.size(), 0.0);
  std::vector<char> chunk_done(n_chunks, 0);
  std::deque<size_t> pending;
  for (size_t c = 0; c < n_chunks; ++c) pending.push_back(c);
  size_t n_done = 0;

  struct Call {
    size_t chunk;
    std::string worker;
    ros::WallTime started;
  };
  std::map<int, Call> calls;
  int next_call = 0;
  auto mailbox = std::make_shared<Mailbox>();

  auto requeue = [&](int id) {
    auto it = calls.find(id);
    if (it == calls.end()) return;
    if (!chunk_done[it->second.chunk]) pending.push_front(it->second.chunk);
    auto w = workers_.find(it->second.worker);
    if (w != workers_.end()) w->second.inflight = std::max(0, w->second.inflight - 1);
    calls.erase(it);
    ++resent_;
  };
  auto bury = [&](const std::string& name, const std::string& why) {
    Worker& w = workers_[name];
    if (!w.dead)
      ROS_WARN_STREAM("evolve: worker " << name << " " << why << "; its tasks go elsewhere");
    w.dead = true;
    std::vector<int> ids;
    for (const auto& [id, call] : calls) {
      if (call.worker == name) ids.push_back(id);
    }
    for (int id : ids) requeue(id);
  };

  ros::WallTime last_look;  // zero: look now
  ros::WallTime idle_since = ros::WallTime::now();
  while (n_done < n_chunks) {
    if (!ros::ok()) throw FarmError("farm: ROS shut down");
    const ros::WallTime now = ros::WallTime::now();
    if ((now - last_look).toSec() >= params_.rediscover) {
      refreshWorkers();
      last_look = now;
    }
    // Hand out chunks to the live workers, least loaded first.
    bool started = true;
    while (!pending.empty() && started) {
      started = false;
      Worker* best = nullptr;
      std::string best_name;
      for (auto& [name, w] : workers_) {
        if (!w.dead && w.inflight < params_.inflight && (!best || w.inflight < best->inflight)) {
          best = &w;
          best_name = name;
        }
      }
      if (best == nullptr) break;
      const size_t chunk = pending.front();
      pending.pop_front();
      flapsim::EvaluateEpisodes srv;
      srv.request.spec = spec_;
      srv.request.weight_count = static_cast<std::uint32_t>(weight_count_);
      const size_t begin = chunk * params_.batch;
      const size_t end = std::min(tasks.size(), begin + params_.batch);
      for (size_t t = begin; t < end; ++t) {
        if (static_cast<int>(tasks[t].weights.size()) != weight_count_) {
          throw FarmError("farm: task " + std::to_string(t) + " has " +
                          std::to_string(tasks[t].weights.size()) + " weights, not " +
                          std::to_string(weight_count_));
        }
        srv.request.weights.insert(srv.request.weights.end(), tasks[t].weights.begin(),
                                   tasks[t].weights.end());
        srv.request.episodes.push_back(tasks[t].episode);
      }
      const int id = next_call++;
      calls[id] = Call{chunk, best_name, now};
      ++best->inflight;
      ros::NodeHandle nh = nh_;
      std::thread([mailbox, id, nh, name = best_name, srv]() mutable {
        ros::ServiceClient client = nh.serviceClient<flapsim::EvaluateEpisodes>(name);
        Answer a;
        a.call = id;
        // A call that fails is made once more before it counts: a dead worker fails again,
        // while a transient failure of the transport (the master's lookup of the service, the
        // connection) under a burst of calls does not bury a live worker. Tasks are pure, so
        // a batch computed twice gives the same values.
        a.ok = client.call(srv);
        if (!a.ok) {
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
          a.ok = client.call(srv);
        }
        a.response = std::move(srv.response);
        {
          std::lock_guard<std::mutex> lock(mailbox->mutex);
          mailbox->answers.push_back(std::move(a));
        }
        mailbox->cv.notify_all();
      }).detach();
      started = true;
    }
    if (calls.empty() && workersUp() > 0) idle_since = now;
    if (calls.empty() && workersUp() == 0) {
      if ((now - idle_since).toSec() > params_.wait) {
        throw FarmError("farm: no flapsim_worker under " + params_.ns + " for " +
                        std::to_string(params_.wait) + " s");
      }
      ROS_WARN_STREAM_THROTTLE(10.0, "evolve: waiting for workers under " << params_.ns);
    } else {
      idle_since = now;
    }

    std::deque<Answer> answers;
    {
      std::unique_lock<std::mutex> lock(mailbox->mutex);
      mailbox->cv.wait_for(lock, std::chrono::milliseconds(100),
                           [&] { return !mailbox->answers.empty(); });
      answers.swap(mailbox->answers);
    }
    for (Answer& a : answers) {
      auto it = calls.find(a.call);
      if (it == calls.end()) continue;  // abandoned after a timeout: already sent elsewhere
      const Call call = it->second;
      if (!a.ok) {
        bury(call.worker, "failed a call");
        continue;
      }
      if (!a.response.success) {
        throw FarmError("farm: worker " + call.worker + " refused a batch: " + a.response.message);
      }
      const size_t begin = call.chunk * params_.batch;
      const size_t end = std::min(tasks.size(), begin + params_.batch);
      if (a.response.fitness.size() != end - begin) {
        bury(call.worker, "answered " + std::to_string(a.response.fitness.size()) + " values for " +
                              std::to_string(end - begin) + " tasks");
        continue;
      }
      calls.erase(it);
      workers_[call.worker].inflight = std::max(0, workers_[call.worker].inflight - 1);
      if (!chunk_done[call.chunk]) {
        std::copy(a.response.fitness.begin(), a.response.fitness.end(), out.begin() + begin);
        chunk_done[call.chunk] = 1;
        ++n_done;
        answered_[call.worker] += static_cast<int>(end - begin);
      }
    }
    // Stalled workers.
    const ros::WallTime later = ros::WallTime::now();
    std::vector<std::string> stalled;
    for (const auto& [id, call] : calls) {
      if ((later - call.started).toSec() > params_.timeout) stalled.push_back(call.worker);
    }
    for (const auto& name : stalled) {
      bury(name, "did not answer within " + std::to_string(params_.timeout) + " s");
    }
  }
  return out;
}

ProgressPublisher::ProgressPublisher(ros::NodeHandle& nh, const std::string& ns) {
  pub_ = nh.advertise<flapsim::FarmProgress>(ns + "/progress", 1, /*latch=*/true);
}

}  // namespace flapsim_ros
