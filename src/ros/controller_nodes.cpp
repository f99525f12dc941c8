#include "flapsim_ros/controller_nodes.h"

#include <geometry_msgs/TransformStamped.h>

#include <cmath>
#include <stdexcept>

#include "flapsim/Step.h"
#include "flapsim/control_loop.h"

namespace flapsim_ros {

namespace {

XmlRpc::XmlRpcValue privateNamespace(const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue ns;
  if (!pnh.getParam(pnh.getNamespace(), ns)) ns = XmlRpc::XmlRpcValue();
  return ns;
}

/// Polls `done` every half millisecond of wall time until it holds or `timeout` passes.
template <typename F>
bool waitFor(F done, double timeout) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && !done()) {
    if (ros::WallTime::now() > deadline) return false;
    ros::WallDuration(0.0005).sleep();
  }
  return ros::ok();
}

}  // namespace

// ---- stroke_controller ---------------------------------------------------------------------

StrokeControllerNode::StrokeControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : nh_(nh), pnh_(pnh), params_(load()) {
  pub_ = nh_.advertise<flapsim::WingCommand>("wing_command", 1, /*latch=*/true);
  publish();
  publish_timer_ = nh_.createTimer(ros::Duration(1.0 / params_.rate),
                                   [this](const ros::TimerEvent&) { publish(); });
  reread_timer_ = nh_.createWallTimer(ros::WallDuration(params_.reread_period),
                                      [this](const ros::WallTimerEvent&) { reread(); });
  for (const std::string& k : params_.unknown_keys) {
    ROS_WARN_STREAM("stroke_controller: ignoring unknown parameter '" << pnh_.resolveName(k)
                                                                      << "'");
  }
  ROS_INFO_STREAM("stroke_controller: " << params_.pairs << " wing pair(s) of '" << params_.creature
                                        << "' on " << pub_.getTopic());
}

StrokeControllerParams StrokeControllerNode::load() const {
  return parseStrokeControllerParams(privateNamespace(pnh_), namespaceBasename(nh_.getNamespace()));
}

void StrokeControllerNode::reread() {
  try {
    StrokeControllerParams p = load();
    bool changed = p.strokes.size() != params_.strokes.size();
    for (size_t i = 0; !changed && i < p.strokes.size(); ++i) {
      const auto &a = p.strokes[i], &b = params_.strokes[i];
      changed = a.downstroke_rate != b.downstroke_rate || a.upstroke_rate != b.upstroke_rate ||
                a.amplitude != b.amplitude || a.shape != b.shape;
    }
    params_.strokes = p.strokes;
    params_.pairs = p.pairs;
    if (changed) {
      ROS_INFO("stroke_controller: new strokes");
      publish();
    }
  } catch (const ParamError& e) {
    ROS_WARN_STREAM_THROTTLE(10.0, "stroke_controller: keeping the last strokes: " << e.what());
  }
}

void StrokeControllerNode::publish() {
  flapsim::WingCommand msg = strokeCommandMsg(params_.strokes);
  msg.header.stamp = ros::Time::now();
  pub_.publish(msg);
}

// ---- ann_controller ------------------------------------------------------------------------

AnnControllerNode::AnnControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : nh_(nh),
      pnh_(pnh),
      params_(
          parseAnnControllerParams(privateNamespace(pnh), namespaceBasename(nh.getNamespace()))),
      spec_(flapsim::loadControllerYaml(params_.weights_file)),
      layout_(flapsim::flapUnitLayout(params_.pairs)),
      listener_(buffer_, nh) {
  controller_ = std::make_unique<flapsim::AnnWingController>(
      flapsim::FlapUnitController(spec_.params, spec_.weights));
  if (params_.rate <= 0.0) params_.rate = 1.0 / spec_.params.control_period;
  creatures_ = !params_.lockstep_creatures.empty() ? params_.lockstep_creatures
                                                   : std::vector<std::string>{params_.creature};
  for (const std::string& c : creatures_) {
    frames_.emplace_back();
    for (const auto& link : layout_.body_links) frames_.back().push_back(c + "/" + link);
  }
  pub_ = nh_.advertise<flapsim::WingCommand>("wing_command", 10);
  if (params_.lockstep)
    start_srv_ = pnh_.advertiseService("start", &AnnControllerNode::onStart, this);
  for (const std::string& k : params_.unknown_keys) {
    ROS_WARN_STREAM("ann_controller: ignoring unknown parameter '" << pnh_.resolveName(k) << "'");
  }
  ROS_INFO_STREAM("ann_controller: " << params_.pairs << " unit(s) of '" << params_.creature
                                     << "' at " << params_.rate << " Hz, weights "
                                     << params_.weights_file
                                     << (params_.lockstep ? ", lockstep" : ""));
}

std::optional<std::vector<flapsim::Quat>> AnnControllerNode::bodies(const ros::Time& stamp,
                                                                    size_t c) const {
  std::vector<flapsim::Quat> out;
  for (const auto& frame : frames_[c]) {
    if (!buffer_.canTransform(params_.world_frame, frame, stamp)) return std::nullopt;
    const geometry_msgs::TransformStamped t =
        buffer_.lookupTransform(params_.world_frame, frame, stamp);
    const auto& r = t.transform.rotation;
    out.emplace_back(r.w, r.x, r.y, r.z);
  }
  return out;
}

