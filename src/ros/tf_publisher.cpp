#include "flapsim_ros/tf_publisher.h"

#include <utility>

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

namespace {

geometry_msgs::TransformStamped stamped(const std::string& parent, const std::string& child,
                                        const flapsim::Pose& pose, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = toTransformMsg(pose);
  return t;
}

}  // namespace

std::vector<geometry_msgs::TransformStamped> movingTransforms(const std::string& creature,
                                                              const flapsim::CreatureModel& model,
                                                              const flapsim::CreatureState& state,
                                                              const ros::Time& stamp,
                                                              const std::string& world_frame) {
  std::vector<geometry_msgs::TransformStamped> out;
  out.push_back(stamped(world_frame, linkFrame(creature, model.links.at(0).name),
                        state.link_poses.at(0), stamp));
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const flapsim::JointModel& joint = model.joints[j];
    if (!joint.movable()) continue;
    out.push_back(stamped(linkFrame(creature, model.links.at(joint.parent_link).name),
                          linkFrame(creature, model.links.at(joint.child_link).name),
                          flapsim::urdfJointPose(model, joint, state.joint_positions.at(j)),
                          stamp));
  }
  return out;
}

std::vector<geometry_msgs::TransformStamped> fixedTransforms(const std::string& creature,
                                                             const flapsim::CreatureModel& model,
                                                             const ros::Time& stamp) {
  std::vector<geometry_msgs::TransformStamped> out;
  for (const flapsim::JointModel& joint : model.joints) {
    if (joint.movable()) continue;
    out.push_back(stamped(linkFrame(creature, model.links.at(joint.parent_link).name),
                          linkFrame(creature, model.links.at(joint.child_link).name),
                          flapsim::urdfJointPose(model, joint, 0.0), stamp));
  }
  // Massless links lumped into the link they are fixed to: frames fixed to it.
  for (const flapsim::LumpedLink& lumped : model.lumped) {
    out.push_back(stamped(linkFrame(creature, model.links.at(lumped.link).name),
                          linkFrame(creature, lumped.name), lumped.pose, stamp));
  }
  return out;
}

TfPublisher::TfPublisher(ros::NodeHandle nh, Builder current, int queue)
    : current_(std::move(current)) {
  ros::AdvertiseOptions ops = ros::AdvertiseOptions::create<tf2_msgs::TFMessage>(
      "/tf", queue, [this](const ros::SingleSubscriberPublisher& p) { onConnect(p); },
      ros::SubscriberStatusCallback(), ros::VoidConstPtr(), &connect_queue_);
  tf_ = nh.advertise(ops);
  tf_static_ = nh.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
}

std::vector<geometry_msgs::TransformStamped> TfPublisher::unsent(
    const std::vector<geometry_msgs::TransformStamped>& transforms,
    std::vector<geometry_msgs::TransformStamped>* already) {
  std::vector<geometry_msgs::TransformStamped> fresh;
  for (const geometry_msgs::TransformStamped& t : transforms) {
    auto [it, inserted] = sent_.emplace(t.child_frame_id, t.header.stamp);
    if (!inserted && it->second == t.header.stamp) {
      already->push_back(t);
      continue;
    }
    it->second = t.header.stamp;
    fresh.push_back(t);
  }
  return fresh;
}

void TfPublisher::publish(const tf2_msgs::TFMessage& msg) {
  tf2_msgs::TFMessage fresh;
  for_new_.transforms.clear();
  fresh.transforms = unsent(msg.transforms, &for_new_.transforms);
  connect_queue_.callAvailable();  // new subscribers: what the publication leaves out
  if (!fresh.transforms.empty()) tf_.publish(fresh);
}

void TfPublisher::serveNewSubscribers(const ros::Time& stamp) {
  if (connect_queue_.isEmpty()) return;
  for_new_ = current_(stamp);
  for (const geometry_msgs::TransformStamped& t : for_new_.transforms) {
    sent_[t.child_frame_id] = t.header.stamp;
  }
  connect_queue_.callAvailable();
}

void TfPublisher::onConnect(const ros::SingleSubscriberPublisher& p) {
  if (!for_new_.transforms.empty()) p.publish(for_new_);
}

void TfPublisher::forgetOlderThan(const ros::Time& stamp) {
  for (auto it = sent_.begin(); it != sent_.end();) {
    it = it->second < stamp ? sent_.erase(it) : std::next(it);
  }
}

void TfPublisher::publishStatic(const std::vector<geometry_msgs::TransformStamped>& transforms) {
  tf2_msgs::TFMessage msg;
  msg.transforms = transforms;
  tf_static_.publish(msg);
}

}  // namespace flapsim_ros
