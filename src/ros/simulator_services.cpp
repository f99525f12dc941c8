#include "flapsim_ros/simulator_services.h"

#include <algorithm>
#include <sstream>
#include <tuple>

#include "flapsim_ros/conversions.h"
#include "flapsim_ros/request_names.h"
#include "flapsim_ros/service_reply.h"
#include "flapsim_ros/state_services.h"
#include "flapsim_ros/urdf_source.h"

namespace flapsim_ros {
namespace {

// A vector's components, to tie to a config's x, y and z.
std::tuple<double, double, double> xyz(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

}  // namespace

SimulatorServices::SimulatorServices(const ros::NodeHandle& pnh, const SimulationParts& parts)
    : parts_(parts) {
  ros::NodeHandle n(pnh);
  services_.push_back(n.advertiseService("reset", &SimulatorServices::onReset, this));
  services_.push_back(n.advertiseService("pause", &SimulatorServices::onPause, this));
  services_.push_back(n.advertiseService("unpause", &SimulatorServices::onUnpause, this));
  services_.push_back(n.advertiseService("step", &SimulatorServices::onStep, this));
  services_.push_back(n.advertiseService("spawn", &SimulatorServices::onSpawn, this));
  services_.push_back(n.advertiseService("delete", &SimulatorServices::onDelete, this));
  services_.push_back(n.advertiseService("get_physics", &SimulatorServices::onGetPhysics, this));
  services_.push_back(n.advertiseService("set_physics", &SimulatorServices::onSetPhysics, this));
}

void SimulatorServices::onWingCommand(const std::string& creature,
                                      const flapsim::WingCommand::ConstPtr& msg) {
  try {
    const WingCommandRequest r = fromMsg(*msg);
    parts_.world.setWingCommands(creature, r.joints, r.strokes);
    NodeCreature* c = parts_.creatures.find(creature);
    if (!c) return;
    c->commanded();
    // Controllers stamp a command with the state it answers: its age is their lag.
    const ros::Time now = simNow(parts_.world);
    const double lag =
        msg->header.stamp.isZero() ? 0.0 : std::max(0.0, (now - msg->header.stamp).toSec());
    const bool was_lagging = c->command_lag > kCommandLagWarning;
    c->command_lag = lag;
    if (lag > kCommandLagWarning) {
      parts_.creatures.warn("wing_command/lag", creature,
                            "creature '" + creature + "': its wing command answers a state " +
                                formatTime(ros::Time(lag)) +
                                " s of sim time old: its controller falls behind " +
                                "(lower the real-time factor, or run it in lockstep)");
    }
    if (was_lagging != (lag > kCommandLagWarning)) parts_.diagnostics.publish();
  } catch (const flapsim::InputError& e) {
    parts_.creatures.warn("wing_command/" + WarningLimiter::kindOf(e.what()), creature,
                          "rejected wing command for '" + creature + "': " + e.what() +
                              " (keeping the previous command)");
  }
}

bool SimulatorServices::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  parts_.physics.restoreLaunch();  // the physics the node started with
  parts_.world.reset();            // the wing commands kept (a lapsed one given back)
  parts_.tf.clear();  // time starts again: listeners that see it jump back clear their buffers
  parts_.stepper.restartPacing();
  ROS_INFO("flapsim: reset, sim time 0");
  parts_.publishers.publishAll();
  parts_.diagnostics.publish();
  return true;
}

bool SimulatorServices::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  parts_.stepper.setPaused(true);
  // Every subscriber sees the step it stays at (paused between publications, it would not).
  parts_.publishers.publishIfNew();
  return true;
}

bool SimulatorServices::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  parts_.stepper.setPaused(false);
  parts_.stepper.restartPacing();
  return true;
}

bool SimulatorServices::onStep(flapsim::Step::Request& req, flapsim::Step::Response& res) {
  res.sim_time = simNow(parts_.world);
  if (!parts_.stepper.paused()) {
    res.success = false;
    res.status_message = "flapsim is running: call flapsim/pause before flapsim/step";
    parts_.creatures.warn("step/running", "", "step refused: " + res.status_message);
    return true;
  }
  if (req.steps > static_cast<std::uint32_t>(parts_.params.max_steps_per_call)) {
    res.success = false;
    res.status_message = "steps " + std::to_string(req.steps) + " is over max_steps_per_call " +
                         std::to_string(parts_.params.max_steps_per_call) +
                         " (parameter ~max_steps_per_call): no step taken";
    parts_.creatures.warn("step/max_steps_per_call", "", "step refused: " + res.status_message);
    return true;
  }
  try {
    // All checked by the world first, so that no creature is commanded unless all can be.
    parts_.world.setWingCommands(stepCommands(req.creatures, req.wing_commands));
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = std::string("wing commands refused, no step taken: ") + e.what();
    parts_.creatures.warn("step/" + WarningLimiter::kindOf(e.what()), "",
                          "step refused: " + res.status_message);
    return true;
  }
  for (const std::string& name : req.creatures) parts_.creatures.find(name)->commanded();
  parts_.publishers.forget();
  const std::uint64_t taken = parts_.stepper.advance(req.steps);
  parts_.publishers.publishIfNew();
  res.sim_time = simNow(parts_.world);
  res.success = taken == req.steps;
  res.status_message = (res.success ? "stepped " : "shutting down: stopped after ") +
                       std::to_string(taken) + " steps at t = " + formatTime(res.sim_time) + " s";
  return true;
}

