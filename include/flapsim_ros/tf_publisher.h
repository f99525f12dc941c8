// The simulator's transforms: a tree that follows each creature's URDF (world -> its root from
// the simulation, parent -> child per joint, fixed joints on /tf_static), published so that no
// listener ever gets a frame twice at one stamp (tf2's TF_REPEATED_DATA).
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/world.h"

namespace flapsim_ros {

/// The moving transforms of a creature, as robot_state_publisher computes them from the URDF
/// and the joint positions, with frames "<creature>/<link>": `world_frame` -> the root link
/// (the simulated pose), then parent link -> child link for every movable joint (the joint's
/// origin, then its rotation or translation by the joint position), in URDF joint order.
std::vector<geometry_msgs::TransformStamped> movingTransforms(const std::string& creature,
                                                              const flapsim::CreatureModel& model,
                                                              const flapsim::CreatureState& state,
                                                              const ros::Time& stamp,
                                                              const std::string& world_frame);

/// Parent link -> child link for every fixed joint (its origin): for /tf_static.
std::vector<geometry_msgs::TransformStamped> fixedTransforms(const std::string& creature,
                                                             const flapsim::CreatureModel& model,
                                                             const ros::Time& stamp);

/// /tf and /tf_static of the simulator node. /tf never carries a child frame twice at one stamp:
/// a transform whose frame went out at that stamp already is left out (a republication of the
/// same step, e.g. `flapsim/step` of 0 steps or a `set_state` while paused, adds nothing a tf2
/// listener keeps). A new subscriber gets the current transforms once: by the next
/// publication, or, while no publication comes (paused), by serveNewSubscribers.
class TfPublisher {
 public:
  /// `current` builds every transform of the current step (all creatures and the view frames),
  /// stamped as given.
  using Builder = std::function<tf2_msgs::TFMessage(const ros::Time&)>;

  /// `queue`: /tf's publisher queue (messages).
  TfPublisher(ros::NodeHandle nh, Builder current, int queue);

  /// Whether anyone subscribes to /tf (else building transforms is wasted).
  bool wanted() const { return tf_.getNumSubscribers() > 0; }
  /// Publishes `msg`, every transform of one step, less those whose frames went out at their
  /// stamp already; a subscriber that joined since the last publication gets those from it.
  void publish(const tf2_msgs::TFMessage& msg);
  /// Sends each subscriber that joined since the last publication every transform at `stamp`
  /// (the current step): for a paused world, where no publication comes.
  void serveNewSubscribers(const ros::Time& stamp);
  /// Forgets which frames went out when: after a reset (time starts again at 0; tf2 listeners
  /// clear their buffers when time jumps back).
  void clear() { sent_.clear(); }
  /// Forgets the frames last sent before `stamp`: a deleted creature's.
  void forgetOlderThan(const ros::Time& stamp);
  /// Replaces what /tf_static holds (latched: every creature's fixed joints).
  void publishStatic(const std::vector<geometry_msgs::TransformStamped>& transforms);

 private:
  /// Splits `transforms` into those whose frames did not go out at their stamp (returned, and
  /// marked sent) and the others (`*already`).
  std::vector<geometry_msgs::TransformStamped> unsent(
      const std::vector<geometry_msgs::TransformStamped>& transforms,
      std::vector<geometry_msgs::TransformStamped>* already);
  void onConnect(const ros::SingleSubscriberPublisher& p);

  Builder current_;
  // The connect callbacks of /tf wait here, not on the node's queue: publish() runs them just
  // before it publishes (a new subscriber gets the transforms this publication leaves out;
  // the others it gets from the publication), and serveNewSubscribers between publications.
  // So every subscriber gets each frame of a step once, whether it joins before or after the
  // step is published. (One joining in the microseconds between publish()'s run of the
  // callbacks and its publication could get a frame twice: the callbacks cannot be run in
  // the same instant as the publication.)
  ros::CallbackQueue connect_queue_;
  ros::Publisher tf_, tf_static_;
  std::unordered_map<std::string, ros::Time> sent_;  // child frame -> stamp last sent
  tf2_msgs::TFMessage for_new_;                      // what onConnect sends
};

}  // namespace flapsim_ros
