#include "flapsim_ros/disturbance_node.h"

#include <ros/callback_queue.h>
#include <ros/names.h>

#include <cmath>
#include <sstream>

#include "flapsim/ApplyWrench.h"
#include "flapsim/GetState.h"
#include "flapsim/evolve.h"
#include "flapsim/world.h"
#include "flapsim_ros/controller_params.h"  // namespaceBasename
#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

namespace {

using XmlRpc::XmlRpcValue;

// `value` within [lo, hi] (or (lo, hi] if `open_lo`), else ParamError naming `key`.
void requireRange(const ParamReader& d, const std::string& key, double value, double lo, double hi,
                  bool open_lo, const std::string& unit) {
  if (!((open_lo ? value > lo : value >= lo) && value <= hi)) {
    std::ostringstream msg;
    msg << "must be in " << (open_lo ? "(" : "[") << lo << ", " << hi << "] " << unit << ", not "
        << value;
    failParam(d.key(key), msg.str());
  }
}

geometry_msgs::Vector3 vectorMsg(const flapsim::Vec3& v) {
  geometry_msgs::Vector3 m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

}  // namespace

DisturbanceParams parseDisturbanceParams(const XmlRpcValue& ns,
                                         const std::string& default_creature) {
  XmlRpcValue empty;
  empty.begin();  // an empty struct: nothing set
  const ParamReader d(ns.getType() == XmlRpcValue::TypeInvalid ? empty : ns, "");
  DisturbanceParams p;
  p.creature = d.string("creature", default_creature);
  const std::string err = validateCreatureName(p.creature);
  if (!err.empty()) failParam(d.key("creature"), "'" + p.creature + "': " + err);
  const int seed = d.integer("seed", static_cast<int>(p.draw.seed));
  if (seed < 0) failParam(d.key("seed"), "must be an integer >= 0, not " + std::to_string(seed));
  p.draw.seed = static_cast<std::uint64_t>(seed);
  p.draw.duration = d.number("duration", p.draw.duration);
  requireRange(d, "duration", p.draw.duration, 0.0, flapsim::kMaxEpisodeDuration, true, "s");
  if (d.has("torque")) {
    p.draw.torque = d.number("torque", 0.0);
    requireRange(d, "torque", *p.draw.torque, 0.0, flapsim::kMaxTorque, false,
                 "N m (a size: its sign is drawn)");
  }
  if (d.has("push")) {
    p.draw.force = d.number("push", 0.0);
    requireRange(d, "push", *p.draw.force, 0.0, flapsim::kMaxForce, false,
                 "N (a size: its sign is drawn)");
  }
  p.apply_wrench_service = d.string("apply_wrench_service", p.apply_wrench_service);
  p.get_state_service = d.string("get_state_service", p.get_state_service);
  p.wait_timeout = d.number("wait_timeout", p.wait_timeout);
  requireRange(d, "wait_timeout", p.wait_timeout, 0.0, 1e6, true, "s");
  d.rejectUnknown();
  return p;
}

DisturbanceNode::DisturbanceNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : nh_(nh), pnh_(pnh) {
  XmlRpcValue ns;
  if (!pnh_.getParam(pnh_.getNamespace(), ns)) ns = XmlRpcValue();
  params_ = parseDisturbanceParams(ns, namespaceBasename(nh_.getNamespace()));
  const std::string node = ros::names::parentNamespace(  // the simulator node's private one
      ros::names::resolve(params_.apply_wrench_service));
  step_size_key_ = ros::names::append(node, "step_size");
  const std::string simulator = ros::names::parentNamespace(node);
  description_key_ =
      ros::names::append(ros::names::append(simulator, params_.creature), "robot_description");
  applied_pub_ = pnh_.advertise<geometry_msgs::WrenchStamped>("applied", 2, /*latch=*/true);
}

bool DisturbanceNode::run() {
  for (const std::string& s : {params_.apply_wrench_service, params_.get_state_service}) {
    if (!ros::service::waitForService(s, ros::Duration(params_.wait_timeout))) {
      ROS_ERROR_STREAM("disturbance: no service " << s << " within " << params_.wait_timeout
                                                  << " s (~wait_timeout)");
      return false;
    }
  }
  // Persistent, as the lockstep client's: roscpp's connection per call loses about one call
  // in 10^4 (doc/reliability.md).
  apply_wrench_ = nh_.serviceClient<flapsim::ApplyWrench>(params_.apply_wrench_service, true);
  get_state_ = nh_.serviceClient<flapsim::GetState>(params_.get_state_service, true);
  torque_.what = "roll torque";
  push_.what = "push";
  // Ahead of the flight if the creature is there: its state answered means it was spawned
  // (its description is set then), and the flight waits for this node to receive /clock.
  ros::Time now;
  if (linkPose("", now, false) && draw()) {
    handOver();
  } else {
    ROS_INFO_STREAM("disturbance: no creature '" << params_.creature
                                                 << "' yet: its wrenches at the first /clock "
                                                    "at which it is there");
  }
  clock_sub_ = nh_.subscribe("/clock", 100, &DisturbanceNode::onClock, this);
  while (ros::ok() && fatal_.empty()) {
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.1));
  }
  if (!fatal_.empty()) throw flapsim::InputError(fatal_);  // the node's fatal cause
  return true;
}

