#include "flapsim_ros/controller_nodes.h"

#include <geometry_msgs/TransformStamped.h>
#include <ros/names.h>

#include <cmath>
#include <stdexcept>

#include "flapsim_ros/conversions.h"
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

/// Subscribes `topic`, keeping its latest message in `slot` (under `mutex`).
template <typename M>
ros::Subscriber keepLatest(ros::NodeHandle& nh, const std::string& topic, std::mutex& mutex,
                           boost::shared_ptr<const M>& slot) {
  return nh.subscribe<M>(topic, 10,
                         boost::function<void(const boost::shared_ptr<const M>&)>(
                             [&mutex, &slot](const boost::shared_ptr<const M>& msg) {
                               std::lock_guard<std::mutex> lock(mutex);
                               slot = msg;
                             }));
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
      listener_(buffer_, nh),
      altimeter_rng_(static_cast<std::uint64_t>(params_.noise_seed)) {
  const std::string mismatch = annControllerMismatch(
      params_, spec_.params, pnh_.resolveName("attitude_source"), pnh_.resolveName("altitude"));
  if (!mismatch.empty()) throw ParamError(mismatch);
  controller_ = std::make_unique<flapsim::AnnWingController>(
      flapsim::FlapUnitController(spec_.params, spec_.weights));
  if (params_.rate <= 0.0) params_.rate = 1.0 / spec_.params.control_period;
  creatures_ = !params_.lockstep_creatures.empty() ? params_.lockstep_creatures
                                                   : std::vector<std::string>{params_.creature};
  for (const std::string& c : creatures_) {
    frames_.emplace_back();
    for (const auto& link : layout_.body_links) frames_.back().push_back(c + "/" + link);
  }
  simulator_ns_ = ros::names::parentNamespace(
      ros::names::parentNamespace(ros::names::resolve(params_.step_service)));
  readings_.resize(creatures_.size());
  filters_.assign(creatures_.size(), flapsim::AttitudeFilter(spec_.params.attitude_filter_time));
  if (params_.attitude_source == AttitudeSource::kTf && spec_.params.attitude_filter_time > 0.0) {
    ROS_WARN_STREAM("ann_controller: the attitude filter of "
                    << params_.weights_file << " is not applied to tf's exact attitude");
  }
  if (params_.attitude_source == AttitudeSource::kTf && spec_.params.velocity_gain > 0.0) {
    ROS_WARN_STREAM("ann_controller: the ground-speed damping of "
                    << params_.weights_file
                    << " is not applied with tf's attitude (it reads odom's twist)");
  }
  if (params_.attitude_source == AttitudeSource::kImu) subscribe();
  // Latched: the simulator holds sim time for the first command, which must not be lost if it
  // goes out before the simulator's subscription connects.
  pub_ = nh_.advertise<flapsim::WingCommand>("wing_command", 10, /*latch=*/true);
  if (params_.lockstep)
    start_srv_ = pnh_.advertiseService("start", &AnnControllerNode::onStart, this);
  ROS_INFO_STREAM(
      "ann_controller: "
      << params_.pairs << " unit(s) of '" << params_.creature << "' at " << params_.rate
      << " Hz, weights " << params_.weights_file << ", attitude from "
      << (params_.attitude_source == AttitudeSource::kImu ? subscribers_.front().getTopic()
                                                          : std::string("tf"))
      << (params_.attitude_source == AttitudeSource::kImu && spec_.params.attitude_filter_time > 0.0
              ? " through an attitude filter of " +
                    std::to_string(spec_.params.attitude_filter_time) + " s"
              : std::string())
      << (params_.attitude_source == AttitudeSource::kImu && spec_.params.velocity_gain > 0.0
              ? ", ground-speed damping " + std::to_string(spec_.params.velocity_gain) +
                    " rad per m/s from odom"
              : std::string())
      << (params_.altitude ? ", holding " + std::to_string(*params_.altitude) + " m"
                           : std::string(", climbing"))
      << (params_.lockstep ? ", lockstep" : ""));
}

void AnnControllerNode::subscribe() {
  for (size_t c = 0; c < creatures_.size(); ++c) {
    const std::string base = ros::names::append(simulator_ns_, creatures_[c]);
    Readings& r = readings_[c];  // readings_ is not resized after this
    subscribers_.push_back(keepLatest(nh_, base + "/imu", mutex_, r.imu));
    if (needsOdom()) {
      subscribers_.push_back(keepLatest(nh_, base + "/odom", mutex_, r.odom));
    }
    if (layout_.units() > 1) {
      subscribers_.push_back(keepLatest(nh_, base + "/joint_states", mutex_, r.joints));
    }
  }
}

std::optional<flapsim::FlapSensing> AnnControllerNode::sense(const ros::Time& stamp, size_t c) {
  std::optional<flapsim::FlapSensing> s =
      params_.attitude_source == AttitudeSource::kTf ? senseTf(stamp, c) : senseImu(stamp, c);
  if (s) s->setpoint = params_.altitude;
  return s;
}

std::optional<flapsim::FlapSensing> AnnControllerNode::senseTf(const ros::Time& stamp,
                                                               size_t c) const {
  std::vector<flapsim::Quat> out;
  double altitude = 0.0;
  for (const auto& frame : frames_[c]) {
    if (!buffer_.canTransform(params_.world_frame, frame, stamp)) return std::nullopt;
    const geometry_msgs::TransformStamped t =
        buffer_.lookupTransform(params_.world_frame, frame, stamp);
    const auto& r = t.transform.rotation;
    out.emplace_back(r.w, r.x, r.y, r.z);
    if (out.size() == 1) altitude = t.transform.translation.z;  // unit 0's body is the root
  }
  flapsim::FlapSensing s(out);
  s.altitude = altitude;
  return s;
}

std::optional<flapsim::FlapSensing> AnnControllerNode::senseImu(const ros::Time& stamp, size_t c) {
  Readings r;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    r = readings_[c];
  }
  // A reading of the wanted time (any, free running) of every sensor the network reads.
  auto fresh = [&](const auto& msg) {
    return msg && (stamp.isZero() || msg->header.stamp == stamp);
  };
  const bool need_odom = needsOdom(), need_joints = layout_.units() > 1;
  if (!fresh(r.imu) || (need_odom && !fresh(r.odom)) || (need_joints && !fresh(r.joints))) {
    return std::nullopt;
  }
  if (!r.model) {
    const std::string key = ros::names::append(simulator_ns_, creatures_[c]) + "/robot_description";
    std::string urdf;
    if (!nh_.getParam(key, urdf)) return std::nullopt;
    r.model = flapsim::parseCreatureModel(urdf, key);
    for (const auto& link : layout_.body_links) {
      const int b = r.model->findLink(link);
      if (b < 0) throw flapsim::InputError(key + " has no link '" + link + "'");
      r.bodies.push_back(b);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    readings_[c].model = r.model;
    readings_[c].bodies = r.bodies;
  }
  std::vector<double> q(r.model->joints.size(), 0.0), qd(q.size(), 0.0);
  if (need_joints) jointVectors(*r.joints, *r.model, q, qd);
  double altitude = need_odom ? r.odom->pose.pose.position.z : 0.0;
  if (need_odom && params_.altitude_noise > 0.0) {
    altitude += params_.altitude_noise * normal_(altimeter_rng_);
  }
  flapsim::ImuReading imu = fromMsg(*r.imu);
  imu.angular_velocity += params_.gyro_bias;  // as the core's episodes bias it, before the filter
  flapsim::FlapSensing s = flapsim::unitSensing(
      *r.model, r.bodies, filters_[c].updateAt(imu, r.imu->header.stamp.toNSec()), q, qd, altitude);
  if (need_odom) {  // odometry's twist is in the root's axes
    s.velocity =
        flapsim::groundSpeedReading(fromMsg(r.odom->twist.twist).linear, params_.velocity_noise,
                                    [this] { return normal_(altimeter_rng_); });
  }
  return s;
}

bool AnnControllerNode::needsOdom() const {
  return spec_.params.altitude_input || spec_.params.climb_input ||
         spec_.params.velocity_gain > 0.0;
}

std::string AnnControllerNode::missing(size_t c) const {
  if (params_.attitude_source == AttitudeSource::kTf) {
    return "transform " + params_.world_frame + " -> " + frames_[c].front() + " (or another unit)";
  }
  return "reading of " + ros::names::append(simulator_ns_, creatures_[c]) + "/imu" +
         (needsOdom() ? ", odom" : "") + (layout_.units() > 1 ? ", joint_states" : "") +
         " or its robot_description";
}

flapsim::WingCommand AnnControllerNode::command(const flapsim::FlapSensing& sensed,
                                                const ros::Time& stamp) const {
  flapsim::WingCommand msg = annCommandMsg(layout_, controller_->commands(sensed));
  msg.header.stamp = stamp;
  return msg;
}

void AnnControllerNode::onTimer(const ros::TimerEvent&) { answer(true); }

bool AnnControllerNode::answer(bool warn) {
  std::optional<flapsim::FlapSensing> s;
  try {
    s = sense(ros::Time(0), 0);
  } catch (const std::exception& e) {
    ROS_WARN_STREAM_THROTTLE(5.0, "ann_controller: " << e.what());
    return false;
  }
  if (!s) {
    if (warn) ROS_WARN_STREAM_THROTTLE(5.0, "ann_controller: no " << missing(0) << " yet");
    return false;
  }
  pub_.publish(command(*s, ros::Time::now()));
  answered_ = true;
  return true;
}

bool AnnControllerNode::onStart(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  started_ = true;
  return true;
}

bool AnnControllerNode::run() {
  if (params_.lockstep) return runLockstep();
  ros::Timer timer =
      nh_.createTimer(ros::Duration(1.0 / params_.rate), &AnnControllerNode::onTimer, this);
  first_answer_timer_ =
      nh_.createWallTimer(ros::WallDuration(0.02), [this](const ros::WallTimerEvent&) {
        if (answered_ || answer(false)) first_answer_timer_.stop();
      });
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
      std::optional<flapsim::FlapSensing> q;
      try {
        if (!lockstep.await([&] { return (q = sense(t, c)).has_value(); }, missing(c))) {
          return false;
        }
      } catch (const std::exception& e) {
        ROS_ERROR_STREAM("ann_controller: " << creatures_[c] << " at t = " << t << ": "
                                            << e.what());
        return false;
      }
      commands[c] = command(*q, t);
    }
    if (!lockstep.advance(creatures_, commands)) return false;
  }
  ROS_INFO_STREAM("ann_controller: lockstep done at t = " << lockstep.time());
  return true;
}

}  // namespace flapsim_ros
