// The simulator node's /diagnostics: one status per creature (frozen, waiting for its
// controller or run without it, its wing command timed out or lagging, or running).
#include <diagnostic_msgs/DiagnosticArray.h>

#include <sstream>

#include "flapsim_ros/simulator_node.h"

namespace flapsim_ros {

void SimulatorNode::publishDiagnostics() {
  diagnostics_wall_ = ros::WallTime::now();
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = now();
  for (const auto& c : creatures_) {
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "flapsim: " + c->name;
    s.hardware_id = c->name;
    const std::optional<flapsim::Divergence> d = world_.divergence(c->name);
    if (d) {
      s.level = diagnostic_msgs::DiagnosticStatus::ERROR;
      s.message = "frozen: diverged at step " + std::to_string(d->step) + ": " + d->quantity;
    } else if (c->awaiting_controller) {
      s.level = diagnostic_msgs::DiagnosticStatus::WARN;
      s.message = "waiting for the first wing command of its controller " + c->controller +
                  ": sim time holds until it comes (~controller_wait_timeout)";
    } else if (c->controller_missing) {
      s.level = diagnostic_msgs::DiagnosticStatus::ERROR;
      std::ostringstream m;
      m << "its controller " << c->controller << " sent no wing command within "
        << params_.controller_wait_timeout << " s of wall time: running without it";
      s.message = m.str();
    } else if (c->command_lapsed) {
      s.level = diagnostic_msgs::DiagnosticStatus::WARN;
      s.message = "wing command timed out at t = " +
                  formatTime(simTime(c->command_step + timeout_steps_, step_ns_)) + " s";
    } else if (c->command_lag > kCommandLagWarning) {
      s.level = diagnostic_msgs::DiagnosticStatus::WARN;
      s.message = "wing commands lag: the last answered a state " +
                  formatTime(ros::Time(c->command_lag)) +
                  " s of sim time old (its controller falls behind)";
    } else {
      s.level = diagnostic_msgs::DiagnosticStatus::OK;
      s.message = "running";
    }
    array.status.push_back(s);
  }
  diagnostics_pub_.publish(array);
}

}  // namespace flapsim_ros