bool DisturbanceNode::draw() {
  if (model_) return true;
  std::string urdf;
  if (!nh_.getParam(description_key_, urdf)) return false;
  model_ = flapsim::parseCreatureModel(urdf, description_key_);
  draws_ = flapsim::realAirDraws(*model_, params_.draw);
  torque_.time = draws_.torque_time;
  push_.time = draws_.force_time;
  torque_.wanted = draws_.torque != 0.0;
  push_.wanted = draws_.force != 0.0;
  for (Pending* p : {&torque_, &push_}) p->handed = !p->wanted;  // none: nothing to hand over
  ROS_INFO_STREAM("disturbance: real air for '"
                  << params_.creature << "' (flight_check --real-air --seed " << params_.draw.seed
                  << " --duration " << params_.draw.duration << ", its first start):\n"
                  << flapsim::describeRealAirDraws(draws_)
                  << "\n(applied here: the torque and the push; the wind, the gyro bias, the "
                     "turbulence and the noises are the simulator's and the controller's)");
  return true;
}

void DisturbanceNode::onClock(const rosgraph_msgs::Clock::ConstPtr& msg) {
  const double t = msg->clock.toSec();
  if (t < last_time_) {  // a reset dropped the wrenches waiting: those still to come again
    for (Pending* p : {&torque_, &push_}) {
      if (!p->wanted || p->time < t) continue;
      p->handed = p->started = false;
      p->applied = geometry_msgs::WrenchStamped();
    }
  }
  last_time_ = t;
  try {
    if (!draw()) {
      // Past the earliest time a disturbance can be drawn at (EpisodeParams' gust window).
      if (!warned_ && t > flapsim::EpisodeParams().gust_window_start * params_.draw.duration) {
        ROS_ERROR_STREAM("disturbance: no " << description_key_ << " at t = " << t
                                            << " s: nothing drawn, nothing applied yet");
        warned_ = true;
      }
      return;
    }
    if (!torque_.handed || !push_.handed) handOver();
    for (Pending* p : {&torque_, &push_}) {
      const ros::Time& start = p->applied.header.stamp;
      if (p->started || start.isZero() || msg->clock < start) continue;
      p->started = true;
      applied_pub_.publish(p->applied);
    }
  } catch (const std::exception& e) {
    fatal_ = e.what();  // a creature it cannot disturb: run() ends with it
  }
}

bool DisturbanceNode::handOver() {
  ros::Time now;  // the sim time they are handed over at
  if (!linkPose(model_->links[0].name, now, true)) return false;
  if (!torque_.handed) {
    torque_.handed = true;
    if (stillToCome(torque_, now)) handTorque();
  }
  if (!push_.handed) {
    if (model_->findLink(draws_.force_link) < 0) {
      throw flapsim::InputError(description_key_ + " has no link '" + draws_.force_link + "'");
    }
    ros::Time stamp;
    const std::optional<flapsim::Pose> wing = linkPose(draws_.force_link, stamp, true);
    if (!wing) return false;
    push_.handed = true;
    if (stillToCome(push_, now)) handPush(*wing);
  }
  return true;
}

