// flapsim_worker: evaluates evolution episodes for evolve --farm. Start it in the
// farm's namespace: flapsim_worker __ns:=/flapsim_farm __name:=worker_1 [_threads:=2].
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/episode_farm.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flapsim_worker");
  ros::NodeHandle nh, pnh("~");
  try {
    flapsim_ros::EpisodeWorkerNode node(nh, pnh);
    node.run();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("flapsim_worker: " << e.what());
    return 1;
  }
  return 0;
}
