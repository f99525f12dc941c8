#include "flapsim_ros/hover_controller_node.h"

#include "flapsim/WingCommand.h"
#include "flapsim/hover_gains.h"
#include "flapsim_ros/controller_params.h"
#include "flapsim_ros/conversions.h"
#include "flapsim_ros/lockstep_client.h"

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
  readLockstepParams(d, p);
  flapsim::HoverControllerParams& c = p.controller;
  // The gains file through the reader flight_check and evolve use (unknown and repeated keys
  // refused by name); a gain also given as a parameter overrides the file's.
  const std::string gains_file = d.string("gains_file", "");
  if (!gains_file.empty()) {
    try {
      c = flapsim::loadHoverGainsYaml(gains_file);
    } catch (const std::exception& e) {
      failParam(d.key("gains_file"), e.what());
    }
  }
  for (const flapsim::HoverParamField& f : flapsim::hoverParamFields()) {
    c.*f.member = d.number(f.name, c.*f.member);
  }
  const std::string bad = flapsim::validateHoverControllerParams(c);
  if (!bad.empty()) failParam(d.key(""), bad);
  d.rejectUnknown();  // as a weights or gains file refuses a key it does not read
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
  imu_sub_ =
      nh_.subscribe<sensor_msgs::Imu>("imu", 10, [this](const sensor_msgs::Imu::ConstPtr& m) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          imu_ = m;
        }
        if (!params_.lockstep) onState();
      });
  odom_sub_ =
      nh_.subscribe<nav_msgs::Odometry>("odom", 10, [this](const nav_msgs::Odometry::ConstPtr& m) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          odom_ = m;
        }
        if (!params_.lockstep) onState();
      });
  // Latched: the simulator holds sim time for the first command (this controller answers the
  // state it gets on connecting), which must not be lost if it goes out before the simulator's
  // subscription connects.
  pub_ = nh_.advertise<flapsim::WingCommand>("wing_command", 10, /*latch=*/true);
  ROS_INFO_STREAM("hover_controller: '" << c << "' at " << params_.controller.altitude << " m, "
                                        << params_.rate << " Hz"
                                        << (params_.lockstep ? ", lockstep" : ""));
}

bool HoverControllerNode::sensorsAt(const ros::Time& stamp, flapsim::HoverSensors& s,
                                    ros::Time& at) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!imu_ || !odom_ || imu_->header.stamp != odom_->header.stamp) return false;
  if (!stamp.isZero() && odom_->header.stamp != stamp) return false;
  at = odom_->header.stamp;
  const auto& q = imu_->orientation;
  s.orientation = flapsim::Quat(q.w, q.x, q.y, q.z).normalized();
  s.angular_velocity =
      flapsim::Vec3(imu_->angular_velocity.x, imu_->angular_velocity.y, imu_->angular_velocity.z);
  const auto& p = odom_->pose.pose.position;
  s.position = flapsim::Vec3(p.x, p.y, p.z);
  const auto& v = odom_->twist.twist.linear;  // body frame (REP 105)
  s.velocity = s.orientation * flapsim::Vec3(v.x, v.y, v.z);
  return true;
}

flapsim::WingCommand HoverControllerNode::command(const flapsim::HoverSensors& s, double dt,
                                                  const ros::Time& stamp) {
  const auto strokes = controller_.update(s, dt);
  WingCommandRequest r;
  r.joints = {flapsim::kHoverWingJoints[0], flapsim::kHoverWingJoints[1]};
  r.strokes = {strokes[0], strokes[1]};
  flapsim::WingCommand msg = toMsg(r);
  msg.header.stamp = stamp;
  return msg;
}

void HoverControllerNode::onState() {
  flapsim::HoverSensors s;
  ros::Time stamp;
  if (!sensorsAt(ros::Time(0), s, stamp)) return;  // the other half of this state yet to come
  const double period = 1.0 / params_.rate;
  if (stamp < last_) {
    controller_.reset();  // sim time went back: the simulator was reset
    last_ = ros::Time();
  }
  // At most `rate` answers a second (to a microsecond: stamps are whole steps).
  if (!last_.isZero() && (stamp - last_).toSec() < period - 1e-6) return;
  const double dt = last_.isZero() ? period : (stamp - last_).toSec();
  last_ = stamp;
  pub_.publish(command(s, dt, stamp));
}

bool HoverControllerNode::run() {
  if (params_.lockstep) return runLockstep();
  ros::spin();
  return true;
}

bool HoverControllerNode::runLockstep() {
  ros::AsyncSpinner spinner(1);  // receives imu and odom
  spinner.start();
  const double period = 1.0 / params_.rate;
  LockstepClient lockstep(nh_, params_, "hover_controller");
  if (!lockstep.connect(period)) return false;
  const long periods = lockstep.periods();
  const std::vector<std::string> creatures = {params_.creature};
  for (long k = 0; ros::ok() && (periods < 0 || k < periods); ++k) {
    const ros::Time t = lockstep.time();
    flapsim::HoverSensors s;
    ros::Time at;
    if (!lockstep.await([&] { return sensorsAt(t, s, at); },
                        imu_sub_.getTopic() + " and " + odom_sub_.getTopic())) {
      return false;
    }
    if (!lockstep.advance(creatures, {command(s, period, t)})) return false;
  }
  ROS_INFO_STREAM("hover_controller: lockstep done at t = " << lockstep.time());
  return true;
}

}  // namespace flapsim_ros
