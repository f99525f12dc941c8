#include "flapsim_ros/simulator_node.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/package.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>

#include "flapsim_ros/urdf_source.h"

namespace flapsim_ros {

namespace {

constexpr double kMaxPacingLag = 0.25;  // s (wall) behind schedule before pacing restarts
constexpr double kPausedPoll = 0.1;     // s (wall) longest callback wait (shutdown is seen)
constexpr double kRunSlice = 0.05;      // s (wall) of stepping between callback rounds
// Steps between checks of the wall time and shutdown: at most this many, and as many as take
// about kSliceTarget of wall time (one, for a slow step: a long chain on the ground).
constexpr std::uint64_t kSliceSteps = 10;
constexpr double kSliceTarget = 0.01;       // s (wall)
constexpr double kDiagnosticsPeriod = 1.0;  // s (wall) between unchanged diagnostics
constexpr double kPausedClockPeriod = 0.1;  // s (wall) between /clock messages while paused

}  // namespace

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : SimulatorNode(nh, pnh, loadNodeParams(pnh)) {}

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                             const NodeParams& params)
    : params_(params),
      nh_(nh),
      pnh_(pnh),
      world_(params.world),
      step_ns_(stepNanoseconds(params.world.step_size)),
      publish_every_(std::max<std::uint64_t>(
          1, static_cast<std::uint64_t>(
                 std::llround(1.0 / (params.publish_rate * params.world.step_size))))),
      paused_(params.paused),
      timeout_steps_(params.wing_command_timeout <= 0.0
                         ? 0
                         : std::max<std::uint64_t>(
                               1, static_cast<std::uint64_t>(std::llround(
                                      params.wing_command_timeout / params.world.step_size)))),
      imu_rng_(static_cast<std::uint64_t>(params.imu.seed)) {
  nh_.setCallbackQueue(&queue_);
  pnh_.setCallbackQueue(&queue_);
  for (const std::string& k : params_.unknown_keys) {
    ROS_WARN_STREAM("flapsim: ignoring unknown parameter '" << pnh_.resolveName(k) << "'");
  }

  // A new subscriber gets the current step's message at once: a paused world is seen.
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>(
      "/clock", publishQueueSize(params_),
      [this](const ros::SingleSubscriberPublisher& p) { p.publish(clockMsg()); });
  tf_ = std::make_unique<TfPublisher>(
      nh_, [this](const ros::Time& t) { return tfMsg(t); }, publishQueueSize(params_));
  marker_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>(
      "aero_markers", 2, [this](const ros::SingleSubscriberPublisher& p) {
        if (params_.markers.enabled) p.publish(aeroMarkerArray(now()));
      });
  view_marker_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>(
      "view_markers", 2,
      [this](const ros::SingleSubscriberPublisher& p) { p.publish(viewMarkerArray(now())); });
  creature_marker_pub_ =
      pnh_.advertise<visualization_msgs::MarkerArray>("creature_markers", 1, /*latch=*/true);
  diagnostics_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  states_pub_ = pnh_.advertise<flapsim::CreatureStates>(
      "creature_states", 10,
      [this](const ros::SingleSubscriberPublisher& p) { p.publish(creatureStatesMsg(now())); });
  advertiseServices();

  // Its callbacks run on queue_ (pnh_'s), between steps. The running values go in before the
  // callback: the node's parameters, not the cfg defaults, are what starts.
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<flapsim::FlapsimConfig>>(
      reconfigure_mutex_, pnh_);
  reconfigure_->updateConfig(runningConfig());
  reconfigure_->setCallback([this](flapsim::FlapsimConfig& config, std::uint32_t level) {
    onReconfigure(config, level);
  });

  spawnConfigured();
  ROS_INFO_STREAM("flapsim: " << creatures_.size() << " creature(s), step "
                              << params_.world.step_size << " s, publishing every "
                              << publish_every_ << " steps, real-time factor "
                              << params_.real_time_factor << (paused_ ? ", paused" : ""));
  publishCreatureMarkers();  // also with no creature: the latched topics say so
  publishStaticTransforms();
  publishAll();
}

SimulatorNode::~SimulatorNode() {
  for (const auto& c : creatures_) nh_.deleteParam(c->name + "/robot_description");
}

// ---- creatures ---------------------------------------------------------------------

