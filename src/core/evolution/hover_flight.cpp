#include "flapsim/hover_flight.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "flapsim/ga.h"

namespace flapsim {

std::string validateHoverFlightParams(const HoverFlightParams& p) {
  if (!(p.duration > 0.0) || !std::isfinite(p.duration)) return "duration must be > 0";
  if (!(p.settle >= 0.0) || p.settle >= p.duration) return "settle must be in [0, duration)";
  if (!std::isfinite(p.start_roll) || !std::isfinite(p.start_pitch) || !p.start_rate.allFinite()) {
    return "start roll, pitch and rate must be finite";
  }
  if (p.start_height && !std::isfinite(*p.start_height)) return "start height must be finite";
  const std::string noise = validateImuNoise(p.imu_noise);
  if (!noise.empty()) return noise;
  const double steps = p.control_period / p.world.step_size;
  if (!(p.control_period > 0.0) || std::abs(steps - std::round(steps)) > 1e-9 * steps ||
      std::round(steps) < 1.0) {
    return "control_period must be a positive multiple of the world's step";
  }
  const std::string w = validateWorldParams(p.world);
  return w.empty() ? "" : "world: " + w;
}

namespace {

// The controller's sensors: the root's IMU (with the flight's noise, and the gyro bias of its
// disturbances) and its odometry (with the altimeter's noise on the height, from a generator
// of its own so that the IMU's draws stay as they were).
HoverSensors hoverSensors(const CreatureState& s, const HoverFlightParams& p, Rng& rng,
                          Rng& altimeter) {
  const ImuReading imu =
      imuReading(s, Vec3::Zero(), Vec3::Zero(), p.imu_noise, [&rng] { return rng.normal(); });
  HoverSensors sensors;
  sensors.orientation = imu.orientation;
  sensors.angular_velocity = imu.angular_velocity;
  sensors.position = s.link_poses[0].position;
  sensors.velocity = s.link_twists[0].linear;
  if (p.gusts) {
    sensors.angular_velocity += p.gust_start.gyro_bias;
    if (p.gusts->altitude_noise > 0.0) {
      sensors.position.z() += p.gusts->altitude_noise * altimeter.normal();
    }
  }
  return sensors;
}

// The figures after the settling time, step by step.
struct HoverFigures {
  HoverFlightResult& r;
  double altitude;
  double stroke_low = std::numeric_limits<double>::infinity(), stroke_high = -stroke_low;
  double stroke_time = 0.0, squares = 0.0, bank = 0.0;
  long samples = 0;

