// Joint drives: how each movable joint is driven in a step (wing strokes, velocity targets,
// feathering, passive damping and Coulomb friction), turned into servo demands and torques
// on a creature's body. Private to flapsim_core.
#pragma once

#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/stroke.h"

namespace flapsim {

struct CreatureBody;

// Time constant of the feathering servo.
constexpr double kFeatherTime = 0.005;

// How a movable joint is driven this step.
struct JointDrive {
  enum class Mode { kPassive, kStroke, kVelocity };
  Mode mode = Mode::kPassive;
  StrokeGenerator stroke;
  double velocity = 0.0;
};

// Joint damping is applied as an explicit torque -d qdot, stable while d dt stays well
// under the joint's inertia. Beyond that it is capped at a quarter of the child link's own
// inertia about the axis per step: the joint is then nearly rigid in velocity either way,
// and a large URDF damping cannot make the step blow up.
double dampingLimit(const CreatureModel& m, const JointModel& j, double dt);
// A <spring> is an explicit torque -k (q - reference), stable while the child link's own
// oscillation sqrt(k / I) dt stays below 2; beyond a quarter of I / dt^2 it is capped there.
double stiffnessLimit(const CreatureModel& m, const JointModel& j, double dt);

// A wing reversing in the next step of `b`: whether a stroke reaches its turning point
// within the step or a stroke's servo was saturated in the last one (the stretch in which a
// wing reverses under its effort limit), and when into the step the first stroke turns (the
// step itself if none does).
struct StrokeTurn {
  bool reversing = false;
  double first_turn = 0.0;
};
StrokeTurn strokeTurn(const CreatureModel& m, const std::vector<JointDrive>& drives,
                      const CreatureBody& b, double dt);

// Sets this step's servo demands and damping torques of every movable joint of `b` from
// `drives` (one per model joint; strokes advance their phase), then the feathering servos.
void applyDrives(const CreatureModel& m, std::vector<JointDrive>& drives, CreatureBody& b,
                 double dt);

}  // namespace flapsim
