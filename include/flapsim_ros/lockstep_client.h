// A controller node's side of lockstep (ann_controller, hover_controller): it drives a paused
// flapsim_node through its step service one control period per call, the wing commands in the
// request (applied before the first step: no race with the wing_command topic), and checks that
// every call advanced sim time by exactly the control period.
#pragma once

#include <ros/ros.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "flapsim/WingCommand.h"
#include "flapsim_ros/controller_params.h"

namespace flapsim_ros {

class LockstepClient {
 public:
  /// `who`: the node's name in its log messages.
  LockstepClient(const ros::NodeHandle& nh, const LockstepParams& params, std::string who);

  /// Counts the steps of a control `period` (s) in the simulator's step (~step_size, else the
  /// parameter step_size next to the step service), waits for the service and has the state at
  /// the current time published. False (logged) on failure.
  bool connect(double period);
  /// The sim time of the state last published.
  const ros::Time& time() const { return time_; }
  /// The control periods to run: lockstep_duration over the period, -1 (forever) if 0.
  long periods() const;
  /// Waits (up to wait_timeout of wall time) until `ready()` holds, as the callbacks of another
  /// thread receive the state; asks for the state again every wall second (a lost
  /// publication). False (logged, naming `what`) on timeout or shutdown.
  bool await(const std::function<bool()>& ready, const std::string& what);
  /// Steps one control period with `commands[i]` for `creatures[i]`. False (logged) if the
  /// call fails or the simulator advanced by another time than the period.
  bool advance(const std::vector<std::string>& creatures,
               const std::vector<flapsim::WingCommand>& commands);

 private:
  bool call(std::uint32_t steps, const std::vector<std::string>& creatures = {},
            const std::vector<flapsim::WingCommand>& commands = {});
  double stepSize() const;

  ros::NodeHandle nh_;
  LockstepParams params_;
  std::string who_;
  ros::ServiceClient step_;
  double period_ = 0.0;
  double step_size_ = 0.0;
  std::uint32_t steps_ = 0;
  ros::Time time_;
};

}  // namespace flapsim_ros