void SimulatorNode::spawnConfigured() {
  for (const CreatureSpec& spec : params_.creatures) {
    const bool from_file = !spec.urdf_file.empty();
    const std::string text = from_file ? flapsim::readUrdfFile(spec.urdf_file) : spec.urdf_xml;
    const std::string source =
        from_file ? spec.urdf_file
                  : (spec.urdf_param.empty() ? "creature '" + spec.name + "' urdf_xml"
                                             : pnh_.resolveName(spec.urdf_param));
    spawn(spec.name, text, source, spec.pose, spec.twist);
    if (!spec.wing_command.empty()) {
      Creature* c = find(spec.name);
      WingCommandRequest r;
      r.strokes = spec.wing_command;
      if (r.strokes.size() == 1) r.strokes.assign(c->model->wing_joints.size(), r.strokes[0]);
      try {
        world_.setWingCommands(spec.name, r.joints, r.strokes);
      } catch (const flapsim::InputError& e) {
        throw ParamError("creature '" + spec.name + "' wing_command: " + e.what());
      }
      commanded(*c, r);
    }
    Creature* c = find(spec.name);
    c->controller = spec.controller;
    c->awaiting_controller =
        !spec.controller.empty() && !c->command && params_.controller_wait_timeout > 0.0;
  }
}

std::vector<std::string> SimulatorNode::spawn(const std::string& name, const std::string& urdf_xml,
                                              const std::string& source, const flapsim::Pose& pose,
                                              const flapsim::Twist& twist) {
  const std::string err = validateCreatureName(name);
  if (!err.empty()) throw flapsim::InputError(err);
  if (world_.has(name)) throw flapsim::InputError("creature name '" + name + "' is taken");
  if (urdf_xml.size() > flapsim::kMaxUrdfFileBytes) {  // a file's limit, for any URDF text
    throw flapsim::InputError(source + ": " + std::to_string(urdf_xml.size()) +
                              " bytes, over the limit of 16 MiB");
  }
  flapsim::CreatureModelPtr model = flapsim::parseCreatureModel(
      urdf_xml, source,
      spawnMeshResolver(params_.urdf_roots, source,
                        [](const std::string& package) { return ros::package::getPath(package); }));
  world_.spawn(name, model, pose, twist);
  auto c = std::make_unique<Creature>();
  c->nh = nh_;
  c->name = name;
  c->model = model;
  try {
    c->geometry = creatureMarkers(name, urdf_xml, source);
    advertiseCreature(*c, urdf_xml);
  } catch (const ros::Exception& e) {
    world_.remove(name);
    throw flapsim::InputError("creature '" + name + "': " + e.what());
  }
  creatures_.push_back(std::move(c));
  publishCreatureMarkers();
  publishStaticTransforms();
  std::vector<std::string> notes = flapsim::implicitJointValues(*model, params_.world.step_size);
  for (const std::string& line : flapsim::geometryNotes(*model)) notes.push_back(line);
  for (std::string& line : notes) {
    line = "creature '" + name + "', " + line;
    ROS_WARN_STREAM("flapsim: " << line);
  }
  return notes;
}

void SimulatorNode::advertiseCreature(Creature& c, const std::string& urdf_xml) {
  const std::string& name = c.name;
  c.description = c.nh.advertise<std_msgs::String>(name + "/robot_description", 1, true);
  std_msgs::String text;
  text.data = urdf_xml;
  c.description.publish(text);
  // A new subscriber gets the current step at once (a paused world is seen); by name: a
  // callback queued before a delete runs after it. A recorder may lag: publishQueueSize.
  const int queue = publishQueueSize(params_);
  c.joint_states = c.nh.advertise<sensor_msgs::JointState>(
      name + "/joint_states", queue, [this, name](const ros::SingleSubscriberPublisher& p) {
        if (const Creature* c = find(name))
          p.publish(jointStateMsg(*c->model, world_.state(name), now()));
      });
  c.odom = c.nh.advertise<nav_msgs::Odometry>(
      name + "/odom", queue, [this, name](const ros::SingleSubscriberPublisher& p) {
        if (const Creature* c = find(name)) {
          p.publish(odometryMsg(name, *c->model, world_.state(name), now(), params_.world_frame));
        }
      });
  c.imu = c.nh.advertise<sensor_msgs::Imu>(name + "/imu", queue,
                                           [this, name](const ros::SingleSubscriberPublisher& p) {
                                             if (const Creature* c = find(name))
                                               p.publish(imuMsgOf(*c, world_.state(name), now()));
                                           });
  c.power = std::make_unique<PowerPublisher>(c.nh, name, c.model, queue, [this, name] {
    return std::make_pair(find(name) ? world_.power(name) : flapsim::CreaturePower(), now());
  });
  c.wing_command = c.nh.subscribe<flapsim::WingCommand>(
      name + "/wing_command", 10,
      [this, name](const flapsim::WingCommand::ConstPtr& msg) { onWingCommand(name, msg); });
  nh_.setParam(name + "/robot_description", urdf_xml);
}