  // `bank_now`: bankAngle of the pose's orientation.
  void add(const Pose& pose, double bank_now, double step, double frequency) {
    const double z = pose.position.z();
    r.min_height = std::min(r.min_height, z);
    r.max_height = std::max(r.max_height, z);
    r.min_upright = std::min(r.min_upright, (pose.orientation * Vec3::UnitZ()).z());
    bank += bank_now;
    squares += (z - altitude) * (z - altitude);
    ++samples;
    stroke_low = std::min(stroke_low, z);
    stroke_high = std::max(stroke_high, z);
    stroke_time += step;
    if (stroke_time >= 1.0 / frequency) {
      r.max_stroke_oscillation = std::max(r.max_stroke_oscillation, stroke_high - stroke_low);
      stroke_low = std::numeric_limits<double>::infinity();
      stroke_high = -stroke_low;
      stroke_time = 0.0;
    }
  }
};

}  // namespace

HoverFlightResult flyHover(const CreatureModelPtr& model, const HoverControllerParams& controller,
                           const HoverFlightParams& p) {
  const std::string err = validateHoverFlightParams(p);
  if (!err.empty()) throw InputError("hover flight: " + err);
  World world(p.world);
  const std::string name = "hover";
  const Pose start = poseFromXyzRpy(Vec3(0.0, 0.0, p.start_height.value_or(controller.altitude)),
                                    Vec3(p.start_roll, p.start_pitch, 0.0));
  Twist spin;
  spin.angular = p.start_rate;
  world.spawn(name, model, start, spin);
  HoverController control(controller);
  Rng rng(p.noise_seed);
  Rng altimeter(mixSeed(p.noise_seed, 0xA171ULL));
  const std::vector<std::string> wings = {kHoverWingJoints[0], kHoverWingJoints[1]};
  const int steps = static_cast<int>(std::lround(p.control_period / p.world.step_size));
  const int updates = static_cast<int>(std::lround(p.duration / p.control_period));
  HoverFlightResult r;
  r.min_height = std::numeric_limits<double>::infinity();
  r.max_height = -r.min_height;
  r.mass = model->totalMass();
  r.lowest_height = start.position.z();
  r.start_tilt = std::acos(std::clamp((start.orientation * Vec3::UnitZ()).z(), -1.0, 1.0));
  HoverFigures figures{r, controller.altitude};
  CreaturePower settled;
  double frequency_sum = 0.0;
  int counted = 0;
  for (int u = 0; u < updates && !(p.end_on_flip && r.flipped); ++u) {
    if (p.gusts) {
      applyEpisodeGusts(world, name, *model, *p.gusts, p.gust_start, u, p.control_period);
    }
    auto strokes =
        control.update(hoverSensors(world.state(name), p, rng, altimeter), p.control_period);
    if (p.override_strokes) p.override_strokes(world.time(), strokes);
    world.setWingCommands(name, wings, {strokes[0], strokes[1]});
    const double frequency = strokes[0].downstroke_rate / (4.0 * strokes[0].amplitude);
    for (int k = 0; k < steps; ++k) {
      world.step(1);
      const Pose pose = world.rootPose(name);
      const double up = (pose.orientation * Vec3::UnitZ()).z();
      r.lowest_upright = std::min(r.lowest_upright, up);
      const double bank = bankAngle(pose.orientation);
      r.largest_bank = std::max(r.largest_bank, std::abs(bank));
      r.lowest_height = std::min(r.lowest_height, pose.position.z());
      if (up < 0.0) r.flipped = true;
      if (world.time() <= p.settle + 0.5 * p.world.step_size) continue;
      figures.add(pose, bank, p.world.step_size, frequency);
    }
    if (world.time() <= p.settle + 0.5 * p.world.step_size) {
      settled = world.power(name);
    } else {
      frequency_sum += frequency;
      ++counted;
    }
  }
  const CreaturePower end = world.power(name);
  const double time = end.time - settled.time;
  r.positive_power =
      time > 0.0 ? (end.totalPositiveWork() - settled.totalPositiveWork()) / time : 0.0;
  r.net_power = time > 0.0 ? (end.totalWork() - settled.totalWork()) / time : 0.0;
  r.mean_frequency = counted > 0 ? frequency_sum / counted : 0.0;
  r.altitude_rms = figures.samples > 0 ? std::sqrt(figures.squares / figures.samples)
                                       : std::numeric_limits<double>::quiet_NaN();
  r.mean_bank = figures.samples > 0 ? figures.bank / figures.samples : 0.0;
  r.start_sag = std::max(0.0, std::min(start.position.z(), controller.altitude) - r.lowest_height);
  r.drift = world.rootPose(name).position - start.position;
  r.drift.z() = 0.0;
  return r;
}

double strokeDiskArea(const CreatureModel& m, double amplitude) {
  double area = 0.0;
  for (int w : m.wing_joints) {
    const JointModel& hinge = m.joints[w];
    // The links hanging from the hinge (links are stored parent before child), and the
    // farthest corner of their boxes from the hinge's axis, all at zero joint angles.
    std::vector<Pose> in_hinge(m.links.size());  // link frame in the hinge's child frame
    std::vector<bool> below(m.links.size(), false);
    below[hinge.child_link] = true;
    double reach = 0.0;
    for (size_t k = static_cast<size_t>(hinge.child_link); k < m.links.size(); ++k) {
      const LinkModel& l = m.links[k];
      if (k != static_cast<size_t>(hinge.child_link)) {
        if (l.parent_joint < 0 || !below[m.joints[l.parent_joint].parent_link]) continue;
        const JointModel& j = m.joints[l.parent_joint];
        in_hinge[k] = in_hinge[j.parent_link] * j.origin;
        below[k] = true;
      }
      for (const Box& b : l.boxes) {
        for (int c = 0; c < 8; ++c) {
          const Vec3 corner(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5);
          const Vec3 p = in_hinge[k].apply(b.origin.apply(corner.cwiseProduct(b.size)));
          reach = std::max(reach, (p - p.dot(hinge.axis) * hinge.axis).norm());
        }
      }
    }
    area += amplitude * reach * reach;
  }
  return area;
}

double idealHoverPower(double weight, double density, double area) {
  return std::sqrt(weight * weight * weight / (2.0 * density * area));
}

}  // namespace flapsim
