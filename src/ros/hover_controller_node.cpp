#include "flapsim_ros/hover_controller_node.h"

#include "flapsim/WingCommand.h"
#include "flapsim_ros/controller_params.h"
#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

HoverControllerNodeParams parseHoverControllerParams(const XmlRpc::XmlRpcValue& ns,
                                                     const std::string& default_creature) {
  static const XmlRpc::XmlRpcValue kEmpty = [] {
    XmlRpc::XmlRpcValue v;
    v.begin();  // an empty struct
    return v;
  }();
  const ParamReader d(ns.getType() == XmlRpc::XmlRpcValue::TypeInvalid ? kEmpty : ns, "");
  HoverControllerNodeParams p;
  p.creature = d.string("creature", default_creature);
  const std::string err = validateCreatureName(p.creature);
  if (!err.empty()) failParam(d.key("creature"), "'" + p.creature + "': " + err);
  p.rate = d.number("rate", p.rate);
  if (!(p.rate > 0.0)) failParam(d.key("rate"), "must be > 0");
  flapsim::HoverControllerParams& c = p.controller;
  c.altitude = d.number("altitude", c.altitude);
  c.trim_frequency = d.number("trim_frequency", c.trim_frequency);
  c.amplitude = d.number("amplitude", c.amplitude);
  c.feather = d.number("feather", c.feather);
  const std::string bad = flapsim::validateHoverControllerParams(c);
  if (!bad.empty()) failParam(d.key(""), bad);
  p.unknown_keys = d.unknownKeys();
  return p;
}

namespace {

XmlRpc::XmlRpcValue privateNamespace(const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue ns;
  if (!pnh.getParam(pnh.getNamespace(), ns)) ns = XmlRpc::XmlRpcValue();
  return ns;
}

}  // namespace

HoverControllerNode::HoverControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : nh_(nh),
      pnh_(pnh),
      params_(
          parseHoverControllerParams(privateNamespace(pnh), namespaceBasename(nh.getNamespace()))),
      controller_(params_.controller) {
  // In the creature's namespace (as ann_controller): imu, odom and wing_command are its topics.
  const std::string& c = params_.creature;
  imu_sub_ = nh_.subscribe<sensor_msgs::Imu>(
      "imu", 10, [this](const sensor_msgs::Imu::ConstPtr& m) { imu_ = m; });
  odom_sub_ = nh_.subscribe<nav_msgs::Odometry>(
      "odom", 10, [this](const nav_msgs::Odometry::ConstPtr& m) { odom_ = m; });
  pub_ = nh_.advertise<flapsim::WingCommand>("wing_command", 10);
  timer_ = nh_.createTimer(ros::Duration(1.0 / params_.rate), &HoverControllerNode::onTimer, this);
  for (const std::string& k : params_.unknown_keys) {
    ROS_WARN_STREAM("hover_controller: ignoring unknown parameter '" << pnh_.resolveName(k) << "'");
  }
  ROS_INFO_STREAM("hover_controller: '" << c << "' at " << params_.controller.altitude << " m, "
                                        << params_.rate << " Hz");
}

void HoverControllerNode::onTimer(const ros::TimerEvent&) {
  if (!imu_ || !odom_) {
    ROS_WARN_STREAM_THROTTLE(5.0, "hover_controller: no " << imu_sub_.getTopic() << " or "
                                                          << odom_sub_.getTopic() << " yet");
    return;
  }
  const ros::Time now = ros::Time::now();
  const double dt = last_.isZero() || now < last_ ? 1.0 / params_.rate : (now - last_).toSec();
  if (now < last_) controller_.reset();  // sim time went back: the simulator was reset
  last_ = now;
  flapsim::HoverSensors s;
  const auto& q = imu_->orientation;
  s.orientation = flapsim::Quat(q.w, q.x, q.y, q.z).normalized();
  s.angular_velocity =
      flapsim::Vec3(imu_->angular_velocity.x, imu_->angular_velocity.y, imu_->angular_velocity.z);
  const auto& p = odom_->pose.pose.position;
  s.position = flapsim::Vec3(p.x, p.y, p.z);
  const auto& v = odom_->twist.twist.linear;  // body frame (REP 105)
  s.velocity = s.orientation * flapsim::Vec3(v.x, v.y, v.z);
  const auto strokes = controller_.update(s, dt);
  WingCommandRequest r;
  r.joints = {flapsim::kHoverWingJoints[0], flapsim::kHoverWingJoints[1]};
  r.strokes = {strokes[0], strokes[1]};
  flapsim::WingCommand msg = toMsg(r);
  msg.header.stamp = now;
  pub_.publish(msg);
}

}  // namespace flapsim_ros
