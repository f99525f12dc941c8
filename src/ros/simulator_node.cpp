#include "flapsim_ros/simulator_node.h"

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {
namespace {

constexpr double kPausedPoll = 0.1;         // s (wall) longest callback wait (shutdown is seen)
constexpr double kPausedClockPeriod = 0.1;  // s (wall) between /clock messages while paused

}  // namespace

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
    : SimulatorNode(nh, pnh, loadNodeParams(pnh)) {}

SimulatorNode::SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                             const NodeParams& params)
    : params_(params), nh_(nh), pnh_(pnh), world_(params.world) {
  nh_.setCallbackQueue(&queue_);
  pnh_.setCallbackQueue(&queue_);
  for (const std::string& k : params_.unknown_keys) {
    ROS_WARN_STREAM("flapsim: ignoring unknown parameter '" << pnh_.resolveName(k) << "'");
  }
  world_.setCommandTimeout(
      flapsim::CommandTimeout{params_.wing_command_timeout, params_.wing_command_timeout_action});
  tf_ = std::make_unique<TfPublisher>(
      nh_, [this](const ros::Time& t) { return publishers_->tfMsg(creatures_->snapshot(t), t); },
      publishQueueSize(params_));
  creatures_ = std::make_unique<CreatureRegistry>(nh_, pnh_, params_, world_, *tf_);
  diagnostics_ = std::make_unique<NodeDiagnostics>(nh_, world_, *creatures_, params_);
  publishers_ = std::make_unique<WorldPublishers>(nh_, pnh_, world_, *creatures_, *tf_,
                                                  *diagnostics_, params_);
  stepper_ = std::make_unique<Stepper>(world_, *creatures_, *publishers_, *diagnostics_, params_);
  state_services_ =
      std::make_unique<StateServices>(pnh_, world_, *creatures_, *publishers_, params_);
  physics_ = std::make_unique<PhysicsConfig>(pnh_, world_, params_, *creatures_,
                                             [this] { stepper_->restartPacing(); });
  services_ = std::make_unique<SimulatorServices>(
      pnh_, SimulationParts{world_, *creatures_, *publishers_, *tf_, *stepper_, *physics_,
                            *diagnostics_, params_});
  wait_ = std::make_unique<ControllerWait>(world_, *creatures_, *diagnostics_, *stepper_, params_);
  creatures_->onWingCommand(
      [this](const std::string& creature, const flapsim::WingCommand::ConstPtr& msg) {
        services_->onWingCommand(creature, msg);
      });

  spawnConfigured();
  ROS_INFO_STREAM(
      "flapsim: " << creatures_->all().size() << " creature(s), step " << params_.world.step_size
                  << " s, publishing every " << publishEvery(params_) << " steps, real-time factor "
                  << params_.real_time_factor << (stepper_->paused() ? ", paused" : ""));
  creatures_->publishLatched(simNow(world_));  // also with no creature: the latched topics say so
  publishers_->publishAll();
}

void SimulatorNode::spawnConfigured() {
  for (const CreatureSpec& spec : params_.creatures) {
    const bool from_file = !spec.urdf_file.empty();
    const std::string text = from_file ? flapsim::readUrdfFile(spec.urdf_file) : spec.urdf_xml;
    const std::string source =
        from_file ? spec.urdf_file
                  : (spec.urdf_param.empty() ? "creature '" + spec.name + "' urdf_xml"
                                             : pnh_.resolveName(spec.urdf_param));
    creatures_->spawn(spec.name, text, source, spec.pose, spec.twist);
    NodeCreature* c = creatures_->find(spec.name);
    if (!spec.wing_command.empty()) {
      std::vector<flapsim::StrokeCommand> strokes = spec.wing_command;
      if (strokes.size() == 1) strokes.assign(c->model->wing_joints.size(), strokes[0]);
      try {
        world_.setWingCommands(spec.name, {}, strokes);
      } catch (const flapsim::InputError& e) {
        throw ParamError("creature '" + spec.name + "' wing_command: " + e.what());
      }
    }
    c->controller = spec.controller;
    c->awaiting_controller = !spec.controller.empty() && spec.wing_command.empty() &&
                             params_.controller_wait_timeout > 0.0;
  }
}

void SimulatorNode::run() {
  stepper_->restartPacing();
  while (ros::ok()) {
    if (stepper_->paused() || wait_->hold()) {
      queue_.callAvailable(ros::WallDuration(kPausedPoll));
      tf_->serveNewSubscribers(simNow(world_));
      // /clock goes on while paused: rospy's subscribers of one topic share a connection, so
      // `rostopic echo /clock` with use_sim_time may miss the message a new connection gets.
      if ((ros::WallTime::now() - clock_wall_).toSec() >= kPausedClockPeriod) {
        clock_wall_ = ros::WallTime::now();
        publishers_->publishClock();
      }
      continue;
    }
    stepper_->runSlice(queue_);
  }
}

}  // namespace flapsim_ros
