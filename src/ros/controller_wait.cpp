#include "flapsim_ros/controller_wait.h"

#include <sstream>
#include <vector>

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {
namespace {

// s (wall) between sends of an awaited creature's state to its connected controllers: the
// state a new subscriber gets at once may reach a controller before its wing_command
// publisher is connected to the node, and its answer is then lost.
constexpr double kResendPeriod = 1.0;
constexpr double kHeldDiagnosticsPeriod = 1.0;  // s (wall) between /diagnostics while held

}  // namespace

ControllerWait::ControllerWait(const flapsim::World& world, CreatureRegistry& creatures,
                               NodeDiagnostics& diagnostics, Stepper& stepper,
                               const NodeParams& params)
    : world_(world),
      creatures_(creatures),
      diagnostics_(diagnostics),
      stepper_(stepper),
      params_(params) {}

bool ControllerWait::hold() {
  std::vector<NodeCreature*> awaited;
  for (const auto& c : creatures_.all()) {
    if (c->awaiting_controller) awaited.push_back(c.get());
  }
  if (stepper_.paused()) {  // paused time is no controller's delay
    held_wall_ = ros::WallTime();
    return !awaited.empty();
  }
  const ros::WallTime wall = ros::WallTime::now();
  if (awaited.empty()) {
    if (holding_) {
      if (!held_wall_.isZero()) held_ += (wall - held_wall_).toSec();
      ROS_INFO_STREAM("flapsim: every controller answered after "
                      << held_ << " s of wall time: running from t = " << formatTime(simNow(world_))
                      << " s");
      end();
    }
    return false;
  }
  if (!holding_) {
    holding_ = true;
    awaited_count_ = awaited.size();
    std::ostringstream who;
    for (const NodeCreature* c : awaited) {
      who << (c == awaited.front() ? "" : ", ") << c->controller << " ('" << c->name << "')";
    }
    ROS_INFO_STREAM("flapsim: holding sim time at t = "
                    << formatTime(simNow(world_)) << " s for the first wing command of "
                    << who.str() << ", at most " << params_.controller_wait_timeout
                    << " s of wall time (~controller_wait_timeout)");
    diagnostics_.publish();
  }
  if (!held_wall_.isZero()) held_ += (wall - held_wall_).toSec();
  held_wall_ = wall;
  if (held_ >= params_.controller_wait_timeout) {
    for (NodeCreature* c : awaited) {
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
    end();
    return false;
  }
  // Each answer shows at once, the wait every second (a monitor that joins late sees it).
  if (awaited.size() != awaited_count_ || diagnostics_.age() >= kHeldDiagnosticsPeriod) {
    awaited_count_ = awaited.size();
    diagnostics_.publish();
  }
  if ((wall - resent_wall_).toSec() >= kResendPeriod) {
    resent_wall_ = wall;
    for (const NodeCreature* c : awaited) {
      if (c->wing_command.getNumPublishers() > 0) {
        c->topics->publishState(snapshotOf(world_, c->name, simNow(world_)));
      }
    }
  }
  return true;
}

void ControllerWait::end() {
  holding_ = false;
  stepper_.restartPacing();
  diagnostics_.publish();
}

}  // namespace flapsim_ros
