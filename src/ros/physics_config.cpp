#include "flapsim_ros/physics_config.h"

#include <cmath>

#include "flapsim_ros/conversions.h"
#include "flapsim_ros/reconfigure_bounds.h"

namespace flapsim_ros {

PhysicsConfig::PhysicsConfig(const ros::NodeHandle& pnh, flapsim::World& world, NodeParams& params,
                             CreatureRegistry& creatures, std::function<void()> changed)
    : world_(world), params_(params), creatures_(creatures), changed_(std::move(changed)) {
  launch_ = running();
  // Its callbacks run on pnh's queue, between steps. The running values go in before the
  // callback: the node's parameters, not the cfg defaults, are what starts.
  server_ = std::make_unique<dynamic_reconfigure::Server<flapsim::FlapsimConfig>>(
      mutex_, ros::NodeHandle(pnh));
  server_->updateConfig(running());
  server_->setCallback(
      [this](flapsim::FlapsimConfig& config, std::uint32_t) { onReconfigure(config); });
}

flapsim::FlapsimConfig PhysicsConfig::running() const {
  flapsim::FlapsimConfig c;
  c.real_time_factor = params_.real_time_factor;
  c.publish_rate = params_.publish_rate;
  const flapsim::AirParams& air = world_.params().air;
  c.wind_x = air.wind.x();
  c.wind_y = air.wind.y();
  c.wind_z = air.wind.z();
  c.density = air.density;
  c.drag_coefficient = air.drag_coefficient;
  const flapsim::Vec3& g = world_.params().gravity;
  c.gravity_x = g.x();
  c.gravity_y = g.y();
  c.gravity_z = g.z();
  c.show_markers = params_.markers.enabled;
  return c;
}

void PhysicsConfig::apply(const flapsim::FlapsimConfig& config) {
  applyQuietly(config);
  server_->updateConfig(running());  // dynparam get shows what runs
}

void PhysicsConfig::restoreLaunch() {
  try {
    applyQuietly(launch_);  // the physics the node started with
  } catch (const flapsim::InputError& e) {
    creatures_.warn("reset", "", "reset keeps the running physics: " + std::string(e.what()));
  }
  server_->updateConfig(running());
}

void PhysicsConfig::applyQuietly(const flapsim::FlapsimConfig& config) {
  if (!std::isfinite(config.real_time_factor) ||
      (config.real_time_factor != 0.0 &&
       (config.real_time_factor < 1e-3 || config.real_time_factor > 1e6))) {
    throw flapsim::InputError(
        "real_time_factor must be 0 (as fast as possible) or in [0.001, 1e6]");
  }
  if (!(config.publish_rate >= 0.01 && config.publish_rate <= 1e6)) {
    throw flapsim::InputError("publish_rate must be in [0.01, 1e6] Hz");
  }
  flapsim::AirParams air = world_.params().air;
  air.wind = flapsim::Vec3(config.wind_x, config.wind_y, config.wind_z);
  air.density = config.density;
  air.drag_coefficient = config.drag_coefficient;
  const flapsim::Vec3 gravity(config.gravity_x, config.gravity_y, config.gravity_z);
  if (!gravity.allFinite() || gravity.norm() > flapsim::kMaxGravity) {
    throw flapsim::InputError("gravity must be finite and at most 1e4 m/s^2");
  }
  world_.setAirParams(air);  // checked first: InputError names the culprit
  world_.setGravity(gravity);
  params_.world.air = air;
  params_.world.gravity = gravity;
  params_.real_time_factor = config.real_time_factor;
  params_.publish_rate = config.publish_rate;
  params_.markers.enabled = config.show_markers;
  const std::uint64_t every = publishEvery(params_);
  changed_();
  ROS_INFO_STREAM("flapsim: physics at t = "
                  << formatTime(simNow(world_)) << " s: real-time factor "
                  << params_.real_time_factor << ", publishing every " << every << " steps, wind ["
                  << air.wind.transpose() << "] m/s, density " << air.density
                  << ", drag coefficient " << air.drag_coefficient << ", gravity ["
                  << gravity.transpose() << "], markers " << (config.show_markers ? "on" : "off"));
}

void PhysicsConfig::onReconfigure(flapsim::FlapsimConfig& config) {
  const flapsim::FlapsimConfig before = running();
  try {
    applyQuietly(config);
    for (const std::string& bound : valuesAtBounds(config, before)) {
      ROS_WARN_STREAM("flapsim: reconfigure: " << bound << " (dynamic_reconfigure clamps a "
                                               << "value outside the range to the bound)");
    }
  } catch (const flapsim::InputError& e) {
    creatures_.warn("reconfigure/" + WarningLimiter::kindOf(e.what()), "",
                    std::string("reconfigure refused, nothing changed: ") + e.what());
    config = running();
  }
}

}  // namespace flapsim_ros
