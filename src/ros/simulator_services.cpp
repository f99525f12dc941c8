// The simulator node's services and topic callbacks (SimulatorNode, continued): they run on
// the node's queue between steps.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "flapsim_ros/reconfigure_bounds.h"
#include "flapsim_ros/request_names.h"
#include "flapsim_ros/simulator_node.h"
#include "flapsim_ros/urdf_source.h"

namespace flapsim_ros {
namespace {

// A vector's components, to tie to a config's x, y and z.
std::tuple<double, double, double> xyz(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

constexpr double kGroundTolerance = 1e-3;  // m below the ground before a reply says so

// How far a creature's collision shapes reach below the ground, if they do ("" if not).
std::string belowGround(const flapsim::CreatureModel& model, const flapsim::CreatureState& state,
                        bool ground) {
  const double lowest = flapsim::lowestBoxPoint(model, state.link_poses);
  if (!ground || lowest >= -kGroundTolerance) return "";
  std::ostringstream below;
  below << "its collision shapes reach " << -lowest
        << " m below the ground (z = 0): the contact will push it out";
  return below.str();
}

}  // namespace

template <class Response>
void SimulatorNode::refuse(Response& res, const std::string& refusal, const std::string& creature,
                           const flapsim::InputError& e) {
  res.success = false;
  res.status_message = refusal + e.what();
  warnThrottled(refusal.substr(0, refusal.find(' ')) + "/" + WarningLimiter::kindOf(e.what()),
                creature, res.status_message);
}

template <class Response, class Body>
bool SimulatorNode::serve(Response& res, const std::string& refusal, const std::string& creature,
                          Body body) {
  try {
    body();
    res.success = true;
  } catch (const flapsim::InputError& e) {
    refuse(res, refusal, creature, e);
  }
  return true;
}

void SimulatorNode::advertiseServices() {
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
  services_.push_back(pnh_.advertiseService("get_physics", &SimulatorNode::onGetPhysics, this));
  services_.push_back(pnh_.advertiseService("set_physics", &SimulatorNode::onSetPhysics, this));
  launch_config_ = runningConfig();  // what reset restores
}

void SimulatorNode::onWingCommand(const std::string& creature,
                                  const flapsim::WingCommand::ConstPtr& msg) {
  try {
    WingCommandRequest r = fromMsg(*msg);
    world_.setWingCommands(creature, r.joints, r.strokes);
    Creature* c = find(creature);
    if (!c) return;
    commanded(*c, std::move(r));
    // Controllers stamp a command with the state it answers: its age is their lag.
    const double lag =
        msg->header.stamp.isZero() ? 0.0 : std::max(0.0, (now() - msg->header.stamp).toSec());
    const bool was_lagging = c->command_lag > kCommandLagWarning;
    c->command_lag = lag;
    if (lag > kCommandLagWarning) {
      warnThrottled("wing_command/lag", creature,
                    "creature '" + creature + "': its wing command answers a state " +
                        formatTime(ros::Time(lag)) +
                        " s of sim time old: its controller falls behind " +
                        "(lower the real-time factor, or run it in lockstep)");
    }
    if (was_lagging != (lag > kCommandLagWarning)) publishDiagnostics();
  } catch (const flapsim::InputError& e) {
    warnThrottled("wing_command/" + WarningLimiter::kindOf(e.what()), creature,
                  "rejected wing command for '" + creature + "': " + e.what() +
                      " (keeping the previous command)");
  }
}

bool SimulatorNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  try {
    applyConfig(launch_config_);  // the physics the node started with
  } catch (const flapsim::InputError& e) {
    warnThrottled("reset", "", "reset keeps the running physics: " + std::string(e.what()));
  }
  reconfigure_->updateConfig(runningConfig());
  world_.reset();
  tf_->clear();  // time starts again: listeners that see it jump back clear their buffers
  for (const auto& c : creatures_) {
    c->command_step = 0;
    c->command_lapsed = false;
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
  // Every subscriber sees the step it stays at (paused between publications, it would not).
  if (published_step_ != world_.stepCount()) publishAll();
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
  for (size_t i = 0; i < creatures.size(); ++i) commanded(*find(creatures[i]), requests[i]);
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
    adoptGazeboNames(req);
    if (req.urdf_xml.empty() == req.urdf_file.empty()) {
      throw flapsim::InputError("spawn '" + req.name +
                                "': give exactly one of model_xml (urdf_xml) and urdf_file");
    }
    const bool from_file = !req.urdf_file.empty();
    const std::vector<std::string> capped =
        spawn(req.name, from_file ? readSpawnUrdf(req.urdf_file, params_.urdf_roots) : req.urdf_xml,
              from_file ? req.urdf_file : "spawn request '" + req.name + "'",
              fromMsg(req.initial_pose), fromMsg(req.initial_twist));
    Creature* c = find(req.name);
    if (tf_->wanted()) tf_->publish(tfMsg(now()));  // the new creature's frames
    res.success = true;
    res.status_message = "spawned '" + req.name + "': " + std::to_string(c->model->links.size()) +
                         " links, " + std::to_string(c->model->wing_joints.size()) + " wing joints";
    ROS_INFO_STREAM("flapsim: " << res.status_message);  // the lines below were warned
    for (const std::string& line : capped) res.status_message += "; " + line;
    const std::string below = belowGround(*c->model, world_.state(req.name), params_.world.ground);
    if (!below.empty()) {  // spawned as asked, as set_state does
      res.status_message += "; " + below;
      warnThrottled("spawn/below_ground", req.name, "spawn: " + res.status_message);
    }
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
    adoptGazeboNames(req);
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

SimulatorNode::ReferenceFrame SimulatorNode::referenceFrame(const std::string& name,
                                                            const std::string& creature) {
  if (name.empty() || name == params_.world_frame) return ReferenceFrame();
  std::string owner = name, link;  // a creature name has no '/' and no ':'
  size_t at = name.find("::"), length = 2;
  if (at == std::string::npos) at = name.find('/'), length = 1;
  const Creature* asked = find(creature);
  if (at != std::string::npos) {
    owner = name.substr(0, at);
    link = name.substr(at + length);
  } else if (asked && asked->model->findFrame(name).link >= 0) {
    owner = creature;  // a link of the creature asked about
    link = name;
  }
  const Creature* c = find(owner);
  // 'fu/' and 'fu::' name no link (they were taken as fu's root).
  const bool no_link = at != std::string::npos && link.empty();
  const flapsim::CreatureState s = c && !no_link ? world_.state(owner) : flapsim::CreatureState();
  FrameMotion motion;
  if (!c || no_link || !flapsim::frameMotion(*c->model, s, link, &motion.pose, &motion.twist)) {
    throw flapsim::InputError("unknown reference_frame '" + name + "' (give '' or '" +
                              params_.world_frame + "', a creature, '<creature>/<link>' or a " +
                              "link of '" + creature + "')");
  }
  return ReferenceFrame{linkFrame(owner, link.empty() ? c->model->links[0].name : link), owner,
                        motion};
}

bool SimulatorNode::onGetState(flapsim::GetState::Request& req, flapsim::GetState::Response& res) {
  res.header.stamp = now();
  res.header.frame_id = params_.world_frame;
  return serve(res, "get_state refused: ", req.name, [&] {
    adoptGazeboNames(req);
    const Creature* c = find(req.name);
    if (!c) throw flapsim::InputError("unknown creature '" + req.name + "'");
    const ReferenceFrame frame = referenceFrame(req.reference_frame, req.name);
    const flapsim::CreatureState s = world_.state(req.name);
    FrameMotion m;  // a link's, or a lumped link's (fixed to the link it is lumped into)
    if (!flapsim::frameMotion(*c->model, s, req.link, &m.pose, &m.twist)) {
      throw flapsim::InputError("creature '" + req.name + "' has no link '" + req.link + "'");
    }
    if (!frame.name.empty()) {
      m = toFrame(frame.motion, m);
      res.header.frame_id = frame.name;
    }
    res.pose = toMsg(m.pose);
    res.twist = toMsg(m.twist);
    const sensor_msgs::JointState joints = jointStateMsg(*c->model, s, res.header.stamp);
    res.joint_names = joints.name;
    res.joint_positions = joints.position;
    res.joint_velocities = joints.velocity;
    res.status_message = "state of '" + req.name + "' link '" +
                         (req.link.empty() ? c->model->links[0].name : req.link) + "'" +
                         (frame.name.empty() ? "" : " in " + frame.name);
  });
}

bool SimulatorNode::onSetState(flapsim::SetState::Request& req, flapsim::SetState::Response& res) {
  return serve(res, "set_state refused, nothing changed: ", req.name, [&] {
    adoptGazeboNames(req);
    const Creature* c = find(req.name);
    if (!c) throw flapsim::InputError("unknown creature '" + req.name + "'");
    // A link of this creature too: taken where it is at the call, before the move (as
    // Gazebo's set_model_state takes its reference_frame).
    const ReferenceFrame frame = referenceFrame(req.reference_frame, req.name);
    flapsim::StateRequest r;
    try {
      r = stateRequest(*c->model, world_.state(req.name), req);
    } catch (const flapsim::InputError& e) {
      throw flapsim::InputError("creature '" + req.name + "': " + e.what());
    }
    if (!frame.name.empty()) {
      const FrameMotion m = fromFrame(frame.motion, FrameMotion{r.pose, r.twist});
      r.pose = m.pose;
      r.twist = m.twist;
    }
    world_.setState(req.name, r);
    res.status_message = "set the state of '" + req.name + "' at t = " + formatTime(now()) + " s";
    const std::string below = belowGround(*c->model, world_.state(req.name), params_.world.ground);
    if (!below.empty()) {
      res.status_message += "; " + below;
      warnThrottled("set_state/below_ground", req.name, "set_state: " + res.status_message);
    }
    published_step_ = UINT64_MAX;
    publishAll();
  });
}

bool SimulatorNode::onApplyWrench(flapsim::ApplyWrench::Request& req,
                                  flapsim::ApplyWrench::Response& res) {
  return serve(res, "apply_wrench refused: ", req.name, [&] {
    adoptGazeboNames(req);
    const ReferenceFrame frame = referenceFrame(req.reference_frame, req.name);
    flapsim::ExternalWrench w = fromMsg(req);
    if (!frame.name.empty()) w = toWorld(w, frame.motion.pose);
    world_.applyWrench(req.name, w);
    res.status_message = "wrench on '" + req.name + "'" +
                         (req.link.empty() ? "" : " link '" + req.link + "'") +
                         (frame.name.empty() ? "" : " given in " + frame.name) +
                         " from t = " + formatTime(now()) + " s";
  });
}

bool SimulatorNode::onClearWrenches(flapsim::ClearWrenches::Request& req,
                                    flapsim::ClearWrenches::Response& res) {
  return serve(res, "clear_wrenches refused: ", req.name, [&] {
    adoptGazeboNames(req);
    const int n = world_.clearWrenches(req.name, req.link);
    res.status_message = "cleared " + std::to_string(n) + " wrench(es)";
  });
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

void SimulatorNode::applyConfig(const flapsim::FlapsimConfig& config) {
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
  ROS_INFO_STREAM("flapsim: physics at t = "
                  << formatTime(now()) << " s: real-time factor " << params_.real_time_factor
                  << ", publishing every " << publish_every_ << " steps, wind ["
                  << air.wind.transpose() << "] m/s, density " << air.density
                  << ", drag coefficient " << air.drag_coefficient << ", gravity ["
                  << gravity.transpose() << "], markers " << (config.show_markers ? "on" : "off"));
}

void SimulatorNode::onReconfigure(flapsim::FlapsimConfig& config, std::uint32_t) {
  const flapsim::FlapsimConfig before = runningConfig();
  try {
    applyConfig(config);
    for (const std::string& bound : valuesAtBounds(config, before)) {
      ROS_WARN_STREAM("flapsim: reconfigure: " << bound << " (dynamic_reconfigure clamps a "
                                               << "value outside the range to the bound)");
    }
  } catch (const flapsim::InputError& e) {
    warnThrottled("reconfigure/" + WarningLimiter::kindOf(e.what()), "",
                  std::string("reconfigure refused, nothing changed: ") + e.what());
    config = runningConfig();
  }
}

bool SimulatorNode::onGetPhysics(flapsim::GetPhysics::Request&,
                                 flapsim::GetPhysics::Response& res) {
  const flapsim::FlapsimConfig c = runningConfig();
  res.step_size = params_.world.step_size;
  res.paused = paused_;
  res.real_time_factor = c.real_time_factor;
  res.publish_rate = c.publish_rate;
  res.gravity.x = c.gravity_x;
  res.gravity.y = c.gravity_y;
  res.gravity.z = c.gravity_z;
  res.air_density = c.density;
  res.drag_coefficient = c.drag_coefficient;
  res.wind.x = c.wind_x;
  res.wind.y = c.wind_y;
  res.wind.z = c.wind_z;
  res.success = true;
  res.status_message = "physics at t = " + formatTime(now()) + " s";
  return true;
}

bool SimulatorNode::onSetPhysics(flapsim::SetPhysics::Request& req,
                                 flapsim::SetPhysics::Response& res) {
  return serve(res, "set_physics refused, nothing changed: ", "", [&] {
    static const std::vector<std::string> kFields = {
        "real_time_factor", "publish_rate", "gravity", "air_density", "drag_coefficient", "wind"};
    for (const std::string& f : req.fields) {
      if (std::find(kFields.begin(), kFields.end(), f) == kFields.end()) {
        throw flapsim::InputError("fields: '" + f + "' is not one of real_time_factor, " +
                                  "publish_rate, gravity, air_density, drag_coefficient, wind");
      }
    }
    auto named = [&](const char* f) {
      return req.fields.empty() ||
             std::find(req.fields.begin(), req.fields.end(), f) != req.fields.end();
    };
    if (req.fields.empty() && req.step_size != params_.world.step_size) {
      std::ostringstream what;
      what << "step_size " << req.step_size << " s: the step size cannot change while the node "
           << "runs (it is ~step_size, " << params_.world.step_size << " s); set_physics "
           << "takes every field: start from flapsim/get_physics, or name the fields to change";
      throw flapsim::InputError(what.str());
    }
    flapsim::FlapsimConfig c = runningConfig();
    if (named("real_time_factor")) c.real_time_factor = req.real_time_factor;
    if (named("publish_rate")) c.publish_rate = req.publish_rate;
    if (named("gravity")) std::tie(c.gravity_x, c.gravity_y, c.gravity_z) = xyz(req.gravity);
    if (named("air_density")) c.density = req.air_density;
    if (named("drag_coefficient")) c.drag_coefficient = req.drag_coefficient;
    if (named("wind")) std::tie(c.wind_x, c.wind_y, c.wind_z) = xyz(req.wind);
    applyConfig(c);
    reconfigure_->updateConfig(runningConfig());  // dynparam get shows what runs
    res.status_message = "physics set at t = " + formatTime(now()) + " s";
  });
}

}  // namespace flapsim_ros
