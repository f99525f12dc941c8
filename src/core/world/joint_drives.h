// The actuation stage of a step: how each movable joint is driven (wing strokes, velocity
// targets, feathering, passive damping, springs and Coulomb friction), turned into this
// step's servo demands (dynamics/servo_stage.h) and passive joint torques on the multibody.
// Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/stroke.h"

namespace flapsim {

class ServoStage;

// Time constant of the feathering servo.
constexpr double kFeatherTime = 0.005;

// How a movable joint is driven this step.
struct JointDrive {
  enum class Mode { kPassive, kStroke, kVelocity, kHold };
  Mode mode = Mode::kPassive;
  StrokeGenerator stroke;
  double velocity = 0.0;
  double position = 0.0;  // kHold: the angle held, approached with the time constant kHoldTime
};

// A held joint's servo asks for (held angle - angle) / kHoldTime: a load that a velocity target
// of zero let creep (contacts act after the servo) leaves an offset of creep x kHoldTime.
constexpr double kHoldTime = 0.01;  // s

// A wing reversing in the next step of the multibody `mb`: whether a stroke reaches its turning
// point within the step or a stroke's servo was saturated in the last one (the stretch in which a
// wing reverses under its effort limit), and when into the step the first stroke turns (the
// step itself if none does).
struct StrokeTurn {
  bool reversing = false;
  double first_turn = 0.0;
};
StrokeTurn strokeTurn(const CreatureModel& m, const std::vector<JointDrive>& drives,
                      const ServoStage& servos, const btMultiBody& mb, double dt);

// Sets this step's servo demands and passive torques of every movable joint from `drives`
// (one per model joint; strokes advance their phase), then the feathering servos.
void applyDrives(const CreatureModel& m, std::vector<JointDrive>& drives, ServoStage& servos,
                 btMultiBody& mb, double dt);

}  // namespace flapsim
