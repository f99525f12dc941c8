// evolve's run apart from main(): the clock of its progress lines, its checkpoints and, with
// --farm, the ROS node, the farm and the progress topic.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "flapsim/evolve_tool.h"
#include "flapsim_ros/episode_farm.h"

namespace flapsim_ros {

class EvolveSession {
 public:
  /// With options.farm: ros::init (argc, argv), the FarmEvaluator and ProgressPublisher.
  EvolveSession(int argc, char** argv, const flapsim::EvolveOptions& options,
                const std::optional<flapsim::EvolveCheckpoint>& resume);
  /// With --farm, ros::shutdown() first: the calls still waiting for an answer end, and the
  /// farm joins its call threads before ROS is gone.
  ~EvolveSession();
  EvolveSession(const EvolveSession&) = delete;
  EvolveSession& operator=(const EvolveSession&) = delete;

  /// Runs the evolution: a progress line per generation (and FarmProgress with --farm), a
  /// checkpoint in the output directory after each.
  flapsim::EvolveResult run();
  /// Seconds since run() began.
  double elapsed() const;
  /// "farm" or "in process".
  std::string evaluatedOn() const { return farm_ ? "farm" : "in process"; }
  /// One line per worker dropped in the run, naming it and why ("" if none).
  std::string droppedReport() const;

 private:
  using Clock = std::chrono::steady_clock;
  void onGeneration(const flapsim::GenerationStats& g);

  flapsim::EvolveOptions options_;
  std::optional<flapsim::EvolveCheckpoint> resume_;
  std::unique_ptr<ros::NodeHandle> nh_;
  std::unique_ptr<FarmEvaluator> farm_;
  std::unique_ptr<ProgressPublisher> progress_;
  Clock::time_point start_, last_;
};

}  // namespace flapsim_ros
