#include "flapsim_ros/lockstep_client.h"

#include <cmath>

#include "flapsim/Step.h"
#include "flapsim/control_loop.h"

namespace flapsim_ros {

LockstepClient::LockstepClient(const ros::NodeHandle& nh, const LockstepParams& params,
                               std::string who)
    : nh_(nh), params_(params), who_(std::move(who)) {}

double LockstepClient::stepSize() const {
  if (params_.step_size > 0.0) return params_.step_size;
  const std::string key =
      ros::names::parentNamespace(ros::names::resolve(params_.step_service)) + "/step_size";
  double step_size = 0.0;
  if (nh_.getParam(key, step_size) && step_size > 0.0) return step_size;
  ROS_WARN_STREAM(who_ << ": neither ~step_size nor " << key << " is set: 0.001 s");
  return 0.001;
}

bool LockstepClient::connect(double period) {
  period_ = period;
  step_size_ = stepSize();
  try {
    steps_ = static_cast<std::uint32_t>(flapsim::ControlLoop(period, step_size_).stepsPerPeriod());
  } catch (const flapsim::InputError& e) {
    ROS_ERROR_STREAM(who_ << ": " << e.what());
    return false;
  }
  if (!ros::service::waitForService(params_.step_service, ros::Duration(params_.wait_timeout))) {
    ROS_ERROR_STREAM(who_ << ": no service " << params_.step_service);
    return false;
  }
  step_ = nh_.serviceClient<flapsim::Step>(params_.step_service, true);
  return call(0);  // the state at the current time, published
}

long LockstepClient::periods() const {
  return params_.lockstep_duration > 0.0 ? std::lround(params_.lockstep_duration / period_) : -1;
}

bool LockstepClient::call(std::uint32_t steps, const std::vector<std::string>& creatures,
                          const std::vector<flapsim::WingCommand>& commands) {
  flapsim::Step srv;
  srv.request.steps = steps;
  srv.request.creatures = creatures;
  srv.request.wing_commands = commands;
  if (!step_.call(srv) || !srv.response.success) {
    ROS_ERROR_STREAM(who_ << ": " << params_.step_service
                          << " failed: " << srv.response.status_message);
    return false;
  }
  time_ = srv.response.sim_time;
  return true;
}

bool LockstepClient::await(const std::function<bool()>& ready, const std::string& what) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(params_.wait_timeout);
  ros::WallTime repeat = ros::WallTime::now() + ros::WallDuration(1.0);
  while (ros::ok() && !ready()) {
    const ros::WallTime now = ros::WallTime::now();
    if (now > deadline) {
      ROS_ERROR_STREAM(who_ << ": no " << what << " at t = " << time_ << " within "
                            << params_.wait_timeout << " s");
      return false;
    }
    if (now > repeat) {  // lost publication: ask again
      repeat = now + ros::WallDuration(1.0);
      if (!call(0)) return false;
    }
    ros::WallDuration(0.0005).sleep();
  }
  return ros::ok();
}

bool LockstepClient::advance(const std::vector<std::string>& creatures,
                             const std::vector<flapsim::WingCommand>& commands) {
  const ros::Time before = time_;
  if (!call(steps_, creatures, commands)) return false;
  const double advanced = (time_ - before).toSec();
  if (std::abs(advanced - period_) > 1e-9) {
    // A wrong ~step_size would fly the controller at another control period, silently.
    ROS_ERROR_STREAM(who_ << ": " << steps_ << " steps advanced the simulator by " << advanced
                          << " s, not the control period " << period_ << " s: ~step_size ("
                          << step_size_ << " s) is not the simulator's step size");
    return false;
  }
  return true;
}

}  // namespace flapsim_ros
