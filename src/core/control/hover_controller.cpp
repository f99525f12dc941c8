#include "flapsim/hover_controller.h"

#include <algorithm>
#include <cmath>

namespace flapsim {

const std::vector<HoverParamField>& hoverParamFields() {
  using P = HoverControllerParams;
  static const std::vector<HoverParamField> fields = {
      {"altitude", &P::altitude},
      {"trim_frequency", &P::trim_frequency},
      {"amplitude", &P::amplitude},
      {"feather", &P::feather},
      {"height_gain", &P::height_gain},
      {"climb_damping", &P::climb_damping},
      {"height_integral", &P::height_integral},
      {"max_frequency_ratio", &P::max_frequency_ratio},
      {"roll_gain", &P::roll_gain},
      {"roll_damping", &P::roll_damping},
      {"max_roll_share", &P::max_roll_share},
      {"pitch_gain", &P::pitch_gain},
      {"pitch_damping", &P::pitch_damping},
      {"max_offset", &P::max_offset},
      {"attitude_integral", &P::attitude_integral},
      {"position_gain", &P::position_gain},
      {"position_integral", &P::position_integral},
      {"velocity_gain", &P::velocity_gain},
      {"max_tilt", &P::max_tilt},
      {"max_stroke", &P::max_stroke},
      {"start_time", &P::start_time},
      {"start_amplitude", &P::start_amplitude}};
  return fields;
}

std::string validateHoverControllerParams(const HoverControllerParams& p) {
  for (const HoverParamField& f : hoverParamFields()) {
    if (!std::isfinite(p.*f.member)) return std::string(f.name) + " must be finite";
  }
  if (p.trim_frequency <= 0.0) return "trim_frequency must be > 0";
  if (p.amplitude <= 0.0) return "amplitude must be > 0";
  if (std::abs(p.feather) > M_PI / 2) return "feather must be within +-pi/2";
  if (p.max_frequency_ratio < 1.0) return "max_frequency_ratio must be >= 1";
  if (p.max_roll_share < 0.0 || p.max_roll_share >= 1.0) return "max_roll_share must be in [0, 1)";
  if (p.max_offset < 0.0 || p.max_tilt < 0.0) return "max_offset and max_tilt must be >= 0";
  if (!(p.max_stroke > p.max_offset)) return "max_stroke must be > max_offset";
  if (p.start_time < 0.0) return "start_time must be >= 0";
  if (!(p.start_amplitude > 0.0 && p.start_amplitude <= 1.0)) {
    return "start_amplitude must be in (0, 1]";
  }
  return "";
}

HoverController::HoverController(const HoverControllerParams& params) : params_(params) {
  const std::string err = validateHoverControllerParams(params);
  if (!err.empty()) throw InputError("hover controller: " + err);
}

void HoverController::reset() {
  started_ = false;
  elapsed_ = 0.0;
  integral_ = 0.0;
  frequency_ = 0.0;
  attitude_integral_.setZero();
  position_integral_.setZero();
  error_mean_ = WindowMean();
  rate_mean_ = WindowMean();
}

Vec3 HoverController::WindowMean::add(const Vec3& value, double dt, double window) {
  samples.push_back(Sample{value, dt});
  time += dt;
  size_t drop = 0;
  while (drop + 1 < samples.size() && time - samples[drop].dt >= window) time -= samples[drop++].dt;
  samples.erase(samples.begin(), samples.begin() + static_cast<long>(drop));
  Vec3 sum = Vec3::Zero();
  for (const Sample& s : samples) sum += s.value * s.dt;
  return time > 0.0 ? Vec3(sum / time) : value;
}

std::array<StrokeCommand, 2> HoverController::update(const HoverSensors& s, double dt) {
  const HoverControllerParams& p = params_;
  constexpr double g = 9.81;
  dt = std::max(dt, 0.0);
  if (!started_) {
    hold_ = s.position;
    started_ = true;
  } else {
    elapsed_ += dt;
  }
  // The start: the amplitudes' share, growing to 1 over start_time at the same wing speed.
  const double share =
      p.start_time > 0.0
          ? std::min(1.0, p.start_amplitude + (1.0 - p.start_amplitude) * elapsed_ / p.start_time)
          : 1.0;
  // One stroke at the frequency last commanded.
  const double period = 1.0 / (frequency_ > 0.0 ? frequency_ : p.trim_frequency);

  // Where the body's up axis should point: up, leaned against the horizontal error.
  Vec3 off = s.position - hold_;
  off.z() = 0.0;
  Vec3 lean = -p.position_gain * off - p.position_integral * position_integral_ -
              p.velocity_gain * s.velocity;
  lean.z() = 0.0;
  if (lean.norm() > p.max_tilt) {
    lean *= p.max_tilt / lean.norm();
  } else {
    position_integral_ += off * dt;  // no wind-up at the tilt limit
  }
  const Vec3 aim = (Vec3::UnitZ() + lean).normalized();
  const Vec3 up = s.orientation * Vec3::UnitZ();
  // The rotation from the body's up axis to the aim, in body axes.
  const Vec3 error = error_mean_.add(s.orientation.conjugate() * up.cross(aim), dt, period);
  const Vec3 rates = rate_mean_.add(s.angular_velocity, dt, period);

  // Height: the lift's vertical share is up.z of it.
  const double e = p.altitude - s.position.z();
  integral_ += e * dt;
  const double a =
      p.height_gain * e + p.height_integral * integral_ - p.climb_damping * s.velocity.z();
  const double lift = std::max(0.05, (1.0 + a / g) / std::max(0.5, up.z()));
  const double ratio =
      std::clamp(std::sqrt(lift), 1.0 / p.max_frequency_ratio, p.max_frequency_ratio);
  const double frequency = p.trim_frequency * ratio;
  frequency_ = frequency / share;  // the stroke's own: its amplitude is share x at that rate

  // The integrals stop growing while their output is at its limit (no wind-up).
  const Vec3 trim = p.attitude_integral * attitude_integral_;
  const double roll_raw = p.roll_gain * error.x() + trim.x() - p.roll_damping * rates.x();
  const double offset_raw = p.pitch_gain * error.y() + trim.y() - p.pitch_damping * rates.y();
  const double roll = std::clamp(roll_raw, -p.max_roll_share, p.max_roll_share);
  const double offset = std::clamp(offset_raw, -p.max_offset, p.max_offset);
  if (roll == roll_raw) attitude_integral_.x() += error.x() * dt;
  if (offset == offset_raw) attitude_integral_.y() += error.y() * dt;
  std::array<StrokeCommand, 2> out;
  for (int side = 0; side < 2; ++side) {
    StrokeCommand& c = out[side];
    c.shape = StrokeShape::kSine;
    const double amplitude = std::min(p.amplitude * (side == 0 ? 1.0 + roll : 1.0 - roll),
                                      p.max_stroke - std::abs(offset));
    // Half a period per half-stroke: 2 amplitude / rate = 1 / (2 f), at the start's share.
    c.downstroke_rate = c.upstroke_rate = 4.0 * amplitude * frequency;
    c.amplitude = share * amplitude;
    c.offset = offset;
    c.downstroke_feather = p.feather;
    c.feather = -p.feather;
  }
  return out;
}

}  // namespace flapsim