bool SimulatorServices::onSpawn(flapsim::SpawnCreature::Request& req,
                                flapsim::SpawnCreature::Response& res) {
  try {
    adoptGazeboNames(req);
    if (req.urdf_xml.empty() == req.urdf_file.empty()) {
      throw flapsim::InputError("spawn '" + req.name +
                                "': give exactly one of model_xml (urdf_xml) and urdf_file");
    }
    const bool from_file = !req.urdf_file.empty();
    const std::vector<std::string> capped = parts_.creatures.spawn(
        req.name, from_file ? readSpawnUrdf(req.urdf_file, parts_.params.urdf_roots) : req.urdf_xml,
        from_file ? req.urdf_file : "spawn request '" + req.name + "'", fromMsg(req.initial_pose),
        fromMsg(req.initial_twist));
    const NodeCreature* c = parts_.creatures.find(req.name);
    if (parts_.tf.wanted()) {  // the new creature's frames
      const ros::Time stamp = simNow(parts_.world);
      parts_.tf.publish(parts_.publishers.tfMsg(parts_.creatures.snapshot(stamp), stamp));
    }
    res.success = true;
    res.status_message = "spawned '" + req.name + "': " + std::to_string(c->model->links.size()) +
                         " links, " + std::to_string(c->model->wing_joints.size()) + " wing joints";
    ROS_INFO_STREAM("flapsim: " << res.status_message);  // the lines below were warned
    for (const std::string& line : capped) res.status_message += "; " + line;
    const std::string below =
        belowGround(*c->model, parts_.world.state(req.name), parts_.params.world.ground);
    if (!below.empty()) {  // spawned as asked, as set_state does
      res.status_message += "; " + below;
      parts_.creatures.warn("spawn/below_ground", req.name, "spawn: " + res.status_message);
    }
    parts_.diagnostics.publish();
  } catch (const std::bad_alloc&) {
    res.success = false;
    res.status_message = "spawn '" + req.name + "': out of memory while reading or building it";
    parts_.creatures.warn("spawn/out_of_memory", "", "spawn refused: " + res.status_message);
  } catch (const std::exception& e) {  // InputError, ModelError
    res.success = false;
    res.status_message = e.what();
    parts_.creatures.warn("spawn/" + WarningLimiter::kindOf(e.what()), "",
                          "spawn refused: " + res.status_message);
  }
  return true;
}

bool SimulatorServices::onDelete(flapsim::DeleteCreature::Request& req,
                                 flapsim::DeleteCreature::Response& res) {
  try {
    adoptGazeboNames(req);
    parts_.creatures.remove(req.name);
    res.success = true;
    res.status_message = "deleted '" + req.name + "'";
    ROS_INFO_STREAM("flapsim: " << res.status_message);
    parts_.diagnostics.publish();
  } catch (const flapsim::InputError& e) {
    res.success = false;
    res.status_message = e.what();
    parts_.creatures.warn("delete", "", "delete refused: " + res.status_message);
  }
  return true;
}

bool SimulatorServices::onGetPhysics(flapsim::GetPhysics::Request&,
                                     flapsim::GetPhysics::Response& res) {
  const flapsim::FlapsimConfig c = parts_.physics.running();
  res.step_size = parts_.params.world.step_size;
  res.paused = parts_.stepper.paused();
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
  res.status_message = "physics at t = " + formatTime(simNow(parts_.world)) + " s";
  return true;
}

bool SimulatorServices::onSetPhysics(flapsim::SetPhysics::Request& req,
                                     flapsim::SetPhysics::Response& res) {
  return serve(parts_.creatures, res, "set_physics refused, nothing changed: ", "", [&] {
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
    const double step_size = parts_.params.world.step_size;
    if (req.fields.empty() && req.step_size != step_size) {
      std::ostringstream what;
      what << "step_size " << req.step_size << " s: the step size cannot change while the node "
           << "runs (it is ~step_size, " << step_size << " s); set_physics "
           << "takes every field: start from flapsim/get_physics, or name the fields to change";
      throw flapsim::InputError(what.str());
    }
    flapsim::FlapsimConfig c = parts_.physics.running();
    if (named("real_time_factor")) c.real_time_factor = req.real_time_factor;
    if (named("publish_rate")) c.publish_rate = req.publish_rate;
    if (named("gravity")) std::tie(c.gravity_x, c.gravity_y, c.gravity_z) = xyz(req.gravity);
    if (named("air_density")) c.density = req.air_density;
    if (named("drag_coefficient")) c.drag_coefficient = req.drag_coefficient;
    if (named("wind")) std::tie(c.wind_x, c.wind_y, c.wind_z) = xyz(req.wind);
    parts_.physics.apply(c);
    res.status_message = "physics set at t = " + formatTime(simNow(parts_.world)) + " s";
  });
}

}  // namespace flapsim_ros
