#include "flapsim_ros/evolve_session.h"

#include <cstdio>
#include <filesystem>

namespace flapsim_ros {

EvolveSession::EvolveSession(int argc, char** argv, const flapsim::EvolveOptions& options,
                             const std::optional<flapsim::EvolveCheckpoint>& resume)
    : options_(options), resume_(resume) {
  if (!options_.farm) return;
  ros::init(argc, argv, "evolve", ros::init_options::AnonymousName);
  nh_ = std::make_unique<ros::NodeHandle>();
  FarmParams fp;
  fp.timeout = options_.farm_timeout;
  fp.wait = options_.farm_wait;
  fp.inflight = options_.farm_inflight;
  fp.batch = options_.farm_batch;
  farm_ = std::make_unique<FarmEvaluator>(*nh_, options_.spec_args,
                                          flapsim::geneCount(options_.params), fp);
  progress_ = std::make_unique<ProgressPublisher>(*nh_, fp.ns);
}

EvolveSession::~EvolveSession() {
  if (farm_) ros::shutdown();
  progress_.reset();
  farm_.reset();
}

double EvolveSession::elapsed() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

void EvolveSession::onGeneration(const flapsim::GenerationStats& g) {
  const auto now = Clock::now();
  const double dt = std::chrono::duration<double>(now - last_).count();
  last_ = now;
  const int first = resume_ ? resume_->generation + 1 : 0;
  const int workers = farm_ ? farm_->workersUp() : options_.params.ga.threads;
  std::fputs(flapsim::evolveProgressLine(options_, g, first, elapsed(), dt, workers).c_str(),
             stdout);
  std::fflush(stdout);
  if (!progress_) return;
  flapsim::FarmProgress msg;
  msg.generation = g.generation;
  msg.generations = options_.params.ga.generations;
  msg.best = g.best;
  msg.mean = g.mean;
  msg.episodes = g.evaluations * options_.params.episode.episodes;
  msg.episodes_per_second = flapsim::episodesPerSecond(options_, g, dt);
  msg.workers_up = workers;
  msg.seconds_left = flapsim::secondsLeft(options_, g, first, elapsed());
  progress_->publish(msg);
}

flapsim::EvolveResult EvolveSession::run() {
  std::filesystem::create_directories(options_.out_dir);
  start_ = last_ = Clock::now();
  flapsim::EvolveHooks hooks;
  hooks.evaluator = farm_.get();
  hooks.resume = resume_ ? &*resume_ : nullptr;
  hooks.on_checkpoint = [&](flapsim::EvolveCheckpoint c) {
    c.args = options_.spec_args;
    flapsim::writeCheckpointFile(options_.out_dir + "/checkpoint.txt", c);
  };
  hooks.on_generation = [&](const flapsim::GenerationStats& g) { onGeneration(g); };
  return flapsim::evolveFlapController(options_.params, hooks);
}

std::string EvolveSession::droppedReport() const {
  std::string report;
  if (!farm_) return report;
  for (const auto& [worker, why] : farm_->dropped()) {
    report += "worker " + worker + " was dropped: " + why + "\n";
  }
  return report;
}

}  // namespace flapsim_ros
