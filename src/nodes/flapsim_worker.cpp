// flapsim_worker: evaluates evolution episodes for evolve --farm. Start it in the
// farm's namespace: flapsim_worker __ns:=/flapsim_farm __name:=worker_1 [_threads:=2].
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/episode_farm.h"
#include "flapsim_ros/node_main.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flapsim_worker");
  return flapsim_ros::runNode("flapsim_worker", [] {
    flapsim_ros::EpisodeWorkerNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    node.run();
    return 0;
  });
}