void SimulatorNode::remove(const std::string& name) {
  world_.remove(name);  // InputError if unknown
  auto it = std::find_if(creatures_.begin(), creatures_.end(),
                         [&](const auto& c) { return c->name == name; });
  if (it == creatures_.end()) return;
  (*it)->joint_states.shutdown();
  (*it)->odom.shutdown();
  (*it)->imu.shutdown();
  (*it)->power->shutdown();
  (*it)->wing_command.shutdown();
  (*it)->description.shutdown();
  nh_.deleteParam(name + "/robot_description");
  creatures_.erase(it);
  publishCreatureMarkers();
  publishStaticTransforms();
  tf_->forgetOlderThan(now());
}

SimulatorNode::Creature* SimulatorNode::find(const std::string& name) {
  for (auto& c : creatures_) {
    if (c->name == name) return c.get();
  }
  return nullptr;
}

void SimulatorNode::commanded(Creature& c, WingCommandRequest request) {
  c.command = std::move(request);
  c.command_step = world_.stepCount();
  c.command_lapsed = false;
  c.awaiting_controller = false;
  c.controller_missing = false;
}

// ---- stepping and publishing ---------------------------------------------------------

ros::Time SimulatorNode::now() const { return simTime(world_.stepCount(), step_ns_); }

std::uint64_t SimulatorNode::advance(std::uint64_t steps, double wall_budget) {
  const ros::WallTime start = ros::WallTime::now();
  std::uint64_t taken = 0;
  while (taken < steps && ros::ok()) {
    const std::uint64_t to_boundary = publish_every_ - world_.stepCount() % publish_every_;
    const std::uint64_t k = std::min({steps - taken, to_boundary, slice_steps_, stepsToTimeout()});
    world_.setRecordCellForces(params_.markers.enabled && params_.markers.per_cell &&
                               marker_pub_.getNumSubscribers() > 0);
    const ros::WallTime chunk_start = ros::WallTime::now();
    world_.step(static_cast<int>(k));
    const double per_step = (ros::WallTime::now() - chunk_start).toSec() / static_cast<double>(k);
    slice_steps_ = std::clamp<std::uint64_t>(
        per_step > 0.0 ? static_cast<std::uint64_t>(kSliceTarget / per_step) : kSliceSteps, 1,
        kSliceSteps);
    taken += k;
    applyTimeouts();
    reportDivergences();
    if (world_.stepCount() % publish_every_ == 0) publishAll();
    if (wall_budget > 0.0 && (ros::WallTime::now() - start).toSec() > wall_budget) break;
  }
  return taken;
}

std::uint64_t SimulatorNode::stepsToTimeout() const {
  std::uint64_t steps = UINT64_MAX;
  if (timeout_steps_ == 0) return steps;
  for (const auto& c : creatures_) {
    if (!c->command || c->command_lapsed) continue;
    const std::uint64_t due = c->command_step + timeout_steps_;
    steps = std::min(steps, due > world_.stepCount() ? due - world_.stepCount() : 1);
  }
  return steps;
}

void SimulatorNode::applyTimeouts() {
  if (timeout_steps_ == 0) return;
  bool lapsed = false;
  for (const auto& c : creatures_) {
    if (!c->command || c->command_lapsed || world_.stepCount() < c->command_step + timeout_steps_) {
      continue;
    }
    const bool hold = params_.wing_command_timeout_action == CommandTimeoutAction::kHold;
    for (int j : c->model->wing_joints) {
      const std::string& joint = c->model->joints[j].name;
      if (hold) {
        world_.holdJoint(c->name, joint);
      } else {
        world_.clearJointCommand(c->name, joint);
      }
    }
    c->command_lapsed = lapsed = true;
    warnThrottled("wing_command_timeout", c->name,
                  "creature '" + c->name + "': no wing command for " +
                      std::to_string(params_.wing_command_timeout) + " s of sim time (since t = " +
                      formatTime(simTime(c->command_step, step_ns_)) + " s): wings " +
                      (hold ? "held" : "released") + " until the next command");
  }
  if (lapsed) publishDiagnostics();
}

