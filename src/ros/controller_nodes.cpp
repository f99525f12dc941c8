#include "flapsim_ros/controller_nodes.h"

#include <geometry_msgs/TransformStamped.h>

#include <cmath>
#include <stdexcept>

#include "flapsim_ros/lockstep_client.h"

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

bool AnnControllerNode::runLockstep() {
  ros::AsyncSpinner spinner(1);  // serves ~start
  spinner.start();
  if (params_.lockstep_wait_for_start) {
    ROS_INFO("ann_controller: lockstep waits for a call of ~start");
    if (!waitFor([&] { return started_.load(); }, params_.wait_timeout)) return false;
  }
  LockstepClient lockstep(nh_, params_, "ann_controller");
  if (!lockstep.connect(1.0 / params_.rate)) return false;
  const long periods = lockstep.periods();
  std::vector<flapsim::WingCommand> commands(creatures_.size());
  for (long k = 0; ros::ok() && (periods < 0 || k < periods); ++k) {
    const ros::Time t = lockstep.time();
    for (size_t c = 0; c < creatures_.size(); ++c) {
      std::optional<std::vector<flapsim::Quat>> q;
      if (!lockstep.await([&] { return (q = bodies(t, c)).has_value(); },
                          "transforms of " + creatures_[c])) {
        return false;
      }
      commands[c] = annCommandMsg(layout_, controller_->commands(*q));
      commands[c].header.stamp = t;
    }
    if (!lockstep.advance(creatures_, commands)) return false;
  }
  ROS_INFO_STREAM("ann_controller: lockstep done at t = " << lockstep.time());
  return true;
}

}  // namespace flapsim_ros
