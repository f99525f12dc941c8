// A creature's topics (<creature>/joint_states, odom, imu, power and the latched
// robot_description), one small publisher per topic, all fed one snapshot of the creature per
// publication (the shape of gazebo_plugins' one class per sensor). A new subscriber gets the
// current step's message at once, so a paused world is seen.
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>

#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "flapsim/sensors.h"
#include "flapsim/world.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/power_publisher.h"

namespace flapsim_ros {

/// A creature at one step, as every topic about it is made from it: read from the world once
/// per publication.
struct CreatureSnapshot {
  std::string name;
  flapsim::CreatureModelPtr model;
  flapsim::CreatureState state;
  flapsim::Vec3 root_acceleration = flapsim::Vec3::Zero();  // World::rootAcceleration
  flapsim::Vec3 gravity = flapsim::Vec3::Zero();            // the world's, for the IMU
  flapsim::CreaturePower power;
  ros::Time stamp;
};

/// The world's sim time: its steps, exact in nanoseconds (simTime).
ros::Time simNow(const flapsim::World& world);

/// The snapshot of creature `name` of `world` now, stamped `stamp`.
CreatureSnapshot snapshotOf(const flapsim::World& world, const std::string& name,
                            const ros::Time& stamp);

/// The IMUs' noise (~imu) on every creature's <creature>/imu: a message's noise is drawn from
/// a generator seeded by (~imu/seed, the creature's name, the message's stamp) alone, so every
/// message of one instant carries the same noise however many are made (one more for each
/// subscriber that connects, none for a publication nobody receives) and a run's noise does
/// not depend on when nodes connect. (Drawn in the order of publication from one generator, it
/// did: two lockstep runs of afc_real_air.test parted at t = 0.25 s.)
class ImuNoiseSource {
 public:
  explicit ImuNoiseSource(const ImuParams& params);
  sensor_msgs::Imu message(const CreatureSnapshot& s) const;

 private:
  flapsim::ImuNoise noise_;
  std::uint64_t seed_;
};

/// One topic of a creature: its message made from a snapshot, published to its subscribers; a
/// new subscriber gets the message of `current()` (none: the creature is gone) at once.
template <class Msg>
class SnapshotPublisher {
 public:
  using Make = std::function<Msg(const CreatureSnapshot&)>;
  using Current = std::function<std::optional<CreatureSnapshot>()>;
  SnapshotPublisher(ros::NodeHandle& nh, const std::string& topic, int queue, Make make,
                    const Current& current) {
    pub_ =
        nh.advertise<Msg>(topic, queue, [make, current](const ros::SingleSubscriberPublisher& p) {
          if (const std::optional<CreatureSnapshot> s = current()) p.publish(make(*s));
        });
    make_ = std::move(make);
  }
  bool wanted() const { return pub_.getNumSubscribers() > 0; }
  void publish(const CreatureSnapshot& s) {
    if (wanted()) pub_.publish(make_(s));
  }
  void shutdown() { pub_.shutdown(); }

 private:
  ros::Publisher pub_;
  Make make_;
};

/// Every topic of one creature.
class CreaturePublishers {
 public:
  /// Topics under `nh` (the creature's own copy of the node's handle, which outlives this:
  /// roscpp keeps a weak pointer to every publisher a handle made until the handle goes).
  /// `current`: the creature's snapshot now, for new subscribers (none once it is deleted: a
  /// connection queued before the delete is served after it). `imu` outlives this.
  CreaturePublishers(ros::NodeHandle& nh, const std::string& name,
                     const flapsim::CreatureModelPtr& model, const std::string& urdf_xml, int queue,
                     const std::string& world_frame, ImuNoiseSource* imu,
                     const SnapshotPublisher<sensor_msgs::Imu>::Current& current);
  /// Power (whose window restarts whether or not anyone listens), then publishState.
  void publish(const CreatureSnapshot& s);
  /// imu, joint_states and odom, in that order, to their subscribers.
  void publishState(const CreatureSnapshot& s);
  void shutdown();

 private:
  ros::Publisher description_;
  SnapshotPublisher<sensor_msgs::JointState> joint_states_;
  SnapshotPublisher<nav_msgs::Odometry> odom_;
  SnapshotPublisher<sensor_msgs::Imu> imu_;
  std::unique_ptr<PowerPublisher> power_;
};

}  // namespace flapsim_ros
