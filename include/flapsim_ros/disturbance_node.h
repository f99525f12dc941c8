// The disturbance node: real air's roll torque and push on a wing (flapsim/real_air.h: what
// flight_check --real-air draws for its first start) applied to a creature through the
// simulator's flapsim/apply_wrench at their times of sim time (/clock).
#pragma once

#include <geometry_msgs/WrenchStamped.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <optional>
#include <string>

#include "flapsim/ApplyWrench.h"
#include "flapsim/real_air.h"

namespace flapsim_ros {

/// The disturbance node's private parameters.
struct DisturbanceParams {
  std::string creature;  // default: the node's namespace's last component
  /// seed, duration: flight_check's --seed and --duration; torque (N m) and push (N): sizes
  /// instead of real air's (>= 0; 0: none).
  flapsim::RealAirDrawParams draw;
  std::string apply_wrench_service = "/flapsim/apply_wrench";
  std::string get_state_service = "/flapsim/get_state";
  double wait_timeout = 30.0;  // s (wall) for the services at start-up
};

/// Private namespace of the disturbance node. Keys (all optional): creature, seed (an integer
/// >= 0), duration (s, in (0, 1e4]), torque (N m, in [0, 1e6]), push (N, in [0, 1e6]),
/// apply_wrench_service, get_state_service, wait_timeout (s, > 0). Throws ParamError naming
/// the bad key.
DisturbanceParams parseDisturbanceParams(const XmlRpc::XmlRpcValue& ns,
                                         const std::string& default_creature);

/// Reads the creature from <simulator>/<creature>/robot_description (the simulator's namespace:
/// apply_wrench_service's), draws real air's disturbances for it once it is there (logged),
/// and applies the roll torque (about the root link's x axis, in its axes at the call) and the
/// push (vertical in the world at the pushed link's centre of mass, which flapsim/get_state
/// gives) at the first /clock at or after their times, each for its duration. Publishes each
/// wrench applied on ~applied (geometry_msgs/WrenchStamped, latched: stamped with the sim time
/// of the state read just before the call, in the frame of the link it acts on, about that
/// frame's origin). The wrench acts from the step after the simulator answers the call: in
/// lockstep the controller may step the simulator meanwhile, so a run is not reproducible to
/// the bit. When sim time goes back (a reset) the disturbances to come are applied again.
class DisturbanceNode {
 public:
  /// Throws ParamError on bad parameters.
  DisturbanceNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

  /// Waits for the services (false if they do not come within wait_timeout), then spins until
  /// shutdown. Throws InputError for a creature it cannot disturb (no flap unit, no wing).
  bool run();

 private:
  /// One disturbance to apply: its time, whether it was, and how.
  struct Pending {
    double time = 0.0;
    bool applied = false;
  };

  void onClock(const rosgraph_msgs::Clock::ConstPtr& msg);
  /// Draws once the creature's description is there; false while it is not.
  bool draw();
  /// Link `link` of the creature in the world (flapsim/get_state), `stamp` the sim time of that
  /// state; nullopt (logged) if the simulator does not answer it.
  std::optional<flapsim::Pose> linkPose(const std::string& link, ros::Time& stamp);
  /// Calls apply_wrench for the creature; false (logged, naming `what`) if it fails.
  bool apply(flapsim::ApplyWrench& call, const char* what);
  bool applyTorque();
  bool applyPush();

  ros::NodeHandle nh_, pnh_;
  DisturbanceParams params_;
  std::string description_key_;  // <simulator>/<creature>/robot_description
  ros::ServiceClient apply_wrench_, get_state_;
  ros::Subscriber clock_sub_;
  ros::Publisher applied_pub_;
  flapsim::CreatureModelPtr model_;
  flapsim::RealAirDraws draws_;
  Pending torque_, push_;
  double last_time_ = 0.0;  // s: the latest /clock
  bool warned_ = false;     // that the description was missing at a disturbance's time
  std::string fatal_;       // why it cannot go on (from a callback), for run()
};

}  // namespace flapsim_ros