bool DisturbanceNode::stillToCome(const Pending& p, const ros::Time& now) const {
  if (p.time >= now.toSec() - flapsim::kWrenchStartTolerance) return true;
  ROS_ERROR_STREAM("disturbance: the " << p.what << " drawn at t = " << p.time
                                       << " s is not applied: sim time was already " << now.toSec()
                                       << " s when it could be handed over");
  return false;
}

std::optional<flapsim::Pose> DisturbanceNode::linkPose(const std::string& link, ros::Time& stamp,
                                                       bool loud) {
  flapsim::GetState state;
  state.request.model_name = params_.creature;
  state.request.link_name = link;
  if (!get_state_.call(state) || !state.response.success) {
    if (loud) {
      ROS_ERROR_STREAM("disturbance: no state of " << params_.creature << "::" << link << " from "
                                                   << params_.get_state_service << ": "
                                                   << state.response.status_message);
    }
    return std::nullopt;
  }
  stamp = state.response.header.stamp;
  return fromMsg(state.response.pose);  // the link frame in the world
}

bool DisturbanceNode::apply(flapsim::ApplyWrench& call, Pending& p) {
  call.request.model_name = params_.creature;
  call.request.start_time = ros::Time(p.time);
  if (!apply_wrench_.call(call) || !call.response.success) {
    ROS_ERROR_STREAM("disturbance: the " << p.what << " failed: " << call.response.status_message);
    return false;
  }
  p.applied.header.stamp = call.response.start_time;
  double step = 0.0;  // a step or more after the drawn time: the simulator had passed it
  if (nh_.getParam(step_size_key_, step) &&
      (call.response.start_time.toSec() - p.time) >= step - flapsim::kWrenchStartTolerance) {
    ROS_ERROR_STREAM("disturbance: the " << p.what << " drawn at t = " << p.time
                                         << " s starts late, at t = " << call.response.start_time
                                         << " s: the simulator had passed its time");
  }
  ROS_INFO_STREAM("disturbance: " << p.what << " drawn at t = " << p.time
                                  << " s: " << call.response.status_message << ", for "
                                  << call.request.duration.toSec() << " s");
  return true;
}

void DisturbanceNode::handTorque() {
  flapsim::ApplyWrench call;
  call.request.reference_frame = params_.creature;  // the root link's axes at the call
  call.request.wrench.torque.x = draws_.torque;
  call.request.duration = ros::Duration(draws_.torque_duration);
  if (!apply(call, torque_)) return;
  torque_.applied.header.frame_id = params_.creature + "/" + model_->links[0].name;
  torque_.applied.wrench.torque.x = draws_.torque;
}

void DisturbanceNode::handPush(const flapsim::Pose& wing) {
  const flapsim::Vec3 com = model_->links[model_->findLink(draws_.force_link)].urdfCom();
  const flapsim::Vec3 at = wing.apply(com);  // the link's centre of mass in the world
  flapsim::ApplyWrench call;
  call.request.body_name = draws_.force_link;  // reference_frame empty: the world
  call.request.reference_point.x = at.x();
  call.request.reference_point.y = at.y();
  call.request.reference_point.z = at.z();
  call.request.wrench.force.z = draws_.force;
  call.request.duration = ros::Duration(draws_.force_duration);
  if (!apply(call, push_)) return;
  // In the pushed link's frame as it was at the call, about its origin.
  const flapsim::Vec3 local = wing.orientation.conjugate() * flapsim::Vec3(0.0, 0.0, draws_.force);
  push_.applied.header.frame_id = params_.creature + "/" + draws_.force_link;
  push_.applied.wrench.force = vectorMsg(local);
  push_.applied.wrench.torque = vectorMsg(com.cross(local));
}

}  // namespace flapsim_ros
