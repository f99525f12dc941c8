#include "flapsim_ros/creature_registry.h"

#include <ros/package.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>

#include "flapsim_ros/conversions.h"
#include "flapsim_ros/urdf_source.h"
#include "flapsim_ros/visuals.h"

namespace flapsim_ros {

CreatureRegistry::CreatureRegistry(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                                   const NodeParams& params, flapsim::World& world, TfPublisher& tf)
    : nh_(nh), params_(params), world_(world), tf_(tf), imu_noise_(params.imu) {
  markers_ = ros::NodeHandle(pnh).advertise<visualization_msgs::MarkerArray>("creature_markers", 1,
                                                                             /*latch=*/true);
}

CreatureRegistry::~CreatureRegistry() {
  for (const auto& c : creatures_) nh_.deleteParam(c->name + "/robot_description");
}

std::vector<std::string> CreatureRegistry::spawn(const std::string& name,
                                                 const std::string& urdf_xml,
                                                 const std::string& source,
                                                 const flapsim::Pose& pose,
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
  auto c = std::make_unique<NodeCreature>();
  c->nh = nh_;
  c->name = name;
  c->model = model;
  try {
    c->geometry = creatureMarkers(name, urdf_xml, source);
    // A new subscriber gets the current step at once (a paused world is seen); by name: a
    // callback queued before a delete runs after it. A recorder may lag: publishQueueSize.
    c->topics = std::make_unique<CreaturePublishers>(
        c->nh, name, model, urdf_xml, publishQueueSize(params_), params_.world_frame, &imu_noise_,
        [this, name]() -> std::optional<CreatureSnapshot> {
          if (!find(name)) return std::nullopt;
          return snapshotOf(world_, name, simNow(world_));
        });
    c->wing_command = c->nh.subscribe<flapsim::WingCommand>(
        name + "/wing_command", 10,
        [this, name](const flapsim::WingCommand::ConstPtr& msg) { on_command_(name, msg); });
    nh_.setParam(name + "/robot_description", urdf_xml);
  } catch (const ros::Exception& e) {
    world_.remove(name);
    throw flapsim::InputError("creature '" + name + "': " + e.what());
  }
  creatures_.push_back(std::move(c));
  publishLatched(simNow(world_));
  std::vector<std::string> notes = flapsim::implicitJointValues(*model, params_.world.step_size);
  for (const std::string& line : flapsim::geometryNotes(*model)) notes.push_back(line);
  for (std::string& line : notes) {
    line = "creature '" + name + "', " + line;
    ROS_WARN_STREAM("flapsim: " << line);
  }
  return notes;
}

void CreatureRegistry::remove(const std::string& name) {
  world_.remove(name);  // InputError if unknown
  auto it = std::find_if(creatures_.begin(), creatures_.end(),
                         [&](const auto& c) { return c->name == name; });
  if (it == creatures_.end()) return;
  (*it)->topics->shutdown();
  (*it)->wing_command.shutdown();
  nh_.deleteParam(name + "/robot_description");
  creatures_.erase(it);
  const ros::Time now = simNow(world_);
  publishLatched(now);
  tf_.forgetOlderThan(now);
}

NodeCreature* CreatureRegistry::find(const std::string& name) {
  for (auto& c : creatures_) {
    if (c->name == name) return c.get();
  }
  return nullptr;
}

const NodeCreature* CreatureRegistry::find(const std::string& name) const {
  return const_cast<CreatureRegistry*>(this)->find(name);
}

std::vector<CreatureSnapshot> CreatureRegistry::snapshot(const ros::Time& stamp) const {
  std::vector<CreatureSnapshot> out;
  out.reserve(creatures_.size());
  for (const auto& c : creatures_) out.push_back(snapshotOf(world_, c->name, stamp));
  return out;
}

void CreatureRegistry::publishLatched(const ros::Time& stamp) {
  visualization_msgs::MarkerArray markers;
  markers.markers.emplace_back();
  markers.markers.back().header.frame_id = params_.world_frame;
  markers.markers.back().action = visualization_msgs::Marker::DELETEALL;
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (const auto& c : creatures_) {
    markers.markers.insert(markers.markers.end(), c->geometry.begin(), c->geometry.end());
    const auto t = fixedTransforms(c->name, *c->model, stamp);
    transforms.insert(transforms.end(), t.begin(), t.end());
  }
  markers_.publish(markers);
  tf_.publishStatic(transforms);
}

void CreatureRegistry::warn(const std::string& kind, const std::string& creature,
                            const std::string& message) {
  const std::string& known = find(creature) ? creature : std::string();
  if (warnings_.allow(kind, known, ros::WallTime::now().toSec())) {
    ROS_WARN_STREAM("flapsim: " << message);
  } else {
    ROS_DEBUG_STREAM("flapsim: " << message);
  }
}

}  // namespace flapsim_ros
