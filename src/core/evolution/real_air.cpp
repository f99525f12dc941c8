#include "flapsim/real_air.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "flapsim/evolve.h"
#include "flapsim/world.h"

namespace flapsim {

namespace {

// A magnitude given instead of real air's: finite and >= 0, else InputError naming `name`.
void checkMagnitude(const std::optional<double>& value, const char* name, double limit,
                    const char* unit) {
  if (value && !(*value >= 0.0 && *value <= limit)) {
    std::ostringstream msg;
    msg << "real air: " << name << " must be in [0, " << limit << "] " << unit
        << " (a size: its sign is drawn), not " << *value;
    throw InputError(msg.str());
  }
}

std::string yamlVector(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
  return text;
}

}  // namespace

RealAirDraws realAirDraws(const CreatureModel& model, const RealAirDrawParams& params) {
  checkMagnitude(params.torque, "torque", kMaxTorque, "N m");
  checkMagnitude(params.force, "force", kMaxForce, "N");
  FlightCheckParams p;
  p.starts = 1;
  p.seed = params.seed;
  p.duration = params.duration;
  p.real_air = true;
  p.real_air_torque = params.torque;
  p.real_air_force = params.force;
  p = realAirParams(p, model);
  const EpisodeParams episode = flightCheckEpisodes(p);
  const EpisodeStart start = episodeStarts(episode, &model).front();
  RealAirDraws d;
  d.wind = start.wind;
  d.gyro_bias = start.gyro_bias;
  d.torque = start.torque_sign * p.gust_torque;
  d.torque_time = start.torque_time;
  d.torque_duration = episode.gust_torque_duration;
  d.force = start.force_sign * p.gust_force;
  d.force_time = start.force_time;
  d.force_duration = episode.gust_force_duration;
  d.force_link = start.force_link;
  return d;
}

RealAirSpinUp realAirSpinUp(const CreatureModel& model) {
  const CreatureState state = spawnedLevel(model);
  // The links' centres of mass in the world and their own inertias about the world's x axis
  // (R diag(I) R^T, its xx element), and the creature's centre of mass.
  std::vector<Vec3> com(model.links.size());
  double mass = 0.0, own = 0.0;
  Vec3 centre = Vec3::Zero();
  for (size_t k = 0; k < model.links.size(); ++k) {
    const LinkModel& l = model.links[k];
    com[k] = state.link_poses[k].apply(l.urdfCom());
    const Eigen::Matrix3d r = l.fromUrdf(state.link_poses[k]).orientation.toRotationMatrix();
    own += r.row(0).cwiseAbs2().dot(l.inertia);
    mass += l.mass;
    centre += l.mass * com[k];
  }
  RealAirSpinUp s;
  s.impulses = realAirImpulses(model);
  if (mass <= 0.0) return s;
  centre /= mass;
  s.roll_inertia = own;
  for (size_t k = 0; k < model.links.size(); ++k) {
    const Vec3 d = com[k] - centre;
    s.roll_inertia += model.links[k].mass * (d.y() * d.y() + d.z() * d.z());
  }
  for (int j : model.wing_joints) {
    const int link = model.joints[j].child_link;
    s.push_arm = std::max(s.push_arm, std::abs(com[link].y() - centre.y()));
  }
  if (s.roll_inertia <= 0.0) return s;
  s.torque_rate = s.impulses.torque * s.impulses.torque_duration / s.roll_inertia;
  s.push_rate = s.impulses.force * s.push_arm * s.impulses.force_duration / s.roll_inertia;
  return s;
}

std::string realAirSpinUpLine(const RealAirSpinUp& s) {
  char text[400];
  std::snprintf(text, sizeof text,
                "real air on this creature: a roll torque of %.4g N m for %g s and a push of %.4g "
                "N for %g s on a wing %.3g m out, which would spin it, held rigid in vacuum "
                "(roll inertia %.3g kg m^2), at %.0f and %.0f rad/s\n",
                s.impulses.torque, s.impulses.torque_duration, s.impulses.force,
                s.impulses.force_duration, s.push_arm, s.roll_inertia, s.torque_rate, s.push_rate);
  return text;
}

std::string describeRealAirDraws(const RealAirDraws& d) {
  char text[512];
  std::snprintf(text, sizeof text,
                "wind [%.3f, %.3f, %.3f] m/s (%.2f m/s, heading %.1f deg from +x)\n"
                "gyro bias [%.4f, %.4f, %.4f] rad/s (%.4f rad/s)\n"
                "roll torque %+.4f N m about the root's x axis at t = %.3f s for %.2f s\n"
                "push %+.4f N (vertical) on %s at t = %.3f s for %.2f s",
                d.wind.x(), d.wind.y(), d.wind.z(), d.wind.norm(),
                std::atan2(d.wind.y(), d.wind.x()) * 180.0 / M_PI, d.gyro_bias.x(), d.gyro_bias.y(),
                d.gyro_bias.z(), d.gyro_bias.norm(), d.torque, d.torque_time, d.torque_duration,
                d.force, d.force_link.empty() ? "(no link)" : d.force_link.c_str(), d.force_time,
                d.force_duration);
  return text;
}

CliParser realAirPrintCli(RealAirPrintOptions& o) {
  CliParser t(
      "usage: disturbance --print WHAT --urdf FILE [--seed S] [--duration T]",
      "Prints what the disturbance node draws for a creature (flight_check --real-air --seed S "
      "--duration T, its first start), without ROS: afc.launch real_air:=true sets the "
      "simulator's air/wind and the controller's ~gyro_bias from it. As a ROS node (no "
      "--print) it applies the roll torque and the push at their times (doc/ros_interface.md).");
  t.text("--print", "WHAT", &o.print, "what to print: wind, gyro_bias (YAML lists) or all",
         {"wind", "gyro_bias", "all"})
      .text("--urdf", "FILE", &o.urdf, "the creature's URDF (required)")
      .seed("--seed", "S", &o.draw.seed, "the seed (flight_check --seed)")
      .real("--duration", "T", &o.draw.duration, {0, kMaxEpisodeDuration, true},
            "the flight, s: the gusts' times are drawn in its 10-60 %");
  return t;
}

std::string realAirPrint(const RealAirPrintOptions& options, const RealAirDraws& draws) {
  if (options.print == "wind") return yamlVector(draws.wind) + "\n";
  if (options.print == "gyro_bias") return yamlVector(draws.gyro_bias) + "\n";
  return describeRealAirDraws(draws) + "\n";
}

}  // namespace flapsim
