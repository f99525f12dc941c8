// What the simulator node publishes at each publication: /clock, every creature's topics,
// /tf, ~creature_states, ~aero_markers, ~view_markers and the view frames that follow the
// creatures, all made from one snapshot of the creatures (CreatureRegistry::snapshot).
#pragma once

#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>
#include <vector>

#include "flapsim/CreatureStates.h"
#include "flapsim/world.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/node_diagnostics.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/tf_publisher.h"
#include "flapsim_ros/visuals.h"

namespace flapsim_ros {

class WorldPublishers {
 public:
  /// /clock and /tf under `nh`, the markers and ~creature_states under `pnh`. The arguments
  /// outlive it. A new subscriber of /clock, ~aero_markers, ~view_markers or
  /// ~creature_states gets the current step's message at once (a paused world is seen as
  /// soon as rviz, a recorder or `rostopic echo` connects); /tf: see TfPublisher.
  WorldPublishers(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                  const flapsim::World& world, const CreatureRegistry& creatures, TfPublisher& tf,
                  NodeDiagnostics& diagnostics, const NodeParams& params);

  /// Every topic at the current step (the diagnostics too if a period passed since them).
  void publishAll();
  /// publishAll() unless the current step went out already (paused between publications, a
  /// subscriber would not see the step the world stays at).
  void publishIfNew();
  /// The next publishIfNew() publishes whatever the step.
  void forget() { published_step_ = UINT64_MAX; }
  void publishClock() { clock_.publish(clockMsg()); }
  /// Whether the world should record each cell's force (per-cell markers are wanted).
  bool wantsCellForces() const;
  /// Every transform of `creatures` and the view frames at `stamp`.
  tf2_msgs::TFMessage tfMsg(const std::vector<CreatureSnapshot>& creatures,
                            const ros::Time& stamp) const;

 private:
  rosgraph_msgs::Clock clockMsg() const;
  flapsim::CreatureStates statesMsg(const std::vector<CreatureSnapshot>& creatures,
                                    const ros::Time& stamp) const;
  visualization_msgs::MarkerArray aeroMarkerArray(const ros::Time& stamp) const;
  /// The readout of sim time and height in the camera's frame.
  visualization_msgs::MarkerArray viewMarkerArray(const ros::Time& stamp) const;
  /// Moves the view frames (flapsim/view, flapsim/camera) to the creatures at `stamp`.
  void updateView(const std::vector<CreatureSnapshot>& creatures, const ros::Time& stamp);

  const flapsim::World& world_;
  const CreatureRegistry& creatures_;
  TfPublisher& tf_;
  NodeDiagnostics& diagnostics_;
  const NodeParams& params_;
  ros::Publisher clock_, aero_markers_, view_markers_, states_;
  ViewFollower view_{kViewTimeConstant};           // the view frame, updated at each publication
  ViewFollower view_distance_{kViewTimeConstant};  // the camera's distance (in x)
  std::uint64_t published_step_ = UINT64_MAX;      // step count of the last publication
};

}  // namespace flapsim_ros
