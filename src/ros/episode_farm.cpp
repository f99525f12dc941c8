#include "flapsim_ros/episode_farm.h"

#include <malloc.h>
#include <ros/master.h>
#include <ros/service_callback_helper.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <functional>
#include <sstream>
#include <thread>

namespace flapsim_ros {

const char* const kFarmNamespace = "/flapsim_farm";
const char* const kEvaluateServiceName = "evaluate_episodes";

// ---- Worker --------------------------------------------------------------------------------

namespace {

// The tasks of a request, or a message naming why it is refused (before any evaluation).
std::string requestTasks(const flapsim::EpisodeRunner& runner,
                         const flapsim::EvaluateEpisodes::Request& req,
                         std::vector<flapsim::EpisodeTask>& tasks) {
  const size_t n = req.episodes.size();
  if (static_cast<int>(req.weight_count) != runner.weightCount()) {
    return "wrong weight count: tasks have " + std::to_string(req.weight_count) +
           " weights, the controller has " + std::to_string(runner.weightCount());
  }
  const double work = static_cast<double>(n) * flapsim::episodeWork(runner.spec());
  if (work > flapsim::kMaxCallWork) {
    std::ostringstream msg;
    msg << "too much work: " << n << " tasks of " << flapsim::episodeWork(runner.spec())
        << " steps x wing pairs, over the limit of " << flapsim::kMaxCallWork << " per call";
    return msg.str();
  }
  tasks.resize(n);
  for (size_t i = 0; i < n; ++i) {
    tasks[i].weights.assign(req.weights.begin() + i * req.weight_count,
                            req.weights.begin() + (i + 1) * req.weight_count);
    tasks[i].episode = req.episodes[i];
    const std::string err = runner.check(tasks[i]);
    if (!err.empty()) return "malformed task " + std::to_string(i) + ": " + err;
  }
  return "";
}

}  // namespace

std::string batchFault(std::size_t tasks, std::size_t weights, std::uint32_t weight_count) {
  if (tasks > static_cast<size_t>(flapsim::kMaxTasksPerCall)) {
    return "too many tasks: " + std::to_string(tasks) + ", over the limit of " +
           std::to_string(flapsim::kMaxTasksPerCall) + " per call";
  }
  if (weights != static_cast<size_t>(weight_count) * tasks) {
    return "malformed batch: " + std::to_string(weights) + " weights for " + std::to_string(tasks) +
           " tasks of " + std::to_string(weight_count);
  }
  return "";
}

flapsim::EvaluateEpisodes::Response evaluateEpisodes(
    flapsim::RunnerCache& cache, const flapsim::EvaluateEpisodes::Request& req) {
  flapsim::EvaluateEpisodes::Response res;
  res.success = false;
  // What sizes the work and memory comes first: nothing is built for a call refused here.
  res.message = batchFault(req.episodes.size(), req.weights.size(), req.weight_count);
  if (!res.message.empty()) return res;
  std::shared_ptr<const flapsim::EpisodeRunner> runner;
  try {
    runner = cache.get(req.spec);
  } catch (const std::exception& e) {
    res.message = std::string("bad spec: ") + e.what();
    return res;
  }
  std::vector<flapsim::EpisodeTask> tasks;
  res.message = requestTasks(*runner, req, tasks);
  if (!res.message.empty()) return res;
  try {
    for (const auto& t : tasks) {
      const std::vector<double> v = runner->values(t);
      res.fitness.insert(res.fitness.end(), v.begin(), v.end());
    }
  } catch (const std::exception& e) {
    res.fitness.clear();
    res.message = std::string("episode failed: ") + e.what();
    return res;
  }
  res.success = true;
  return res;
}

namespace {

struct RequestCounts {
  std::uint32_t weight_count = 0, weights = 0, episodes = 0;
};

// The counts of a serialized EvaluateEpisodes request, read in place (its arrays are not
// copied); false if the bytes end before them.
bool peekCounts(const std::uint8_t* data, std::size_t size, RequestCounts& n) {
  std::size_t at = 0;
  auto u32 = [&](std::uint32_t& v) {
    if (size - at < 4) return false;
    std::memcpy(&v, data + at, 4);
    at += 4;
    return true;
  };
  std::uint32_t strings = 0, length = 0;
  if (!u32(strings)) return false;
  for (std::uint32_t i = 0; i < strings; ++i) {
    if (!u32(length) || size - at < length) return false;
    at += length;
  }
  if (!u32(n.weight_count) || !u32(n.weights) || (size - at) / 8 < n.weights) return false;
  at += static_cast<std::size_t>(n.weights) * 8;
  return u32(n.episodes);
}

// ~evaluate_episodes: a request whose counts are beyond the limits is refused from its bytes,
// before they are copied into a request (roscpp's own helper held an 80 MB batch twice); the
// others are deserialized and given to `answer`.
class EvaluateHelper : public ros::ServiceCallbackHelper {
 public:
  using Answer = std::function<void(const flapsim::EvaluateEpisodes::Request*,
                                    flapsim::EvaluateEpisodes::Response&)>;
  explicit EvaluateHelper(Answer answer) : answer_(std::move(answer)) {}
  bool call(ros::ServiceCallbackHelperCallParams& params) override {
    const ros::SerializedMessage& m = params.request;
    const std::size_t size = m.num_bytes - (m.message_start - m.buf.get());
    flapsim::EvaluateEpisodes::Response res;
    res.success = false;
    RequestCounts n;
    res.message = peekCounts(m.message_start, size, n)
                      ? batchFault(n.episodes, n.weights, n.weight_count)
                      : "malformed request: it ends before its arrays";
    if (res.message.empty()) {
      flapsim::EvaluateEpisodes::Request req;
      ros::serialization::deserializeMessage(m, req);
      answer_(&req, res);
    } else {
      answer_(nullptr, res);
    }
    params.response = ros::serialization::serializeServiceResponse(true, res);
    return true;
  }