void AnnControllerNode::command(const std::vector<flapsim::Quat>& bodies, const ros::Time& stamp) {
  flapsim::WingCommand msg = annCommandMsg(layout_, controller_->commands(bodies));
  msg.header.stamp = stamp;
  pub_.publish(msg);
}

void AnnControllerNode::onTimer(const ros::TimerEvent&) {
  const auto q = bodies(ros::Time(0));
  if (!q) {
    ROS_WARN_STREAM_THROTTLE(5.0, "ann_controller: no transform " << params_.world_frame << " -> "
                                                                  << frames_.front().front()
                                                                  << " (or another unit) yet");
    return;
  }
  command(*q, ros::Time::now());
}

bool AnnControllerNode::onStart(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  started_ = true;
  return true;
}

bool AnnControllerNode::run() {
  if (params_.lockstep) return runLockstep();
  ros::Timer timer =
      nh_.createTimer(ros::Duration(1.0 / params_.rate), &AnnControllerNode::onTimer, this);
  ros::spin();
  return true;
}

double AnnControllerNode::simulatorStepSize() const {
  if (params_.step_size > 0.0) return params_.step_size;
  const std::string key =
      ros::names::parentNamespace(ros::names::resolve(params_.step_service)) + "/step_size";
  double step_size = 0.0;
  if (nh_.getParam(key, step_size) && step_size > 0.0) return step_size;
  ROS_WARN_STREAM("ann_controller: neither ~step_size nor " << key << " is set: 0.001 s");
  return 0.001;
}

bool AnnControllerNode::runLockstep() {
  ros::AsyncSpinner spinner(1);  // serves ~start
  spinner.start();
  const double period = 1.0 / params_.rate;
  const double step_size = simulatorStepSize();
  long steps = 0;
  try {
    steps = flapsim::ControlLoop(period, step_size).stepsPerPeriod();
  } catch (const flapsim::InputError& e) {
    ROS_ERROR_STREAM("ann_controller: " << e.what());
    return false;
  }
  const double timeout = params_.wait_timeout;
  if (!ros::service::waitForService(params_.step_service, ros::Duration(timeout))) {
    ROS_ERROR_STREAM("ann_controller: no service " << params_.step_service);
    return false;
  }
  ros::ServiceClient step = nh_.serviceClient<flapsim::Step>(params_.step_service, true);
  if (params_.lockstep_wait_for_start) {
    ROS_INFO("ann_controller: lockstep waits for a call of ~start");
    if (!waitFor([&] { return started_.load(); }, timeout)) return false;
  }
  flapsim::Step srv;
  // The commands travel with the step request (applied before the first step): no race
  // between the wing_command topic and the service.
  auto call = [&](std::uint32_t n, const std::vector<flapsim::WingCommand>& commands = {}) {
    srv.request.steps = n;
    srv.request.creatures.clear();
    srv.request.wing_commands = commands;
    if (!commands.empty()) srv.request.creatures = creatures_;
    if (!step.call(srv) || !srv.response.success) {
      ROS_ERROR_STREAM("ann_controller: " << params_.step_service
                                          << " failed: " << srv.response.status_message);
      return false;
    }
    return true;
  };
  if (!call(0)) return false;  // the state at the current time, published
  ros::Time t = srv.response.sim_time;
  const long periods =
      params_.lockstep_duration > 0.0 ? std::lround(params_.lockstep_duration / period) : -1;
  std::vector<flapsim::WingCommand> commands(creatures_.size());
  for (long k = 0; ros::ok() && (periods < 0 || k < periods); ++k) {
    for (size_t c = 0; c < creatures_.size(); ++c) {
      std::optional<std::vector<flapsim::Quat>> q;
      ros::WallTime repeat = ros::WallTime::now() + ros::WallDuration(1.0);
      const bool got = waitFor(
          [&] {
            q = bodies(t, c);
            if (!q && ros::WallTime::now() > repeat) {  // lost publication: ask again
              repeat = ros::WallTime::now() + ros::WallDuration(1.0);
              call(0);
            }
            return q.has_value();
          },
          timeout);
      if (!got) {
        ROS_ERROR_STREAM("ann_controller: no transforms of " << creatures_[c] << " at t = " << t);
        return false;
      }
      commands[c] = annCommandMsg(layout_, controller_->commands(*q));
      commands[c].header.stamp = t;
    }
    if (!call(static_cast<std::uint32_t>(steps), commands)) return false;
    const ros::Duration advanced = srv.response.sim_time - t;
    if (std::abs(advanced.toSec() - period) > 1e-9) {
      // A wrong ~step_size would fly the network at another control period, silently.
      ROS_ERROR_STREAM("ann_controller: " << steps << " steps advanced the simulator by "
                                          << advanced.toSec() << " s, not the control period "
                                          << period << " s: ~step_size (" << step_size
                                          << " s) is not the simulator's step size");
      return false;
    }
    t = srv.response.sim_time;
  }
  ROS_INFO_STREAM("ann_controller: lockstep done at t = " << t);
  return true;
}

}  // namespace flapsim_ros
