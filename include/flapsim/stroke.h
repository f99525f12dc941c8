// The flapping stroke: a wing-rate command turned into a joint-velocity target.
#pragma once

#include <string>

namespace flapsim {

/// How the wing angle moves between its turning points.
///  - kTriangle (the paper's): at the constant rate w1 down, w2 up; the velocity reverses at
///    each turn within a step.
///  - kSine: each half-stroke a half cosine of the triangle's duration (2 theta0 / w), from
///    rest at one turning point to rest at the other, peaking at pi/2 w mid-stroke: the
///    smooth stroke of hummingbirds, insects and resonant flapping robots, whose motor does
///    not have to reverse the wing at once. With w1 != w2 the two halves differ in length
///    ("split cycle"). The stroke follows time, not the wing: a wing that lags is driven back
///    onto it. A half-stroke runs from where the last one ended to the turning point of the
///    command at its start, so a new amplitude or offset takes effect at the next turn
///    without a jump (a new rate at once); the first starts from the wing's angle.
///    Feathering turns the wing smoothly across each turn (kSineFlipFraction).
enum class StrokeShape { kTriangle, kSine };

/// "triangle" or "sine"; std::invalid_argument naming the text otherwise.
StrokeShape strokeShapeFromString(const std::string& text);
std::string toString(StrokeShape shape);

/// Downstroke rate w1 and upstroke rate w2 (rad/s, >= 0), amplitude theta0 (rad, >= 0).
struct StrokeCommand {
  double downstroke_rate = 0.0;
  double upstroke_rate = 0.0;
  double amplitude = 0.0;
  /// Feathering: pitch (rad, |.| <= pi/2) of the wing about its span during the upstroke,
  /// for wings with a feather joint; 0 keeps the wing flat.
  double feather = 0.0;
  /// The pitch during the downstroke (rad, |.| <= pi/2); 0 (the paper's) keeps it flat. A
  /// hovering wing flies +alpha one way and -alpha back.
  double downstroke_feather = 0.0;
  /// The stroke's mean angle (rad): it turns at offset - amplitude and offset + amplitude.
  /// Moves the wings' lift forward or back (a hovering flier's pitch control).
  double offset = 0.0;
  StrokeShape shape = StrokeShape::kTriangle;
};

/// Largest stroke rate (rad/s) and amplitude (rad) a command may give.
constexpr double kMaxStrokeRate = 1e5;
constexpr double kMaxStrokeAmplitude = 1e3;

/// Of a sine stroke's half-strokes, the fraction on each side of a turn in which a feathering
/// wing turns from one half-stroke's pitch to the other's, along a quarter sine on each side
/// (so the wing is half-way at the turn and turns at the same rate across it): the flip
/// takes 25 % of a stroke cycle, within the 16-32 % of the Robofly's symmetric rotations
/// (Dickinson, Lehmann & Sane 1999).
constexpr double kSineFlipFraction = 0.25;

/// Empty string if valid, else a message naming the bad field.
std::string validateStroke(const StrokeCommand& command);

/// Swings down at w1 to offset - theta0, then up at w2 to offset + theta0, and repeats.
/// Starts with a downstroke. Pure state machine: no clock, no physics.
class StrokeGenerator {
 public:
  enum class Phase { kDown, kUp };

  /// A new shape (or the first command) starts the stroke where the wing is at the next
  /// target() call.
  void setCommand(const StrokeCommand& command);
  const StrokeCommand& command() const { return command_; }
  Phase phase() const { return phase_; }
  void reset() {
    phase_ = Phase::kDown;
    started_ = false;
  }

  /// Joint-velocity target for the current joint angle (updates the phase). With a step
  /// `dt` > 0 it is the mean velocity over the next step of the ideal stroke from this
  /// angle: a step in which the stroke would reach its turning point goes there and back
  /// for the rest of the step, so the turn falls where the command says whatever the step
  /// size (without it, a wing overshoots by up to one step's travel, w dt). A sine stroke
  /// advances its clock by `dt` and asks for the velocity that reaches the stroke's angle at
  /// the end of the step.
  double target(double joint_position, double dt = 0.0);
  /// Time until the stroke reaches its next turning point from this angle at the current
  /// phase's rate (0 if it is there or past it; infinity at rate 0). Changes nothing.
  double timeToTurn(double joint_position) const;
  /// The feather angle the wing should have now (after target() for a step: at its end): a
  /// triangle stroke's half-stroke pitch, a sine stroke's smooth turn between them.
  double featherTarget() const;

 private:
  double sineTarget(double q, double dt);
  double halfPeriod(Phase phase) const;    // s; infinity at rate 0
  double turningPoint(Phase phase) const;  // where a half-stroke of `phase` turns (rad)

  StrokeCommand command_;
  Phase phase_ = Phase::kDown;
  bool started_ = false;   // a sine stroke's half-stroke is set
  double progress_ = 0.0;  // sine: fraction of the current half-stroke done, [0, 1)
  double from_ = 0.0;      // sine: the current half-stroke's start and end angles (rad)
  double to_ = 0.0;
};

}  // namespace flapsim