void SimulatorNode::reportDivergences() {
  const std::vector<flapsim::Divergence> frozen = world_.takeDivergences();
  for (const flapsim::Divergence& d : frozen) {
    ROS_ERROR_STREAM("flapsim: creature '"
                     << d.creature << "' diverged at step " << d.step
                     << " (t = " << formatTime(simTime(d.step, step_ns_)) << " s): " << d.quantity
                     << "; frozen at its last good state until flapsim/reset or flapsim/delete");
  }
  if (!frozen.empty()) publishDiagnostics();
}

sensor_msgs::Imu SimulatorNode::imuMsgOf(const Creature& c, const flapsim::CreatureState& s,
                                         const ros::Time& stamp) {
  const flapsim::ImuNoise noise{params_.imu.orientation_noise, params_.imu.angular_velocity_noise,
                                params_.imu.linear_acceleration_noise};
  return imuMsg(c.name, *c.model, s, world_.rootAcceleration(c.name), world_.params().gravity,
                stamp, noise, [this] { return imu_normal_(imu_rng_); });
}

void SimulatorNode::publishCreature(const Creature& c, const ros::Time& stamp) {
  c.power->publish(world_.power(c.name), stamp);
  publishCreatureState(c, stamp);
}

void SimulatorNode::publishCreatureState(const Creature& c, const ros::Time& stamp) {
  const bool need_js = c.joint_states.getNumSubscribers() > 0;
  const bool need_odom = c.odom.getNumSubscribers() > 0;
  const bool need_imu = c.imu.getNumSubscribers() > 0;
  if (!need_js && !need_odom && !need_imu) return;
  const flapsim::CreatureState s = world_.state(c.name);
  if (need_imu) c.imu.publish(imuMsgOf(c, s, stamp));
  if (need_js) c.joint_states.publish(jointStateMsg(*c.model, s, stamp));
  if (need_odom) c.odom.publish(odometryMsg(c.name, *c.model, s, stamp, params_.world_frame));
}

void SimulatorNode::updateView(const ros::Time& stamp) {
  if (creatures_.empty()) return;
  flapsim::Vec3 centroid = flapsim::Vec3::Zero();
  std::vector<flapsim::Vec3> origins;
  for (const auto& c : creatures_) {
    const flapsim::CreatureState s = world_.state(c->name);
    centroid += centreOfMass(*c->model, s);
    for (const flapsim::Pose& p : s.link_poses) origins.push_back(p.position);
  }
  view_.update(centroid / static_cast<double>(creatures_.size()), stamp.toSec());
  const double distance =
      cameraDistance(origins, view_.position(), params_.view, params_.view.distance);
  view_distance_.update(flapsim::Vec3(distance, 0.0, 0.0), stamp.toSec());
}

void SimulatorNode::publishAll() {
  const ros::Time stamp = now();
  clock_pub_.publish(clockMsg());
  updateView(stamp);
  for (const auto& c : creatures_) publishCreature(*c, stamp);
  if (tf_->wanted()) tf_->publish(tfMsg(stamp));
  if (states_pub_.getNumSubscribers() > 0) states_pub_.publish(creatureStatesMsg(stamp));
  if (params_.markers.enabled && marker_pub_.getNumSubscribers() > 0) {
    marker_pub_.publish(aeroMarkerArray(stamp));
  }
  if (view_marker_pub_.getNumSubscribers() > 0) view_marker_pub_.publish(viewMarkerArray(stamp));
  if ((ros::WallTime::now() - diagnostics_wall_).toSec() >= kDiagnosticsPeriod) {
    publishDiagnostics();
  }
  published_step_ = world_.stepCount();
}

rosgraph_msgs::Clock SimulatorNode::clockMsg() const {
  rosgraph_msgs::Clock clock;
  clock.clock = now();
  return clock;
}

tf2_msgs::TFMessage SimulatorNode::tfMsg(const ros::Time& stamp) const {
  tf2_msgs::TFMessage tf;
  for (const auto& c : creatures_) {
    auto t =
        movingTransforms(c->name, *c->model, world_.state(c->name), stamp, params_.world_frame);
    tf.transforms.insert(tf.transforms.end(), t.begin(), t.end());
  }
  tf.transforms.push_back(viewTransform(view_.position(), stamp, params_.world_frame));
  geometry_msgs::TransformStamped camera = tf.transforms.back();
  camera.child_frame_id = kCameraFrame;
  camera.transform =
      toTransformMsg(cameraPose(view_.position(), view_distance_.position().x(), params_.view));
  tf.transforms.push_back(camera);
  return tf;
}

