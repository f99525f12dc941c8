// The disturbance node: real air's roll torque and push on a wing (flapsim/real_air.h: what
// flight_check --real-air draws for its first start) applied to a creature through the
// simulator's flapsim/apply_wrench, handed over ahead with their times of sim time as
// start_time.
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
/// apply_wrench_service's), draws real air's disturbances for it (logged), and hands both
/// wrenches to flapsim/apply_wrench ahead, each with its drawn time as start_time and its drawn
/// duration: the simulator starts each at the first step that starts at or after its time,
/// the same step run after run, however the calls travel. The roll torque is about the root
/// link's x axis as it points then, the push vertical in the world at the pushed link's centre
/// of mass then (flapsim/get_state; the point moves with the link, so it is still the centre
/// of mass when the push starts). It does so at start-up, before it subscribes to /clock, when
/// the creature is there (afc.launch's flight starts only once this node receives /clock, so
/// the simulator is held meanwhile); else at the first /clock at which it is there. A drawn time
/// already past then is not applied late: it logs an error naming the wrench and both times
/// (and one if the simulator answers a start a step or more after the drawn time).
/// Publishes each wrench on ~applied (geometry_msgs/WrenchStamped, latched) at the first /clock
/// at or after its start: stamped with the sim time of the step it started at (the simulator's
/// answer), in the frame of the link it acts on as that frame was when it was handed over,
/// about that frame's origin. When sim time goes back (a reset drops the wrenches waiting) the
/// disturbances still to come are handed over again at that /clock, with the creature as it
/// is then.
class DisturbanceNode {
 public:
  /// Throws ParamError on bad parameters.
  DisturbanceNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

  /// Waits for the services (false if they do not come within wait_timeout), then spins until
  /// shutdown. Throws InputError for a creature it cannot disturb (no flap unit, no wing).
  bool run();

 private:
  /// One disturbance: its drawn time, whether it was handed to the simulator, and what
  /// ~applied says once it has started.
  struct Pending {
    const char* what = "";
    double time = 0.0;                     // s: drawn
    bool wanted = false;                   // drawn with a size (0: none)
    bool handed = false;                   // to apply_wrench, or refused (logged)
    bool started = false;                  // published on ~applied
    geometry_msgs::WrenchStamped applied;  // stamp: the sim time of the step it starts at
  };

  void onClock(const rosgraph_msgs::Clock::ConstPtr& msg);
  /// Draws once the creature's description is there; false while it is not.
  bool draw();
  /// Hands the disturbances not yet handed over to apply_wrench; false (logged) if the
  /// simulator does not give the creature's state.
  bool handOver();
  /// Link `link` of the creature in the world (flapsim/get_state), `stamp` the sim time of that
  /// state; nullopt (logged if `loud`) if the simulator does not answer it.
  std::optional<flapsim::Pose> linkPose(const std::string& link, ros::Time& stamp, bool loud);
  /// Whether `p`'s drawn time is still to come at sim time `now` (logged if not).
  bool stillToCome(const Pending& p, const ros::Time& now) const;
  /// Calls apply_wrench for the creature with `p`'s drawn time as start_time; false (logged,
  /// naming it) if it fails. Keeps the step it starts at as `p.applied`'s stamp.
  bool apply(flapsim::ApplyWrench& call, Pending& p);
  void handTorque();
  void handPush(const flapsim::Pose& wing);

  ros::NodeHandle nh_, pnh_;
  DisturbanceParams params_;
  std::string description_key_;  // <simulator>/<creature>/robot_description
  std::string step_size_key_;    // the simulator node's step_size parameter
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
