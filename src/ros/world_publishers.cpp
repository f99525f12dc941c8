#include "flapsim_ros/world_publishers.h"

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {
namespace {

constexpr double kDiagnosticsPeriod = 1.0;  // s (wall) between unchanged diagnostics

}  // namespace

WorldPublishers::WorldPublishers(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                                 const flapsim::World& world, const CreatureRegistry& creatures,
                                 TfPublisher& tf, NodeDiagnostics& diagnostics,
                                 const NodeParams& params)
    : world_(world), creatures_(creatures), tf_(tf), diagnostics_(diagnostics), params_(params) {
  ros::NodeHandle n(nh), p(pnh);
  clock_ = n.advertise<rosgraph_msgs::Clock>(
      "/clock", publishQueueSize(params_),
      [this](const ros::SingleSubscriberPublisher& s) { s.publish(clockMsg()); });
  aero_markers_ = p.advertise<visualization_msgs::MarkerArray>(
      "aero_markers", 2, [this](const ros::SingleSubscriberPublisher& s) {
        if (params_.markers.enabled) s.publish(aeroMarkerArray(simNow(world_)));
      });
  view_markers_ = p.advertise<visualization_msgs::MarkerArray>(
      "view_markers", 2, [this](const ros::SingleSubscriberPublisher& s) {
        s.publish(viewMarkerArray(simNow(world_)));
      });
  states_ = p.advertise<flapsim::CreatureStates>(
      "creature_states", 10, [this](const ros::SingleSubscriberPublisher& s) {
        const ros::Time stamp = simNow(world_);
        s.publish(statesMsg(creatures_.snapshot(stamp), stamp));
      });
}

void WorldPublishers::publishAll() {
  const ros::Time stamp = simNow(world_);
  const std::vector<CreatureSnapshot> snapshot = creatures_.snapshot(stamp);
  clock_.publish(clockMsg());
  updateView(snapshot, stamp);
  for (size_t i = 0; i < snapshot.size(); ++i) creatures_.all()[i]->topics->publish(snapshot[i]);
  if (tf_.wanted()) tf_.publish(tfMsg(snapshot, stamp));
  if (states_.getNumSubscribers() > 0) states_.publish(statesMsg(snapshot, stamp));
  if (params_.markers.enabled && aero_markers_.getNumSubscribers() > 0) {
    aero_markers_.publish(aeroMarkerArray(stamp));
  }
  if (view_markers_.getNumSubscribers() > 0) view_markers_.publish(viewMarkerArray(stamp));
  if (diagnostics_.age() >= kDiagnosticsPeriod) diagnostics_.publish();
  published_step_ = world_.stepCount();
}

void WorldPublishers::publishIfNew() {
  if (published_step_ != world_.stepCount()) publishAll();
}

bool WorldPublishers::wantsCellForces() const {
  return params_.markers.enabled && params_.markers.per_cell &&
         aero_markers_.getNumSubscribers() > 0;
}

void WorldPublishers::updateView(const std::vector<CreatureSnapshot>& creatures,
                                 const ros::Time& stamp) {
  if (creatures.empty()) return;
  flapsim::Vec3 centroid = flapsim::Vec3::Zero();
  std::vector<flapsim::Vec3> origins;
  for (const CreatureSnapshot& c : creatures) {
    centroid += centreOfMass(*c.model, c.state);
    for (const flapsim::Pose& p : c.state.link_poses) origins.push_back(p.position);
  }
  view_.update(centroid / static_cast<double>(creatures.size()), stamp.toSec());
  const double distance =
      cameraDistance(origins, view_.position(), params_.view, params_.view.distance);
  view_distance_.update(flapsim::Vec3(distance, 0.0, 0.0), stamp.toSec());
}

rosgraph_msgs::Clock WorldPublishers::clockMsg() const {
  rosgraph_msgs::Clock clock;
  clock.clock = simNow(world_);
  return clock;
}

tf2_msgs::TFMessage WorldPublishers::tfMsg(const std::vector<CreatureSnapshot>& creatures,
                                           const ros::Time& stamp) const {
  tf2_msgs::TFMessage tf;
  for (const CreatureSnapshot& c : creatures) {
    auto t = movingTransforms(c.name, *c.model, c.state, stamp, params_.world_frame);
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

visualization_msgs::MarkerArray WorldPublishers::aeroMarkerArray(const ros::Time& stamp) const {
  visualization_msgs::MarkerArray markers;
  markers.markers.emplace_back();
  markers.markers.back().header.stamp = stamp;
  markers.markers.back().header.frame_id = params_.world_frame;
  markers.markers.back().action = visualization_msgs::Marker::DELETEALL;
  for (const auto& c : creatures_.all()) {
    auto m = aeroMarkers(c->name, world_.aeroForces(c->name), params_.markers, stamp,
                         params_.world_frame);
    markers.markers.insert(markers.markers.end(), m.begin(), m.end());
  }
  return markers;
}

visualization_msgs::MarkerArray WorldPublishers::viewMarkerArray(const ros::Time& stamp) const {
  visualization_msgs::MarkerArray markers;
  markers.markers.push_back(viewReadout(stamp, view_.position()));
  return markers;
}

flapsim::CreatureStates WorldPublishers::statesMsg(const std::vector<CreatureSnapshot>& creatures,
                                                   const ros::Time& stamp) const {
  flapsim::CreatureStates m;
  m.header.stamp = stamp;
  m.header.frame_id = params_.world_frame;
  for (const CreatureSnapshot& c : creatures) {
    m.name.push_back(c.name);
    m.pose.push_back(toMsg(c.state.link_poses.at(0)));
    m.twist.push_back(toMsg(c.state.link_twists.at(0)));
  }
  return m;
}

}  // namespace flapsim_ros