visualization_msgs::MarkerArray SimulatorNode::aeroMarkerArray(const ros::Time& stamp) const {
  visualization_msgs::MarkerArray markers;
  markers.markers.emplace_back();
  markers.markers.back().header.stamp = stamp;
  markers.markers.back().header.frame_id = params_.world_frame;
  markers.markers.back().action = visualization_msgs::Marker::DELETEALL;
  for (const auto& c : creatures_) {
    auto m = aeroMarkers(c->name, world_.aeroForces(c->name), params_.markers, stamp,
                         params_.world_frame);
    markers.markers.insert(markers.markers.end(), m.begin(), m.end());
  }
  return markers;
}

visualization_msgs::MarkerArray SimulatorNode::viewMarkerArray(const ros::Time& stamp) const {
  visualization_msgs::MarkerArray markers;
  markers.markers.push_back(viewReadout(stamp, view_.position()));
  return markers;
}

flapsim::CreatureStates SimulatorNode::creatureStatesMsg(const ros::Time& stamp) const {
  flapsim::CreatureStates m;
  m.header.stamp = stamp;
  m.header.frame_id = params_.world_frame;
  for (const auto& c : creatures_) {
    const flapsim::CreatureState s = world_.state(c->name);
    m.name.push_back(c->name);
    m.pose.push_back(toMsg(s.link_poses.at(0)));
    m.twist.push_back(toMsg(s.link_twists.at(0)));
  }
  return m;
}

void SimulatorNode::publishCreatureMarkers() {
  visualization_msgs::MarkerArray markers;
  markers.markers.emplace_back();
  markers.markers.back().header.frame_id = params_.world_frame;
  markers.markers.back().action = visualization_msgs::Marker::DELETEALL;
  for (const auto& c : creatures_) {
    markers.markers.insert(markers.markers.end(), c->geometry.begin(), c->geometry.end());
  }
  creature_marker_pub_.publish(markers);
}

void SimulatorNode::publishStaticTransforms() {
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (const auto& c : creatures_) {
    auto t = fixedTransforms(c->name, *c->model, now());
    transforms.insert(transforms.end(), t.begin(), t.end());
  }
  tf_->publishStatic(transforms);
}

void SimulatorNode::restartPacing() {
  pace_wall_ = ros::WallTime::now();
  pace_step_ = world_.stepCount();
}

void SimulatorNode::run() {
  restartPacing();
  while (ros::ok()) {
    if (paused_ || holdForControllers()) {
      queue_.callAvailable(ros::WallDuration(kPausedPoll));
      tf_->serveNewSubscribers(now());
      // /clock goes on while paused: rospy's subscribers of one topic share a connection, so
      // `rostopic echo /clock` with use_sim_time may miss the message a new connection gets.
      if ((ros::WallTime::now() - clock_wall_).toSec() >= kPausedClockPeriod) {
        clock_wall_ = ros::WallTime::now();
        clock_pub_.publish(clockMsg());
      }
      continue;
    }
    advance(publish_every_ - world_.stepCount() % publish_every_, kRunSlice);
    queue_.callAvailable();
    if (paused_ || params_.real_time_factor <= 0.0) continue;
    const double sim_elapsed =
        static_cast<double>(world_.stepCount() - pace_step_) * params_.world.step_size;
    const ros::WallTime due =
        pace_wall_ + ros::WallDuration(sim_elapsed / params_.real_time_factor);
    ros::WallTime wall = ros::WallTime::now();
    if (wall > due + ros::WallDuration(kMaxPacingLag)) {
      restartPacing();  // too slow for this factor: run as fast as possible, don't burst
      continue;
    }
    while (ros::ok() && !paused_ && wall < due) {
      queue_.callAvailable(std::min(due - wall, ros::WallDuration(kPausedPoll)));
      wall = ros::WallTime::now();
    }
  }
}

void SimulatorNode::warnThrottled(const std::string& kind, const std::string& creature,
                                  const std::string& message) {
  // The cause holds no caller's text: a name that is not a creature's counts as none.
  const std::string& known = find(creature) ? creature : std::string();
  if (warnings_.allow(kind, known, ros::WallTime::now().toSec())) {
    ROS_WARN_STREAM("flapsim: " << message);
  } else {
    ROS_DEBUG_STREAM("flapsim: " << message);
  }
}

}  // namespace flapsim_ros
