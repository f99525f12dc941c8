// Episodes: the starts an evaluation draws (attitude, wind, gusts, setpoint, step size,
// sensor noise) and one flight under a controller that reads the creature's sensors.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

#include "flapsim/control_loop.h"
#include "flapsim/evolve.h"
#include "flapsim/ga.h"

namespace flapsim {

// ---- Episodes ------------------------------------------------------------------------------

namespace {

// "<name> must be in [lo, hi]" unless lo <= x <= hi (NaN is outside).
std::string range(const char* name, double x, double lo, double hi, const char* unit = "") {
  if (x >= lo && x <= hi) return "";
  std::ostringstream msg;
  msg << name << " must be in [" << lo << ", " << hi << "]" << unit;
  return msg.str();
}

// The disturbances' and the altitude hold's settings.
std::string validateDisturbances(const EpisodeParams& p) {
  if (!(p.min_wind >= 0.0 && p.max_wind >= p.min_wind && p.max_wind <= kMaxGust)) {
    return "need 0 <= min_wind <= max_wind <= " + std::to_string(static_cast<int>(kMaxGust));
  }
  const std::string imu = validateImuNoise(p.imu_noise);
  if (!imu.empty()) return "imu_noise: " + imu;
  for (const std::string& err :
       {range("altitude_noise", p.altitude_noise, 0.0, 1e3, " m"),
        range("gyro_bias", p.gyro_bias, 0.0, 1e3, " rad/s"),
        range("velocity_noise", p.velocity_noise, 0.0, 1e3, " m/s"),
        range("gust_torque", p.gust_torque, -kMaxTorque, kMaxTorque, " N m"),
        range("gust_force", p.gust_force, -kMaxForce, kMaxForce, " N"),
        range("gust_torque_duration", p.gust_torque_duration, 1e-9, kMaxEpisodeDuration, " s"),
        range("gust_force_duration", p.gust_force_duration, 1e-9, kMaxEpisodeDuration, " s"),
        range("gust_window_start", p.gust_window_start, 0.0, 1.0),
        range("gust_window_end", p.gust_window_end, p.gust_window_start, 1.0),
        range("tilt_weight", p.tilt_weight, 0.0, 1e6),
        range("upright_floor", p.upright_floor, 0.0, 1.0),
        range("upright_floor_weight", p.upright_floor_weight, 0.0, 1e6, " m"),
        range("altitude_rms_ceiling", p.altitude_rms_ceiling, 0.0, 1e3, " m"),
        range("altitude_rms_weight", p.altitude_rms_weight, 0.0, 1e6, " m"),
        range("settle_time", p.settle_time, 0.0, kMaxEpisodeDuration, " s")}) {
    if (!err.empty()) return err;
  }
  if (p.altitude_hold && !(p.min_altitude >= -kMaxPosition && p.max_altitude <= kMaxPosition &&
                           p.min_altitude <= p.max_altitude)) {
    return "need min_altitude <= max_altitude (finite)";
  }
  return "";
}

}  // namespace

std::string validateEpisodeParams(const EpisodeParams& p) {
  const std::string w = validateWorldParams(p.world);
  if (!w.empty()) return "world: " + w;
  if (!(p.duration > 0.0 && p.duration <= kMaxEpisodeDuration)) {
    return "duration must be in (0, " + std::to_string(static_cast<int>(kMaxEpisodeDuration)) +
           "] s";
  }
  if (p.episodes < 1 || p.episodes > kMaxEpisodes) {
    return "episodes must be in [1, " + std::to_string(kMaxEpisodes) + "]";
  }
  if (!(p.min_roll >= 0.0 && p.max_roll >= p.min_roll && p.max_roll <= M_PI)) {
    return "need 0 <= min_roll <= max_roll <= pi";
  }
  for (const std::string& err :
       {range("start_height", p.start_height, -kMaxPosition, kMaxPosition, " m"),
        range("max_pitch", p.max_pitch, 0.0, M_PI, " rad"),
        range("max_start_rate", p.max_start_rate, 0.0, kMaxStartRate, " rad/s"),
        range("max_gust", p.max_gust, 0.0, kMaxGust, " m/s"),
        range("flip_penalty", p.flip_penalty, 0.0, kMaxFlipPenalty, " m")}) {
    if (!err.empty()) return err;
  }
  if (std::isnan(p.crash_height) || p.crash_height > kMaxPosition) {
    return "crash_height must be -inf (off) or a height up to " + std::to_string(kMaxPosition) +
           " m";
  }
  if (std::isfinite(p.crash_height) && p.flip_penalty <= 0.0) {
    return "crash_height needs flip_penalty > 0 (a crash ends the episode as a flip does)";
  }
  const std::string d = validateDisturbances(p);
  if (!d.empty()) return d;
  if (p.step_sizes.size() > static_cast<size_t>(kMaxStepSizes)) {
    return "step_sizes: more than " + std::to_string(kMaxStepSizes);
  }
  std::vector<double> steps = p.step_sizes;
  if (steps.empty()) steps.push_back(p.world.step_size);
  for (double dt : steps) {
    WorldParams step_only;
    step_only.step_size = dt;
    const std::string err = validateWorldParams(step_only);
    if (!err.empty()) return "step_sizes: " + err;
    if (p.duration / dt > kMaxEpisodeSteps) {
      std::ostringstream msg;
      msg << "duration / step size = " << p.duration / dt << " steps, over the limit of "
          << kMaxEpisodeSteps << " per episode";
      return msg.str();
    }
  }
  return "";
}

TurbulenceParams episodeTurbulence(const TurbulenceParams& base, const EpisodeStart& start,
                                   double height) {
  TurbulenceParams t = base;
  t.seed = mixSeed(base.seed, start.noise_seed, 0x7475726275ULL);
  if (t.wind_at_6m > 0.0) t.height = std::clamp(height, kMinTurbulenceHeight, kMaxTurbulenceHeight);
  return t;
}

EpisodeStart attitudeStart(double roll, double pitch) {
  EpisodeStart s;
  s.roll = roll;
  s.pitch = pitch;
  return s;
}

void applyEpisodeGusts(World& world, const std::string& name, const CreatureModel& model,
                       const EpisodeParams& p, const EpisodeStart& start, std::int64_t s,
                       double control_period) {
  auto due = [&](double time) {
    return static_cast<double>(s) == std::floor(time / control_period);
  };
  if (due(start.gust_time) && start.gust.squaredNorm() > 0.0) {
    AirParams air = world.params().air;
    air.wind += start.gust;
    world.setAirParams(air);
  }
  if (p.gust_torque != 0.0 && due(start.torque_time)) {
    ExternalWrench w;
    w.torque =
        start.torque_sign * p.gust_torque * (world.rootPose(name).orientation * Vec3::UnitX());
    w.duration = p.gust_torque_duration;
    world.applyWrench(name, w);
  }
  if (p.gust_force != 0.0 && due(start.force_time)) {
    const int link = model.findLink(start.force_link);
    if (link < 0) {
      throw InputError("episode: '" + model.name + "' has no link '" + start.force_link + "'");
    }
    ExternalWrench w;
    w.link = start.force_link;
    w.force = Vec3(0.0, 0.0, start.force_sign * p.gust_force);
    w.point = world.state(name).link_poses[link].apply(model.links[link].urdfCom());
    w.duration = p.gust_force_duration;
    world.applyWrench(name, w);
  }
}

std::vector<EpisodeStart> episodeStarts(const EpisodeParams& p, const CreatureModel* model) {
  Rng rng(mixSeed(p.seed, 0x57A27ULL));
  std::vector<EpisodeStart> starts(std::max(p.episodes, 0));
  for (size_t k = 0; k < starts.size(); ++k) {
    const double roll = rng.uniform(p.min_roll, p.max_roll);
    starts[k].roll = k % 2 == 0 ? roll : -roll;
    starts[k].pitch = rng.uniform(-p.max_pitch, p.max_pitch);
  }
  // The robust draws come from streams of their own, so the paper's starts stay the same.
  Rng robust(mixSeed(p.seed, 0x20B057ULL));
  for (EpisodeStart& s : starts) {
    for (int a = 0; a < 3; ++a) s.rate[a] = robust.uniform(-p.max_start_rate, p.max_start_rate);
    const double heading = robust.uniform(0.0, 2.0 * M_PI);
    const double speed = robust.uniform(0.0, p.max_gust);
    s.gust = Vec3(speed * std::cos(heading), speed * std::sin(heading), 0.0);
    s.gust_time = robust.uniform(0.0, 0.5 * p.duration);
    if (!p.step_sizes.empty()) s.step_size = p.step_sizes[robust.index(p.step_sizes.size())];
    s.noise_seed = robust.next();
  }
  // Wind, gusts and setpoints from a third stream: the same draws for every start whatever
  // is switched on, so switching one on changes nothing else.
  std::vector<std::string> wings;
  if (p.gust_force != 0.0 && !p.gust_link.empty() && model != nullptr &&
      model->findLink(p.gust_link) < 0) {
    throw InputError("episode: '" + model->name + "' has no link '" + p.gust_link +
                     "' (gust_link)");
  }
  if ((p.gust_force != 0.0 || p.real_air) && p.gust_link.empty()) {
    if (model == nullptr) throw InputError("episode: a push on a drawn wing needs the creature");
    for (int j : model->wing_joints)
      wings.push_back(model->links[model->joints[j].child_link].name);
    if (wings.empty()) throw InputError("episode: '" + model->name + "' has no wing to push");
  }
  Rng disturb(mixSeed(p.seed, 0xD157B5ULL));
  const double t0 = p.gust_window_start * p.duration, t1 = p.gust_window_end * p.duration;
  for (EpisodeStart& s : starts) {
    const double speed = disturb.uniform(p.min_wind, p.max_wind);
    const double heading = disturb.uniform(0.0, 2.0 * M_PI);
    s.wind = Vec3(speed * std::cos(heading), speed * std::sin(heading), 0.0);
    s.torque_time = disturb.uniform(t0, t1);
    s.torque_sign = disturb.bernoulli(0.5) ? 1.0 : -1.0;
    s.force_time = disturb.uniform(t0, t1);
    const double force_sign = disturb.bernoulli(0.5) ? 1.0 : -1.0;
    const std::uint64_t wing = disturb.next();
    const double altitude = disturb.uniform(p.min_altitude, p.max_altitude);
    s.force_link = p.gust_link;
    if (!wings.empty()) {
      s.force_link = wings[wing % wings.size()];
      s.force_sign = force_sign;
    }
    if (p.altitude_hold) s.altitude = altitude;
  }
  // Gyro biases from a fourth stream (the other draws stay as they were).
  Rng bias(mixSeed(p.seed, 0xB1A5ULL));
  for (EpisodeStart& s : starts) {
    const double size = bias.uniform(0.0, p.gyro_bias);
    const Vec3 direction(bias.normal(), bias.normal(), bias.normal());
    s.gyro_bias = size * direction.normalized();
  }
  if (p.first_start_level && !starts.empty()) {
    EpisodeStart& s = starts.front();
    s.roll = s.pitch = 0.0;
    s.rate = Vec3::Zero();
    s.gust = s.wind = Vec3::Zero();
    if (p.altitude_hold) s.altitude = p.start_height;
  }
  return starts;
}

namespace {

// The units as the controller senses them (flapsim/sensors.h): the root's IMU with the
// episode's noise through the controller's attitude filter, exact joint encoders, the
// altimeter with its noise, the root's velocity (odometry's twist) with its noise.
FlapSensing sense(const World& world, const std::string& name, const CreatureModel& model,
                  const std::vector<int>& bodies, const EpisodeParams& p, const Vec3& gyro_bias,
                  Rng& rng, AttitudeFilter& filter, double control_period) {
  const CreatureState state = world.state(name);
  const std::function<double()> normal = [&rng] { return rng.normal(); };
  ImuReading raw =
      imuReading(state, world.rootAcceleration(name), world.params().gravity, p.imu_noise, normal);
  raw.angular_velocity += gyro_bias;
  const ImuReading imu = filter.update(raw, control_period);
  double altitude = state.link_poses[0].position.z();
  if (p.altitude_noise > 0.0) altitude += p.altitude_noise * rng.normal();
  FlapSensing s =
      unitSensing(model, bodies, imu, state.joint_positions, state.joint_velocities, altitude);
  // As odometry's twist reports it: in the root's axes.
  const Quat to_body = state.link_poses[0].orientation.conjugate();
  s.velocity = groundSpeedReading(to_body * state.link_twists[0].linear, p.velocity_noise, normal);
  return s;
}

// The running sums of an episode's samples.
struct Tally {
  double score = 0.0;
  double bank = 0.0;
  double altitude_sq = 0.0;
  std::int64_t settled = 0;
  std::int64_t samples = 0;
};

// One sample of the root at `root` (time `t`) into the result's extremes and the tally;
// returns its score.
double addSample(EpisodeResult& r, Tally& tally, const EpisodeParams& p, const EpisodeStart& start,
                 const Pose& root, double t) {
  const double z = root.position.z();
  const Eigen::Matrix3d axes = root.orientation.toRotationMatrix();
  const double up = axes(2, 2);
  r.min_upright = std::min(r.min_upright, up);
  r.min_height = std::min(r.min_height, z);
  r.max_height = std::max(r.max_height, z);
  r.final_height = z;
  r.final_upright = up;
  r.lateral_drift = std::hypot(root.position.x(), root.position.y());
  if (up >= 0.5) r.upright_fraction += 1.0;
  tally.bank += std::asin(std::clamp(axes(2, 1), -1.0, 1.0));
  ++tally.samples;
  const bool settled = t > p.settle_time + 1e-9;
  if (settled) r.min_upright_settled = std::min(r.min_upright_settled, up);
  if (!start.altitude) return z;
  const double error = z - *start.altitude;
  if (settled) {
    tally.altitude_sq += error * error;
    ++tally.settled;
  }
  return -std::abs(error) - p.tilt_weight * (1.0 - up);
}

// What an altitude-holding episode loses for its settled samples: the upright floor's and the
// altitude rms ceiling's terms (the rms only if some sample settled).
double settledTerms(const EpisodeParams& p, const EpisodeResult& r, bool settled) {
  double loss = 0.0;
  if (p.upright_floor > 0.0) {
    loss += p.upright_floor_weight * std::max(0.0, p.upright_floor - r.min_upright_settled);
  }
  if (p.altitude_rms_ceiling > 0.0 && settled) {
    loss += p.altitude_rms_weight * std::max(0.0, r.altitude_rms - p.altitude_rms_ceiling);
  }
  return loss;
}

}  // namespace

EpisodeResult runEpisode(const CreatureModelPtr& model, const WingController& controller,
                         double control_period, const EpisodeParams& p, const EpisodeStart& start,
                         bool record_trace) {
  const std::string err = validateEpisodeParams(p);
  if (!err.empty()) throw InputError("episode: " + err);
  WorldParams world_params = p.world;
  if (start.step_size > 0.0) world_params.step_size = start.step_size;
  world_params.air.wind += start.wind;
  world_params.air.turbulence =
      episodeTurbulence(p.world.air.turbulence, start, start.altitude.value_or(p.start_height));
  const ControlLoop loop(control_period, world_params.step_size);
  const FlapUnitLayout layout = flapUnitLayout(*model);
  std::vector<int> bodies;
  for (const auto& name : layout.body_links) bodies.push_back(model->findLink(name));

  World world(world_params);
  // As a launch file's pose {xyz: [0, 0, h], rpy: [roll, pitch, 0]} gives it.
  const Pose pose =
      poseFromXyzRpy(Vec3(0.0, 0.0, p.start_height), Vec3(start.roll, start.pitch, 0.0));
  const std::string name = "creature";
  Twist twist;
  twist.angular = start.rate;
  world.spawn(name, model, pose, twist);

  const std::int64_t samples = loop.periodsIn(p.duration);
  Rng noise(start.noise_seed);
  AttitudeFilter filter(controller.attitudeFilterTime());
  EpisodeResult result;
  result.max_height = -std::numeric_limits<double>::infinity();
  result.min_height = std::numeric_limits<double>::infinity();
  Tally tally;
  for (std::int64_t s = 0; s < samples; ++s) {
    applyEpisodeGusts(world, name, *model, p, start, s, control_period);
    FlapSensing sensed =
        sense(world, name, *model, bodies, p, start.gyro_bias, noise, filter, control_period);
    sensed.setpoint = start.altitude;
    const std::vector<StrokeCommand> commands = controller.commands(sensed);
    world.setWingCommands(name, layout.wing_joints, commands);
    world.step(loop.stepsPerPeriod());

    const Pose root = world.rootPose(name);
    const double t = static_cast<double>(s + 1) * control_period;
    const double score = addSample(result, tally, p, start, root, t);
    result.flipped = result.flipped || result.final_upright < 0.0;
    result.crashed = result.crashed || root.position.z() < p.crash_height;
    if (p.flip_penalty > 0.0 && (result.flipped || result.crashed)) {
      // Upside down or crashed: the rest of the flight scores the score here less the penalty.
      tally.score += static_cast<double>(samples - s) * (score - p.flip_penalty);
      break;
    }
    tally.score += score;
    if (record_trace) {
      EpisodeSample sample;
      sample.time = t;
      sample.height = root.position.z();
      sample.upright = result.final_upright;
      sample.root = root;
      sample.air = world.airVelocity(name);
      for (const auto& c : commands) {
        sample.downstroke.push_back(c.downstroke_rate);
        sample.upstroke.push_back(c.upstroke_rate);
      }
      result.trace.push_back(std::move(sample));
    }
  }
  const double n = static_cast<double>(std::max<std::int64_t>(samples, 1));
  result.fitness = tally.score / n;
  result.upright_fraction /= n;
  result.mean_bank = tally.bank / static_cast<double>(std::max<std::int64_t>(tally.samples, 1));
  if (tally.settled > 0) {
    result.altitude_rms = std::sqrt(tally.altitude_sq / static_cast<double>(tally.settled));
  }
  if (start.altitude) result.fitness -= settledTerms(p, result, tally.settled > 0);
  const CreaturePower power = world.power(name);
  result.positive_power = power.meanPositivePower();
  result.net_power = power.time > 0.0 ? power.totalWork() / power.time : 0.0;
  result.mass = power.mass;
  return result;
}

}  // namespace flapsim
