// disturbance: real air's roll torque and push on a wing, drawn as flight_check --real-air
// draws them, applied to a creature at their sim times (flapsim_ros::DisturbanceNode). With
// --print it prints the draws without ROS (flapsim/real_air.h), as afc.launch real_air:=true
// reads the wind and the gyro bias.
#include <ros/ros.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "flapsim/real_air.h"
#include "flapsim_ros/disturbance_node.h"
#include "flapsim_ros/node_main.h"

namespace {

int printDraws(const std::vector<std::string>& args) {
  flapsim::RealAirPrintOptions options;
  flapsim::CliParser cli = flapsim::realAirPrintCli(options);
  try {
    cli.parse(args);
    if (cli.help()) {
      std::printf("%s", cli.usage().c_str());
      return 0;
    }
    if (options.urdf.empty()) throw flapsim::InputError("--urdf: the creature's URDF is required");
    const flapsim::RealAirDraws draws =
        flapsim::realAirDraws(*flapsim::loadCreatureModel(options.urdf), options.draw);
    std::printf("%s", flapsim::realAirPrint(options, draws).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "disturbance: %s\n", e.what());
    return 2;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  for (const std::string& a : args) {
    if (a == "--print" || a == "--help" || a == "-h") return printDraws(args);
  }
  ros::init(argc, argv, "disturbance");
  return flapsim_ros::runNode("disturbance", [] {
    flapsim_ros::DisturbanceNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    return node.run() ? 0 : 1;
  });
}
