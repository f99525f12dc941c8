// The simulator node's wait for its creatures' controllers (SimulatorNode, continued): a
// creature that names a `controller` in ~creatures holds sim time until that controller's
// first wing command, as a scenario waits for rviz and the recorder, so the controller flies
// it from t = 0 (before, a free-running controller's first command came some 0.7 s of sim
// time late, the creature falling meanwhile).
#include <sstream>

#include "flapsim_ros/simulator_node.h"

namespace flapsim_ros {
namespace {

// s (wall) between sends of an awaited creature's state to its connected controllers: the
// state a new subscriber gets at once may reach a controller before its wing_command
// publisher is connected to the node, and its answer is then lost.
constexpr double kResendPeriod = 1.0;
constexpr double kHeldDiagnosticsPeriod = 1.0;  // s (wall) between /diagnostics while held

}  // namespace

bool SimulatorNode::holdForControllers() {
  std::vector<Creature*> awaited;
  for (const auto& c : creatures_) {
    if (c->awaiting_controller) awaited.push_back(c.get());
  }
  if (paused_) {  // paused time is no controller's delay
    held_wall_ = ros::WallTime();
    return !awaited.empty();
  }
  const ros::WallTime wall = ros::WallTime::now();
  if (awaited.empty()) {
    if (holding_) {
      holding_ = false;
      if (!held_wall_.isZero()) held_ += (wall - held_wall_).toSec();
      ROS_INFO_STREAM("flapsim: every controller answered after "
                      << held_ << " s of wall time: running from t = " << formatTime(now())
                      << " s");
      restartPacing();
      publishDiagnostics();
    }
    return false;
  }
  if (!holding_) {
    holding_ = true;
    awaited_count_ = awaited.size();
    std::ostringstream who;
    for (const Creature* c : awaited) {
      who << (c == awaited.front() ? "" : ", ") << c->controller << " ('" << c->name << "')";
    }
    ROS_INFO_STREAM("flapsim: holding sim time at t = "
                    << formatTime(now()) << " s for the first wing command of " << who.str()
                    << ", at most " << params_.controller_wait_timeout
                    << " s of wall time (~controller_wait_timeout)");
    publishDiagnostics();
  }
  if (!held_wall_.isZero()) held_ += (wall - held_wall_).toSec();
  held_wall_ = wall;
  if (held_ >= params_.controller_wait_timeout) {
    for (Creature* c : awaited) {
      c->awaiting_controller = false;
      c->controller_missing = true;
      ROS_ERROR_STREAM("flapsim: creature '"
                       << c->name << "': its controller " << c->controller
                       << " sent no wing command on " << c->wing_command.getTopic() << " within "
                       << params_.controller_wait_timeout
                       << " s of wall time (~controller_wait_timeout): running without it"
                       << (c->wing_command.getNumPublishers() == 0
                               ? " (nothing publishes that topic)"
                               : ""));
    }
    holding_ = false;
    restartPacing();
    publishDiagnostics();
    return false;
  }
  // Each answer shows at once, the wait every second (a monitor that joins late sees it).
  if (awaited.size() != awaited_count_ ||
      (wall - diagnostics_wall_).toSec() >= kHeldDiagnosticsPeriod) {
    awaited_count_ = awaited.size();
    publishDiagnostics();
  }
  if ((wall - resent_wall_).toSec() >= kResendPeriod) {
    resent_wall_ = wall;
    for (const Creature* c : awaited) {
      if (c->wing_command.getNumPublishers() > 0) publishCreatureState(*c, now());
    }
  }
  return true;
}

}  // namespace flapsim_ros
