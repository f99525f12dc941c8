#include "flapsim_ros/node_diagnostics.h"

#include <diagnostic_msgs/DiagnosticArray.h>

#include <sstream>

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

NodeDiagnostics::NodeDiagnostics(const ros::NodeHandle& nh, const flapsim::World& world,
                                 const CreatureRegistry& creatures, const NodeParams& params)
    : world_(world), creatures_(creatures), params_(params) {
  pub_ = ros::NodeHandle(nh).advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
}

void NodeDiagnostics::publish() {
  last_ = ros::WallTime::now();
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = simNow(world_);
  const std::uint64_t step_ns = stepNanoseconds(world_.params().step_size);
  for (const auto& c : creatures_.all()) {
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "flapsim: " + c->name;
    s.hardware_id = c->name;
    const std::optional<flapsim::Divergence> d = world_.divergence(c->name);
    const std::optional<flapsim::CommandLapse> lapse = world_.commandLapse(c->name);
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
    } else if (lapse) {
      s.level = diagnostic_msgs::DiagnosticStatus::WARN;
      s.message =
          "wing command timed out at t = " + formatTime(simTime(lapse->step, step_ns)) + " s";
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
  pub_.publish(array);
}

}  // namespace flapsim_ros
