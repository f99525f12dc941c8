// The controller nodes: stroke_controller (open loop, from parameters) and
// ann_controller (the evolved network on every unit of a creature).
#pragma once

#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/controller_file.h"
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

/// Reads world -> <creature>/unit<k>_body from tf, runs the network of the
/// weights file on every unit and publishes <creature>/wing_command. Free
/// running: a sim-time timer at `rate`. Lockstep: see AnnControllerParams.
class AnnControllerNode {
 public:
  /// Throws ParamError on bad parameters, std::runtime_error on a bad weights file.
  AnnControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

  /// Free running: spins until shutdown. Lockstep: drives the simulator until
  /// lockstep_duration, then returns. Returns false if lockstep failed.
  bool run();

  const AnnControllerParams& params() const { return params_; }

 private:
  /// Orientations of the unit bodies of creature `c` (an index of creatures_) at `stamp`
  /// (ros::Time(0): latest), if every transform is available.
  std::optional<std::vector<flapsim::Quat>> bodies(const ros::Time& stamp, size_t c = 0) const;
  void command(const std::vector<flapsim::Quat>& bodies, const ros::Time& stamp);
  void onTimer(const ros::TimerEvent& event);
  bool runLockstep();
  bool onStart(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);

  ros::NodeHandle nh_, pnh_;
  AnnControllerParams params_;
  flapsim::ControllerSpec spec_;
  flapsim::FlapUnitLayout layout_;
  std::vector<std::string> creatures_;            // params_.creature, or lockstep_creatures
  std::vector<std::vector<std::string>> frames_;  // per creature: its unit bodies' frames
  std::unique_ptr<flapsim::AnnWingController> controller_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  ros::Publisher pub_;
  ros::ServiceServer start_srv_;
  std::atomic<bool> started_{false};
};

}  // namespace flapsim_ros
