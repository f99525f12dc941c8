// fake_worker (tests only): a hostile episode-farm worker. It serves ~evaluate_episodes as
// flapsim_worker does but answers by ~mode: "nan", "inf" or "huge" (1e308) as the fitness of
// every task, "wrong_count" (one value too many, each 0), or "refuse" (success = false).
// Start it in the farm's namespace: fake_worker __ns:=/flapsim_farm __name:=bad _mode:=nan
#include <ros/ros.h>

#include <cmath>
#include <limits>
#include <string>

#include "flapsim/EvaluateEpisodes.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "fake_worker");
  ros::NodeHandle pnh("~");
  const std::string mode = pnh.param<std::string>("mode", "nan");
  const double value = mode == "nan"    ? std::nan("")
                       : mode == "inf"  ? std::numeric_limits<double>::infinity()
                       : mode == "huge" ? 1e308
                                        : 0.0;
  if (mode != "nan" && mode != "inf" && mode != "huge" && mode != "wrong_count" &&
      mode != "refuse") {
    ROS_FATAL_STREAM("fake_worker: unknown ~mode '" << mode << "'");
    return 1;
  }
  ros::ServiceServer server =
      pnh.advertiseService<flapsim::EvaluateEpisodes::Request, flapsim::EvaluateEpisodes::Response>(
          "evaluate_episodes",
          [&](flapsim::EvaluateEpisodes::Request& req, flapsim::EvaluateEpisodes::Response& res) {
            res.success = mode != "refuse";
            res.message = mode == "refuse" ? "fake worker: refusing" : "";
            if (res.success)
              res.fitness.assign(req.episodes.size() + (mode == "wrong_count"), value);
            return true;
          });
  ROS_INFO_STREAM("fake_worker: answering '" << mode << "' on " << server.getService());
  ros::spin();
  return 0;
}
