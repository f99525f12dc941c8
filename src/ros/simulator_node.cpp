#include "flapsim_ros/simulator_node.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>

#include "flapsim_ros/urdf_source.h"

namespace flapsim_ros {

namespace {

constexpr double kMaxPacingLag = 0.25;  // s (wall) behind schedule before pacing restarts
constexpr double kPausedPoll = 0.1;     // s (wall) longest callback wait (shutdown is seen)
constexpr double kRunSlice = 0.05;      // s (wall) of stepping between callback rounds
// Steps between checks of the wall time and shutdown: at most this many, and as many as take
// about kSliceTarget of wall time (one, for a creature whose step is slow: a long chain on
// the ground).
constexpr std::uint64_t kSliceSteps = 10;
constexpr double kSliceTarget = 0.01;       // s (wall)
constexpr double kDiagnosticsPeriod = 1.0;  // s (wall) between unchanged diagnostics

std::string formatTime(const ros::Time& t) {
  std::ostringstream os;
  os.precision(9);
  os << std::fixed << t.toSec();
  return os.str();
}

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
      imu_rng_(static_cast<std::uint64_t>(params.imu.seed)) {
  nh_.setCallbackQueue(&queue_);
  pnh_.setCallbackQueue(&queue_);
  for (const std::string& k : params_.unknown_keys) {
    ROS_WARN_STREAM("flapsim: ignoring unknown parameter '" << pnh_.resolveName(k) << "'");
  }

  // A new subscriber gets the current step's message at once: a paused world is seen.
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>(
      "/clock", 10, [this](const ros::SingleSubscriberPublisher& p) { p.publish(clockMsg()); });
  tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>(
      "/tf", 100, [this](const ros::SingleSubscriberPublisher& p) { p.publish(tfMsg(now())); });
  marker_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>(
      "aero_markers", 2, [this](const ros::SingleSubscriberPublisher& p) {
        if (params_.markers.enabled) p.publish(aeroMarkerArray(now()));
      });
  creature_marker_pub_ =
      pnh_.advertise<visualization_msgs::MarkerArray>("creature_markers", 1, /*latch=*/true);
  diagnostics_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  states_pub_ = pnh_.advertise<flapsim::CreatureStates>(
      "creature_states", 10,
      [this](const ros::SingleSubscriberPublisher& p) { p.publish(creatureStatesMsg(now())); });
  services_.push_back(pnh_.advertiseService("reset", &SimulatorNode::onReset, this));
  services_.push_back(pnh_.advertiseService("pause", &SimulatorNode::onPause, this));
  services_.push_back(pnh_.advertiseService("unpause", &SimulatorNode::onUnpause, this));
  services_.push_back(pnh_.advertiseService("step", &SimulatorNode::onStep, this));
  services_.push_back(pnh_.advertiseService("spawn", &SimulatorNode::onSpawn, this));
  services_.push_back(pnh_.advertiseService("delete", &SimulatorNode::onDelete, this));
  services_.push_back(pnh_.advertiseService("get_state", &SimulatorNode::onGetState, this));
  services_.push_back(pnh_.advertiseService("set_state", &SimulatorNode::onSetState, this));
  services_.push_back(pnh_.advertiseService("apply_wrench", &SimulatorNode::onApplyWrench, this));
  services_.push_back(
      pnh_.advertiseService("clear_wrenches", &SimulatorNode::onClearWrenches, this));

  // Its callbacks run on queue_ (pnh_'s), between steps. The running values go in before the
  // callback: the node's parameters, not the cfg defaults, are what starts.
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<flapsim::FlapsimConfig>>(
      reconfigure_mutex_, pnh_);
  reconfigure_->updateConfig(runningConfig());
  reconfigure_->setCallback([this](flapsim::FlapsimConfig& config, std::uint32_t level) {
    onReconfigure(config, level);
  });

  for (const CreatureSpec& spec : params_.creatures) {
    const bool from_file = !spec.urdf_file.empty();
    const std::string text = from_file ? flapsim::readUrdfFile(spec.urdf_file) : spec.urdf_xml;
    const std::string source =
        from_file ? spec.urdf_file
                  : (spec.urdf_param.empty() ? "creature '" + spec.name + "' urdf_xml"
                                             : pnh_.resolveName(spec.urdf_param));
    spawn(spec.name, text, source, spec.pose, spec.twist);
    if (!spec.wing_command.empty()) {
      const size_t wings = find(spec.name)->model->wing_joints.size();
      WingCommandRequest r;
      r.strokes = spec.wing_command;
      if (r.strokes.size() == 1) r.strokes.assign(wings, spec.wing_command[0]);
      try {
        world_.setWingCommands(spec.name, r.joints, r.strokes);
      } catch (const flapsim::InputError& e) {
        throw ParamError("creature '" + spec.name + "' wing_command: " + e.what());
      }
      find(spec.name)->command = r;
    }
  }
  ROS_INFO_STREAM("flapsim: " << creatures_.size() << " creature(s), step "
                              << params_.world.step_size << " s, publishing every "
                              << publish_every_ << " steps, real-time factor "
                              << params_.real_time_factor << (paused_ ? ", paused" : ""));
  publishCreatureMarkers();
  publishAll();
}

SimulatorNode::~SimulatorNode() {
  for (const auto& c : creatures_) nh_.deleteParam(c->name + "/robot_description");
}

// ---- creatures ---------------------------------------------------------------------

std::vector<std::string> SimulatorNode::spawn(const std::string& name, const std::string& urdf_xml,
                                              const std::string& source, const flapsim::Pose& pose,
                                              const flapsim::Twist& twist) {
  const std::string err = validateCreatureName(name);
  if (!err.empty()) throw flapsim::InputError(err);
  if (world_.has(name)) throw flapsim::InputError("creature name '" + name + "' is taken");
  flapsim::CreatureModelPtr model = flapsim::parseCreatureModel(urdf_xml, source);
  world_.spawn(name, model, pose, twist);
  auto c = std::make_unique<Creature>();
  c->nh = nh_;
  c->name = name;
  c->model = model;
  try {
    c->geometry = creatureMarkers(name, urdf_xml, source);
    c->description = c->nh.advertise<std_msgs::String>(name + "/robot_description", 1, true);
    std_msgs::String text;
    text.data = urdf_xml;
    c->description.publish(text);
    c->joint_states = c->nh.advertise<sensor_msgs::JointState>(name + "/joint_states", 10);
    c->odom = c->nh.advertise<nav_msgs::Odometry>(name + "/odom", 10);
    c->imu = c->nh.advertise<sensor_msgs::Imu>(name + "/imu", 10);
    c->power = std::make_unique<PowerPublisher>(c->nh, name, model);
    c->wing_command = c->nh.subscribe<flapsim::WingCommand>(
        name + "/wing_command", 10,
        [this, name](const flapsim::WingCommand::ConstPtr& msg) { onWingCommand(name, msg); });
    nh_.setParam(name + "/robot_description", urdf_xml);
  } catch (const ros::Exception& e) {
    world_.remove(name);
    throw flapsim::InputError("creature '" + name + "': " + e.what());
  }
  creatures_.push_back(std::move(c));
  publishCreatureMarkers();
  std::vector<std::string> capped = flapsim::cappedJointValues(*model, params_.world.step_size);
  for (std::string& line : capped) {
    line = "creature '" + name + "', " + line;
    ROS_WARN_STREAM("flapsim: " << line);
  }
  return capped;
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
}

SimulatorNode::Creature* SimulatorNode::find(const std::string& name) {
  for (auto& c : creatures_) {
    if (c->name == name) return c.get();
  }
  return nullptr;
}

// ---- stepping and publishing ---------------------------------------------------------

ros::Time SimulatorNode::now() const { return simTime(world_.stepCount(), step_ns_); }

std::uint64_t SimulatorNode::advance(std::uint64_t steps, double wall_budget) {
  const ros::WallTime start = ros::WallTime::now();
  std::uint64_t taken = 0;
  while (taken < steps && ros::ok()) {
    const std::uint64_t to_boundary = publish_every_ - world_.stepCount() % publish_every_;
    const std::uint64_t k = std::min({steps - taken, to_boundary, slice_steps_});
    world_.setRecordCellForces(params_.markers.enabled && params_.markers.per_cell &&
                               marker_pub_.getNumSubscribers() > 0);
    const ros::WallTime chunk_start = ros::WallTime::now();
    world_.step(static_cast<int>(k));
    const double per_step = (ros::WallTime::now() - chunk_start).toSec() / static_cast<double>(k);
    slice_steps_ = std::clamp<std::uint64_t>(
        per_step > 0.0 ? static_cast<std::uint64_t>(kSliceTarget / per_step) : kSliceSteps, 1,
        kSliceSteps);
    taken += k;
    reportDivergences();
    if (world_.stepCount() % publish_every_ == 0) publishAll();
    if (wall_budget > 0.0 && (ros::WallTime::now() - start).toSec() > wall_budget) break;
  }
  return taken;
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

void SimulatorNode::publishDiagnostics() {
  diagnostics_wall_ = ros::WallTime::now();
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = now();
  for (const auto& c : creatures_) {
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "flapsim: " + c->name;
    s.hardware_id = c->name;
    const std::optional<flapsim::Divergence> d = world_.divergence(c->name);
    if (d) {
      s.level = diagnostic_msgs::DiagnosticStatus::ERROR;
      s.message = "frozen: diverged at step " + std::to_string(d->step) + ": " + d->quantity;
    } else {
      s.level = diagnostic_msgs::DiagnosticStatus::OK;
      s.message = "running";
    }
    array.status.push_back(s);
  }
  diagnostics_pub_.publish(array);
}

void SimulatorNode::publishCreature(const Creature& c, const ros::Time& stamp,
                                    std::vector<geometry_msgs::TransformStamped>* tf) {
  const bool need_tf = tf != nullptr;
  const bool need_js = c.joint_states.getNumSubscribers() > 0;
  const bool need_odom = c.odom.getNumSubscribers() > 0;
  const bool need_imu = c.imu.getNumSubscribers() > 0;
  c.power->publish(world_.power(c.name), stamp);
  if (!need_tf && !need_js && !need_odom && !need_imu) return;
  const flapsim::CreatureState s = world_.state(c.name);
  if (need_imu) {
    const ImuNoise noise{params_.imu.angular_velocity_noise, params_.imu.linear_acceleration_noise};
    c.imu.publish(imuMsg(c.name, *c.model, s, world_.rootAcceleration(c.name),
                         world_.params().gravity, stamp, noise,
                         [this] { return imu_normal_(imu_rng_); }));
  }
  if (need_js) c.joint_states.publish(jointStateMsg(*c.model, s, stamp));
  if (need_odom) c.odom.publish(odometryMsg(c.name, *c.model, s, stamp, params_.world_frame));
  if (need_tf) {
    auto t = linkTransforms(c.name, *c.model, s, stamp, params_.world_frame);
    tf->insert(tf->end(), t.begin(), t.end());
  }
}

void SimulatorNode::publishAll() {
  const ros::Time stamp = now();
  clock_pub_.publish(clockMsg());

  flapsim::Vec3 centroid = flapsim::Vec3::Zero();
  for (const auto& c : creatures_) centroid += centreOfMass(*c->model, world_.state(c->name));
  if (!creatures_.empty())
    view_.update(centroid / static_cast<double>(creatures_.size()), stamp.toSec());

  const bool need_tf = tf_pub_.getNumSubscribers() > 0;
  tf2_msgs::TFMessage tf;
  for (const auto& c : creatures_) publishCreature(*c, stamp, need_tf ? &tf.transforms : nullptr);
  if (need_tf) {
    tf.transforms.push_back(viewTransform(view_.position(), stamp, params_.world_frame));
    tf_pub_.publish(tf);
  }
  if (states_pub_.getNumSubscribers() > 0) states_pub_.publish(creatureStatesMsg(stamp));
  if (params_.markers.enabled && marker_pub_.getNumSubscribers() > 0) {
    marker_pub_.publish(aeroMarkerArray(stamp));
  }
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
    auto t = linkTransforms(c->name, *c->model, world_.state(c->name), stamp, params_.world_frame);
    tf.transforms.insert(tf.transforms.end(), t.begin(), t.end());
  }
  tf.transforms.push_back(viewTransform(view_.position(), stamp, params_.world_frame));
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

void SimulatorNode::restartPacing() {
  pace_wall_ = ros::WallTime::now();
  pace_step_ = world_.stepCount();
}

void SimulatorNode::run() {
  restartPacing();
  while (ros::ok()) {
    if (paused_) {
      queue_.callAvailable(ros::WallDuration(kPausedPoll));
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
  if (warnings_.allow(kind, creature, ros::WallTime::now().toSec())) {
    ROS_WARN_STREAM("flapsim: " << message);
  } else {
    ROS_DEBUG_STREAM("flapsim: " << message);
  }
}

// ---- callbacks -----------------------------------------------------------------------

void SimulatorNode::onWingCommand(const std::string& creature,
                                  const flapsim::WingCommand::ConstPtr& msg) {
  try {
    WingCommandRequest r = fromMsg(*msg);
    world_.setWingCommands(creature, r.joints, r.strokes);
    if (Creature* c = find(creature)) c->command = std::move(r);
  } catch (const flapsim::InputError& e) {
    warnThrottled("wing_command/" + WarningLimiter::kindOf(e.what()), creature,
                  "rejected wing command for '" + creature + "': " + e.what() +
                      " (keeping the previous command)");
  }
}

bool SimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  world_.reset();
  for (const auto& c : creatures_) {
    if (!c->command) continue;
    try {
      world_.setWingCommands(c->name, c->command->joints, c->command->strokes);
    } catch (const flapsim::InputError& e) {
      warnThrottled("reset", c->name, "after reset: " + std::string(e.what()));
    }
  }
  restartPacing();
  ROS_INFO("flapsim: reset, sim time 0");
  publishAll();
  publishDiagnostics();
  return true;
}

bool SimulatorNode::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = true;
  return true;
}

bool SimulatorNode::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = false;
  restartPacing();
  return true;
}

void SimulatorNode::applyWingCommands(const std::vector<std::string>& creatures,
                                      const std::vector<flapsim::WingCommand>& commands) {
  // All checked first, so that no creature is commanded unless all can be.
  const std::vector<WingCommandRequest> requests =
      checkStepCommands(creatures, commands, [this](const std::string& name) {
        const Creature* c = find(name);
        return c ? c->model : nullptr;
      });
  for (size_t i = 0; i < creatures.size(); ++i) {
    world_.setWingCommands(creatures[i], requests[i].joints, requests[i].strokes);
  }
  for (size_t i = 0; i < creatures.size(); ++i) find(creatures[i])->command = requests[i];
}

bool SimulatorNode::onStep(flapsim::Step::Request& req, flapsim::Step::Response& res) {
  res.sim_time = now();
  if (!paused_) {
    res.success = false;
    res.status_message = "flapsim is running: call flapsim/pause before flapsim/step";
    warnThrottled("step/running", "", "step refused: " + res.status_message);
    return true;
  }
  if (req.steps > static_cast<std::uint32_t>(params_.max_steps_per_call)) {
    res.success = false;
    res.status_message = "steps " + std::to_string(req.steps) + " is over max_steps_per_call " +
                         std::to_string(params_.max_steps_per_call) +
                         " (parameter ~max_steps_per_call): no step taken";
    warnThrottled("step/max_steps_per_call", "", "step refused: " + res.status_message);
    return true;
  }
  try {
    applyWingCommands(req.creatures, req.wing_commands);
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = std::string("wing commands refused, no step taken: ") + e.what();
    warnThrottled("step/" + WarningLimiter::kindOf(e.what()), "",
                  "step refused: " + res.status_message);
    return true;
  }
  published_step_ = UINT64_MAX;
  const std::uint64_t taken = advance(req.steps);
  if (published_step_ != world_.stepCount()) publishAll();
  res.sim_time = now();
  res.success = taken == req.steps;
  res.status_message = (res.success ? "stepped " : "shutting down: stopped after ") +
                       std::to_string(taken) + " steps at t = " + formatTime(res.sim_time) + " s";
  return true;
}

bool SimulatorNode::onSpawn(flapsim::SpawnCreature::Request& req,
                            flapsim::SpawnCreature::Response& res) {
  try {
    if (req.urdf_xml.empty() == req.urdf_file.empty()) {
      throw flapsim::InputError("spawn '" + req.name +
                                "': give exactly one of urdf_xml and urdf_file");
    }
    const bool from_file = !req.urdf_file.empty();
    const std::vector<std::string> capped =
        spawn(req.name, from_file ? readSpawnUrdf(req.urdf_file, params_.urdf_roots) : req.urdf_xml,
              from_file ? req.urdf_file : "spawn request '" + req.name + "'",
              fromMsg(req.initial_pose), fromMsg(req.initial_twist));
    Creature* c = find(req.name);
    tf2_msgs::TFMessage tf;
    publishCreature(*c, now(), &tf.transforms);
    tf_pub_.publish(tf);
    res.success = true;
    res.status_message = "spawned '" + req.name + "': " + std::to_string(c->model->links.size()) +
                         " links, " + std::to_string(c->model->wing_joints.size()) + " wing joints";
    ROS_INFO_STREAM("flapsim: " << res.status_message);  // the lines below were warned
    for (const std::string& line : capped) res.status_message += "; " + line;
    publishDiagnostics();
  } catch (const std::bad_alloc&) {
    res.success = false;
    res.status_message = "spawn '" + req.name + "': out of memory while reading or building it";
    warnThrottled("spawn/out_of_memory", "", "spawn refused: " + res.status_message);
  } catch (const std::exception& e) {  // InputError, ModelError
    res.success = false;
    res.status_message = e.what();
    warnThrottled("spawn/" + WarningLimiter::kindOf(e.what()), "",
                  "spawn refused: " + res.status_message);
  }
  return true;
}

bool SimulatorNode::onDelete(flapsim::DeleteCreature::Request& req,
                             flapsim::DeleteCreature::Response& res) {
  try {
    remove(req.name);
    res.success = true;
    res.status_message = "deleted '" + req.name + "'";
    ROS_INFO_STREAM("flapsim: " << res.status_message);
    publishDiagnostics();
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = e.what();
    warnThrottled("delete", "", "delete refused: " + res.status_message);
  }
  return true;
}

bool SimulatorNode::onGetState(flapsim::GetState::Request& req, flapsim::GetState::Response& res) {
  res.header.stamp = now();
  res.header.frame_id = params_.world_frame;
  const Creature* c = find(req.name);
  const int link = !c ? -1 : req.link.empty() ? 0 : c->model->findLink(req.link);
  if (link < 0) {
    res.success = false;
    res.status_message = !c ? "unknown creature '" + req.name + "'"
                            : "creature '" + req.name + "' has no link '" + req.link + "'";
    warnThrottled("get_state", req.name, "get_state refused: " + res.status_message);
    return true;
  }
  const flapsim::CreatureState s = world_.state(req.name);
  res.pose = toMsg(s.link_poses.at(link));
  res.twist = toMsg(s.link_twists.at(link));
  const sensor_msgs::JointState joints = jointStateMsg(*c->model, s, res.header.stamp);
  res.joint_names = joints.name;
  res.joint_positions = joints.position;
  res.joint_velocities = joints.velocity;
  res.success = true;
  res.status_message = "state of '" + req.name + "' link '" + c->model->links[link].name + "'";
  return true;
}

bool SimulatorNode::onSetState(flapsim::SetState::Request& req, flapsim::SetState::Response& res) {
  try {
    const Creature* c = find(req.name);
    if (!c) throw flapsim::InputError("unknown creature '" + req.name + "'");
    flapsim::StateRequest r;
    try {
      r = stateRequest(*c->model, world_.state(req.name), req);
    } catch (const flapsim::InputError& e) {
      throw flapsim::InputError("creature '" + req.name + "': " + e.what());
    }
    world_.setState(req.name, r);
    res.success = true;
    res.status_message = "set the state of '" + req.name + "' at t = " + formatTime(now()) + " s";
    published_step_ = UINT64_MAX;
    publishAll();
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = std::string("set_state refused, nothing changed: ") + e.what();
    warnThrottled("set_state/" + WarningLimiter::kindOf(e.what()), req.name, res.status_message);
  }
  return true;
}

bool SimulatorNode::onApplyWrench(flapsim::ApplyWrench::Request& req,
                                  flapsim::ApplyWrench::Response& res) {
  try {
    world_.applyWrench(req.name, fromMsg(req));
    res.success = true;
    res.status_message = "wrench on '" + req.name + "'" +
                         (req.link.empty() ? "" : " link '" + req.link + "'") +
                         " from t = " + formatTime(now()) + " s";
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = std::string("apply_wrench refused: ") + e.what();
    warnThrottled("apply_wrench/" + WarningLimiter::kindOf(e.what()), req.name, res.status_message);
  }
  return true;
}

bool SimulatorNode::onClearWrenches(flapsim::ClearWrenches::Request& req,
                                    flapsim::ClearWrenches::Response& res) {
  try {
    const int n = world_.clearWrenches(req.name, req.link);
    res.success = true;
    res.status_message = "cleared " + std::to_string(n) + " wrench(es)";
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = std::string("clear_wrenches refused: ") + e.what();
    warnThrottled("clear_wrenches/" + WarningLimiter::kindOf(e.what()), req.name,
                  res.status_message);
  }
  return true;
}

flapsim::FlapsimConfig SimulatorNode::runningConfig() const {
  flapsim::FlapsimConfig c;
  c.real_time_factor = params_.real_time_factor;
  c.publish_rate = params_.publish_rate;
  const flapsim::AirParams& air = world_.params().air;
  c.wind_x = air.wind.x();
  c.wind_y = air.wind.y();
  c.wind_z = air.wind.z();
  c.density = air.density;
  c.drag_coefficient = air.drag_coefficient;
  const flapsim::Vec3& g = world_.params().gravity;
  c.gravity_x = g.x();
  c.gravity_y = g.y();
  c.gravity_z = g.z();
  c.show_markers = params_.markers.enabled;
  return c;
}

void SimulatorNode::onReconfigure(flapsim::FlapsimConfig& config, std::uint32_t) {
  try {
    if (!std::isfinite(config.real_time_factor) ||
        (config.real_time_factor != 0.0 &&
         (config.real_time_factor < 1e-3 || config.real_time_factor > 1e6))) {
      throw flapsim::InputError(
          "real_time_factor must be 0 (as fast as possible) or in [0.001, 1e6]");
    }
    if (!(config.publish_rate >= 0.01 && config.publish_rate <= 1e6)) {
      throw flapsim::InputError("publish_rate must be in [0.01, 1e6] Hz");
    }
    flapsim::AirParams air = world_.params().air;
    air.wind = flapsim::Vec3(config.wind_x, config.wind_y, config.wind_z);
    air.density = config.density;
    air.drag_coefficient = config.drag_coefficient;
    const flapsim::Vec3 gravity(config.gravity_x, config.gravity_y, config.gravity_z);
    if (!gravity.allFinite() || gravity.norm() > flapsim::kMaxGravity) {
      throw flapsim::InputError("gravity must be finite and at most 1e4 m/s^2");
    }
    world_.setAirParams(air);  // checked first: InputError names the culprit
    world_.setGravity(gravity);
    params_.world.air = air;
    params_.world.gravity = gravity;
    params_.real_time_factor = config.real_time_factor;
    params_.publish_rate = config.publish_rate;
    publish_every_ = std::max<std::uint64_t>(
        1, static_cast<std::uint64_t>(
               std::llround(1.0 / (params_.publish_rate * params_.world.step_size))));
    params_.markers.enabled = config.show_markers;
    restartPacing();
    ROS_INFO_STREAM("flapsim: reconfigured at t = "
                    << formatTime(now()) << " s: real-time factor " << params_.real_time_factor
                    << ", publishing every " << publish_every_ << " steps, wind ["
                    << air.wind.transpose() << "] m/s, density " << air.density
                    << ", drag coefficient " << air.drag_coefficient << ", gravity ["
                    << gravity.transpose() << "], markers "
                    << (config.show_markers ? "on" : "off"));
  } catch (const flapsim::InputError& e) {
    warnThrottled("reconfigure/" + WarningLimiter::kindOf(e.what()), "",
                  std::string("reconfigure refused, nothing changed: ") + e.what());
    config = runningConfig();
  }
}

}  // namespace flapsim_ros