 private:
  Answer answer_;
};

}  // namespace

EpisodeWorkerNode::EpisodeWorkerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : nh_(nh), pnh_(pnh) {
  threads_ = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  pnh_.param("threads", threads_, threads_);
  if (threads_ < 1 || threads_ > 256) throw std::invalid_argument("~threads must be in [1, 256]");
  // Blocks of 1 MiB and more (a large request, its strings) are mapped and handed back when
  // freed: glibc's threshold would otherwise rise to the size of the last one freed (up to
  // 32 MiB), and the next ones would stay in the heap (+32 MB after the campaign's calls).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  ros::AdvertiseServiceOptions options;
  options.init<flapsim::EvaluateEpisodes>(
      kEvaluateServiceName, [](flapsim::EvaluateEpisodes::Request&,
                               flapsim::EvaluateEpisodes::Response&) { return false; });
  options.helper = boost::make_shared<EvaluateHelper>(
      [this](const flapsim::EvaluateEpisodes::Request* req,
             flapsim::EvaluateEpisodes::Response& res) { answer(req, res); });
  server_ = pnh_.advertiseService(options);
  service_name_ = server_.getService();
  if (service_name_.rfind(std::string(kFarmNamespace) + "/", 0) != 0) {
    ROS_WARN_STREAM("flapsim_worker: " << service_name_ << " is not under " << kFarmNamespace
                                       << ": evolve --farm will not find it (start with __ns:="
                                       << kFarmNamespace << ")");
  }
  ROS_INFO_STREAM("flapsim_worker: serving " << service_name_ << " on " << threads_
                                             << " thread(s)");
}

void EpisodeWorkerNode::answer(const flapsim::EvaluateEpisodes::Request* req,
                               flapsim::EvaluateEpisodes::Response& res) {
  if (req != nullptr) res = evaluateEpisodes(cache_, *req);
  if (!res.success) {
    ROS_WARN_STREAM_THROTTLE(5.0, "flapsim_worker: refused a batch: " << res.message);
  } else {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    tasks_done_ += req != nullptr ? req->episodes.size() : res.fitness.size();
  }
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
    : link_(nh, spec, weight_count, params.ns),
      scheduler_(link_, flapsim::evaluationSpecFromArgs(spec), weight_count, params) {}

flapsim::WorkerReply FarmEvaluator::Link::call(const std::string& worker,
                                               const std::vector<flapsim::EpisodeTask>& tasks) {
  flapsim::EvaluateEpisodes srv;
  srv.request.spec = spec_;
  srv.request.weight_count = static_cast<std::uint32_t>(weight_count_);
  for (const auto& t : tasks) {
    srv.request.weights.insert(srv.request.weights.end(), t.weights.begin(), t.weights.end());
    srv.request.episodes.push_back(t.episode);
  }
  ros::ServiceClient client = nh_.serviceClient<flapsim::EvaluateEpisodes>(worker);
  // A call that fails is made once more before it counts: a dead worker fails again, while a
  // transient failure of the transport (the master's lookup of the service, the connection)
  // under a burst of calls does not bury a live worker. Tasks are pure, so a batch computed
  // twice gives the same values.
  flapsim::WorkerReply reply;
  reply.delivered = client.call(srv);
  if (!reply.delivered && ros::ok()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    reply.delivered = client.call(srv);
  }
  reply.success = srv.response.success;
  reply.message = srv.response.message;
  reply.fitness = std::move(srv.response.fitness);
  return reply;
}

ProgressPublisher::ProgressPublisher(ros::NodeHandle& nh, const std::string& ns) {
  pub_ = nh.advertise<flapsim::FarmProgress>(ns + "/progress", 1, /*latch=*/true);
}

}  // namespace flapsim_ros
