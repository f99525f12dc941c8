// The controller nodes: stroke_controller (open loop, from parameters) and
// ann_controller (the evolved network on every unit of a creature).
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/controller_file.h"
#include "flapsim/sensors.h"
#include "flapsim_ros/controller_params.h"

namespace flapsim_ros {

/// Publishes the strokes of `~` parameters to <creature>/wing_command
/// (latched) at `rate` Hz of sim time, and at once when they change. The
/// parameters are re-read every `reread_period` wall seconds, so
/// `rosparam set /<node>/downstroke_rate 45` takes effect within that time;
/// a bad value is logged and the last good strokes are kept.
class StrokeControllerNode {
 public:
  /// Throws ParamError on bad start-up parameters.
  StrokeControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

 private:
  StrokeControllerParams load() const;
  void reread();
  void publish();

  ros::NodeHandle nh_, pnh_;
  StrokeControllerParams params_;
  ros::Publisher pub_;
  ros::Timer publish_timer_;
  ros::WallTimer reread_timer_;
};

/// Reads the units of its creature(s) from their sensors (AttitudeSource: the IMU, the
/// encoders and the altimeter by default, tf as the ground truth), runs the network of the
/// weights file on every unit and publishes <creature>/wing_command. Free running: a
/// sim-time timer at `rate`, on the latest readings. Lockstep: see AnnControllerParams; the
/// readings stamped with the current sim time.
class AnnControllerNode {
 public:
  /// Throws ParamError on bad parameters, std::runtime_error on a bad weights file.
  AnnControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

  /// Free running: spins until shutdown. Lockstep: drives the simulator until
  /// lockstep_duration, then returns. Returns false if lockstep failed.
  bool run();

  const AnnControllerParams& params() const { return params_; }

 private:
  // The latest sensor messages of one creature (imu source), written by the subscriptions.
  struct Readings {
    sensor_msgs::Imu::ConstPtr imu;
    nav_msgs::Odometry::ConstPtr odom;
    sensor_msgs::JointState::ConstPtr joints;
    flapsim::CreatureModelPtr model;  // from <creature>/robot_description, once it is set
    std::vector<int> bodies;          // the unit bodies' link indices in it
  };

  /// The units of creature `c` (an index of creatures_) as sensed at `stamp` (ros::Time(0):
  /// the latest), if every reading is there.
  std::optional<flapsim::FlapSensing> sense(const ros::Time& stamp, size_t c);
  std::optional<flapsim::FlapSensing> senseTf(const ros::Time& stamp, size_t c) const;
  std::optional<flapsim::FlapSensing> senseImu(const ros::Time& stamp, size_t c);
  /// What sense() waits for, for the messages.
  std::string missing(size_t c) const;
  /// The network reads the altimeter or the ground speed: odom's pose z, its twist.
  bool needsOdom() const;
  void subscribe();
  flapsim::WingCommand command(const flapsim::FlapSensing& sensed, const ros::Time& stamp) const;
  void onTimer(const ros::TimerEvent& event);
  /// Free running: publishes the command for the latest readings; false (and, if `warn`, a
  /// throttled warning) while a reading is missing.
  bool answer(bool warn);
  bool runLockstep();
  bool onStart(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);

  ros::NodeHandle nh_, pnh_;
  AnnControllerParams params_;
  flapsim::ControllerSpec spec_;
  flapsim::FlapUnitLayout layout_;
  std::vector<std::string> creatures_;            // params_.creature, or lockstep_creatures
  std::vector<std::vector<std::string>> frames_;  // per creature: its unit bodies' frames
  std::string simulator_ns_;                      // the namespace of the simulator's topics
  std::unique_ptr<flapsim::AnnWingController> controller_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  ros::Publisher pub_;
  ros::ServiceServer start_srv_;
  std::vector<ros::Subscriber> subscribers_;
  mutable std::mutex mutex_;        // guards readings_
  std::vector<Readings> readings_;  // per creature
  // Per creature, used by sense() only: the attitude filter of the weights file (restarted
  // when the stamps go back, as after a reset).
  std::vector<flapsim::AttitudeFilter> filters_;
  std::mt19937_64 altimeter_rng_;  // the altimeter's and ground speed's noise, from ~noise_seed
  std::normal_distribution<double> normal_;
  std::atomic<bool> started_{false};
  // Free running, until the first command: the simulator holds sim time for it (its creature's
  // `controller`), so the sim-time timer does not fire yet; this one polls in wall time.
  ros::WallTimer first_answer_timer_;
  bool answered_ = false;
};

}  // namespace flapsim_ros
