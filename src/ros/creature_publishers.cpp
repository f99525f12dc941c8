#include "flapsim_ros/creature_publishers.h"

#include <std_msgs/String.h>

#include "flapsim/ga.h"
#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

ros::Time simNow(const flapsim::World& world) {
  return simTime(world.stepCount(), stepNanoseconds(world.params().step_size));
}

CreatureSnapshot snapshotOf(const flapsim::World& world, const std::string& name,
                            const ros::Time& stamp) {
  CreatureSnapshot s;
  s.name = name;
  s.model = world.model(name);
  s.state = world.state(name);
  s.root_acceleration = world.rootAcceleration(name);
  s.gravity = world.params().gravity;
  s.power = world.power(name);
  s.stamp = stamp;
  return s;
}

ImuNoiseSource::ImuNoiseSource(const ImuParams& params)
    : noise_{params.orientation_noise, params.angular_velocity_noise,
             params.linear_acceleration_noise},
      seed_(static_cast<std::uint64_t>(params.seed)) {}

sensor_msgs::Imu ImuNoiseSource::message(const CreatureSnapshot& s) const {
  // FNV-1a of the creature's name: its own stream, the same in every process.
  std::uint64_t name = 1469598103934665603ULL;
  for (const unsigned char c : s.name) name = (name ^ c) * 1099511628211ULL;
  std::mt19937_64 rng(flapsim::mixSeed(seed_, name, s.stamp.toNSec()));
  std::normal_distribution<double> normal;
  return imuMsg(s.name, *s.model, s.state, s.root_acceleration, s.gravity, s.stamp, noise_,
                [&] { return normal(rng); });
}

CreaturePublishers::CreaturePublishers(ros::NodeHandle& nh, const std::string& name,
                                       const flapsim::CreatureModelPtr& model,
                                       const std::string& urdf_xml, int queue,
                                       const std::string& world_frame, ImuNoiseSource* imu,
                                       const SnapshotPublisher<sensor_msgs::Imu>::Current& current)
    : description_(nh.advertise<std_msgs::String>(name + "/robot_description", 1, true)),
      joint_states_(
          nh, name + "/joint_states", queue,
          [](const CreatureSnapshot& s) { return jointStateMsg(*s.model, s.state, s.stamp); },
          current),
      odom_(
          nh, name + "/odom", queue,
          [world_frame](const CreatureSnapshot& s) {
            return odometryMsg(s.name, *s.model, s.state, s.stamp, world_frame);
          },
          current),
      imu_(
          nh, name + "/imu", queue, [imu](const CreatureSnapshot& s) { return imu->message(s); },
          current) {
  std_msgs::String text;
  text.data = urdf_xml;
  description_.publish(text);
  power_ = std::make_unique<PowerPublisher>(nh, name, model, queue, [current] {
    const std::optional<CreatureSnapshot> s = current();
    return s ? std::make_pair(s->power, s->stamp)
             : std::make_pair(flapsim::CreaturePower(), ros::Time());
  });
}

void CreaturePublishers::publish(const CreatureSnapshot& s) {
  power_->publish(s.power, s.stamp);
  publishState(s);
}

void CreaturePublishers::publishState(const CreatureSnapshot& s) {
  imu_.publish(s);
  joint_states_.publish(s);
  odom_.publish(s);
}

void CreaturePublishers::shutdown() {
  joint_states_.shutdown();
  odom_.shutdown();
  imu_.shutdown();
  power_->shutdown();
  description_.shutdown();
}

}  // namespace flapsim_ros
