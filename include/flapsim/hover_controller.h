// The hover controller of the hover creature (make_creature --layout hover): PD with integral
// on the height, PD on the attitude, and a slow hold of the horizontal position, from what an
// IMU and an altimeter give. Its default gains are the hand-designed ones; evolve --preset
// hover evolves them on the episode farm (flapsim/hover_evolution.h, config/hover_1_gains.yaml).
// ROS-free; no clock.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "flapsim/stroke.h"
#include "flapsim/types.h"

namespace flapsim {

/// Gains and trim of the hover controller. Strokes are sine strokes (StrokeShape::kSine) of
/// both wings at one frequency, the wings pitched +feather in the forward stroke (the
/// downstroke) and -feather back:
///  - height: the frequency, f = trim_frequency sqrt(1 + a / g) with a = height_gain e +
///    height_integral int(e) - climb_damping vz (lift grows as f^2), over the cosine of the tilt;
///  - roll: the wings' amplitudes, amplitude (1 +- u) left and right at the same frequency
///    (their lift grows as amplitude^2), u = roll_gain e_x + attitude_integral int(e_x) -
///    roll_damping p;
///  - pitch: the strokes' mean angle (StrokeCommand::offset), which moves the lift fore or aft of
///    the centre of mass, offset = pitch_gain e_y + attitude_integral int(e_y) - pitch_damping q
///    (the integrals trim a steady moment: a side wind rolls the creature with it, as the swept
///    wings meet the sideways flow unequally);
///  - start: from the first update the amplitudes grow from start_amplitude of theirs to the
///    whole over start_time at the same wing speed (the stroke rate kept, so the frequency
///    falls from 1 / start_amplitude of its value): a stroke from rest begins with a short
///    half-stroke on one side of the body, whose lift and drag moment the rest of the stroke
///    does not balance, and a smaller first stroke kicks the body less;
///  - position: the attitude aimed at leans the lift against the horizontal position error, its
///    integral and the velocity, tilt = -position_gain (x - x0) - position_integral int(x - x0)
///    - velocity_gain v, at most max_tilt (x0: where the first update found the creature).
/// e is the rotation (rad, body axes) from the body's up axis to the one aimed at and p, q the
/// body rates, each averaged over the last stroke period (at the frequency last commanded): the
/// body rocks at the stroke's frequency (the wings' drag pulls the hinges fore and aft above the
/// centre of mass), and the strokes take a new amplitude or offset at their turns, so an unfiltered
/// reading, sampled at the same phase of every stroke, would steer by the rocking.
struct HoverControllerParams {
  double altitude = 3.0;              // m, of the root link's origin
  double trim_frequency = 14.5;       // Hz: the stroke frequency that about carries the weight
  double amplitude = 1.0;             // rad, each wing's stroke amplitude at zero roll
  double feather = 0.61;              // rad, mid-stroke pitch (35 deg)
  double height_gain = 4.0;           // 1/s^2
  double climb_damping = 3.0;         // 1/s
  double height_integral = 1.0;       // 1/s^3
  double max_frequency_ratio = 1.35;  // f within [1 / this, this] x trim_frequency
  double roll_gain = 0.12;            // per rad
  double roll_damping = 0.015;        // per rad/s
  double max_roll_share = 0.2;        // |u| at most
  double pitch_gain = 0.2;            // rad of offset per rad
  double pitch_damping = 0.025;       // rad of offset per rad/s
  double max_offset = 0.25;           // rad
  double attitude_integral = 0.3;     // per rad s (roll share), rad of offset per rad s (pitch)
  double position_gain = 0.1;         // rad of tilt per m
  double position_integral = 0.02;    // rad of tilt per m s
  double velocity_gain = 0.15;        // rad of tilt per m/s
  double max_tilt = 0.2;              // rad
  /// rad: a wing's amplitude + |offset| at most this (its amplitude cut to fit), inside the
  /// hover wings' stops at +-1.5 rad; the hand-designed gains never reach it (1.2 + 0.25).
  double max_stroke = 1.45;
  double start_time = 0.4;       // s over which the amplitudes grow to the whole (0: at once)
  double start_amplitude = 0.6;  // the amplitudes' share at the first update, (0, 1]
};

/// Empty if valid, else a message naming the bad field.
std::string validateHoverControllerParams(const HoverControllerParams& params);

/// A field of HoverControllerParams by name: the hover_controller node's private parameter and
/// the gains file's key (flapsim/hover_gains.h) of the same name.
struct HoverParamField {
  const char* name;
  double HoverControllerParams::*member;
};
/// Every field of HoverControllerParams, in declaration order.
const std::vector<HoverParamField>& hoverParamFields();

/// What the controller reads: an IMU's orientation and body rates, and the root's position and
/// velocity in the world frame (an altimeter, a position fix: the odometry).
struct HoverSensors {
  Quat orientation = Quat::Identity();
  Vec3 angular_velocity = Vec3::Zero();  // body frame
  Vec3 position = Vec3::Zero();          // world frame
  Vec3 velocity = Vec3::Zero();          // world frame
};

class HoverController {
 public:
  /// Throws InputError for invalid params.
  explicit HoverController(const HoverControllerParams& params = HoverControllerParams());
  /// The left and right wings' strokes after `dt` s since the last update (the first update
  /// after construction or reset() also takes the horizontal position to hold).
  std::array<StrokeCommand, 2> update(const HoverSensors& sensors, double dt);
  void reset();
  const HoverControllerParams& params() const { return params_; }

 private:
  // The mean of a signal over the last `window` s of updates.
  struct WindowMean {
    struct Sample {
      Vec3 value;
      double dt;
    };
    std::vector<Sample> samples;  // oldest first
    double time = 0.0;            // summed dt of the samples
    Vec3 add(const Vec3& value, double dt, double window);
  };

  HoverControllerParams params_;
  bool started_ = false;
  double elapsed_ = 0.0;                   // s of updates since the first (the start's clock)
  Vec3 hold_ = Vec3::Zero();               // the horizontal position held
  double integral_ = 0.0;                  // of the height error, m s
  double frequency_ = 0.0;                 // Hz, last commanded (0: none yet)
  Vec3 attitude_integral_ = Vec3::Zero();  // of the attitude error (body axes), rad s
  Vec3 position_integral_ = Vec3::Zero();  // of the horizontal position error, m s
  WindowMean error_mean_, rate_mean_;
};

/// The hover creature's wing joints in the order HoverController::update gives their strokes.
constexpr const char* kHoverWingJoints[2] = {"wing_left_joint", "wing_right_joint"};

}  // namespace flapsim
