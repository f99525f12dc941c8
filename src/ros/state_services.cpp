#include "flapsim_ros/state_services.h"

#include <cmath>
#include <cstdint>
#include <sstream>

#include "flapsim_ros/request_names.h"
#include "flapsim_ros/service_reply.h"

namespace flapsim_ros {
namespace {

constexpr double kGroundTolerance = 1e-3;  // m below the ground before a reply says so

}  // namespace

std::string belowGround(const flapsim::CreatureModel& model, const flapsim::CreatureState& state,
                        bool ground) {
  const double lowest = flapsim::lowestBoxPoint(model, state.link_poses);
  if (!ground || lowest >= -kGroundTolerance) return "";
  std::ostringstream below;
  below << "its collision shapes reach " << -lowest
        << " m below the ground (z = 0): the contact will push it out";
  return below.str();
}

StateServices::StateServices(const ros::NodeHandle& pnh, flapsim::World& world,
                             CreatureRegistry& creatures, WorldPublishers& publishers,
                             const NodeParams& params)
    : world_(world), creatures_(creatures), publishers_(publishers), params_(params) {
  ros::NodeHandle n(pnh);
  services_.push_back(n.advertiseService("get_state", &StateServices::onGetState, this));
  services_.push_back(n.advertiseService("set_state", &StateServices::onSetState, this));
  services_.push_back(n.advertiseService("apply_wrench", &StateServices::onApplyWrench, this));
  services_.push_back(n.advertiseService("clear_wrenches", &StateServices::onClearWrenches, this));
}

StateServices::ReferenceFrame StateServices::referenceFrame(const std::string& name,
                                                            const std::string& creature) {
  if (name.empty() || name == params_.world_frame) return ReferenceFrame();
  std::string owner = name, link;  // a creature name has no '/' and no ':'
  size_t at = name.find("::"), length = 2;
  if (at == std::string::npos) at = name.find('/'), length = 1;
  const NodeCreature* asked = creatures_.find(creature);
  if (at != std::string::npos) {
    owner = name.substr(0, at);
    link = name.substr(at + length);
  } else if (asked && asked->model->findFrame(name).link >= 0) {
    owner = creature;  // a link of the creature asked about
    link = name;
  }
  const NodeCreature* c = creatures_.find(owner);
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

bool StateServices::onGetState(flapsim::GetState::Request& req, flapsim::GetState::Response& res) {
  res.header.stamp = simNow(world_);
  res.header.frame_id = params_.world_frame;
  return serve(creatures_, res, "get_state refused: ", req.name, [&] {
    adoptGazeboNames(req);
    const NodeCreature* c = creatures_.find(req.name);
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

bool StateServices::onSetState(flapsim::SetState::Request& req, flapsim::SetState::Response& res) {
  return serve(creatures_, res, "set_state refused, nothing changed: ", req.name, [&] {
    adoptGazeboNames(req);
    const NodeCreature* c = creatures_.find(req.name);
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
    res.status_message =
        "set the state of '" + req.name + "' at t = " + formatTime(simNow(world_)) + " s";
    const std::string below = belowGround(*c->model, world_.state(req.name), params_.world.ground);
    if (!below.empty()) {
      res.status_message += "; " + below;
      creatures_.warn("set_state/below_ground", req.name, "set_state: " + res.status_message);
    }
    publishers_.publishAll();
  });
}

bool StateServices::onApplyWrench(flapsim::ApplyWrench::Request& req,
                                  flapsim::ApplyWrench::Response& res) {
  return serve(creatures_, res, "apply_wrench refused: ", req.name, [&] {
    adoptGazeboNames(req);
    const ReferenceFrame frame = referenceFrame(req.reference_frame, req.name);
    flapsim::ExternalWrench w = fromMsg(req);
    if (!frame.name.empty()) w = toWorld(w, frame.motion.pose);
    const double from = world_.applyWrench(req.name, w), h = world_.params().step_size;
    // That step's sim time as /clock stamps it (in whole steps of whole nanoseconds).
    res.start_time =
        simTime(static_cast<std::uint64_t>(std::llround(from / h)), stepNanoseconds(h));
    res.status_message = "wrench on '" + req.name + "'" +
                         (req.link.empty() ? "" : " link '" + req.link + "'") +
                         (frame.name.empty() ? "" : " given in " + frame.name) +
                         " acts from t = " + formatTime(res.start_time) + " s";
  });
}

bool StateServices::onClearWrenches(flapsim::ClearWrenches::Request& req,
                                    flapsim::ClearWrenches::Response& res) {
  return serve(creatures_, res, "clear_wrenches refused: ", req.name, [&] {
    adoptGazeboNames(req);
    const int n = world_.clearWrenches(req.name, req.link);
    res.status_message = "cleared " + std::to_string(n) + " wrench(es)";
  });
}

}  // namespace flapsim_ros
