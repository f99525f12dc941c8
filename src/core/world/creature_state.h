// Reading and setting a creature's state between steps. Private to flapsim_core.
#pragma once

#include <string>

#include "flapsim/world.h"
#include "world/creature.h"

namespace flapsim {

struct Motion {
  Pose pose;
  Twist twist;  // of the frame's origin
};

// A link frame's pose and twist given those of a frame at `frame` in it (the given ones, bit
// for bit, when `frame` is exactly the link frame).
Motion linkMotion(const Pose& pose, const Twist& twist, const Pose& frame);

// The creature's state, read without changing it (the link frames computed into locals).
CreatureState readState(const CreatureModel& m, const CreatureSim& sim);

// Puts the creature in `request`'s state (checked by World::setState, but for what needs the
// body: the link, a fixed base, the speed limit, each refused with an InputError naming
// `name`, the state unchanged).
void placeCreature(const std::string& name, const CreatureModel& m, CreatureSim& sim,
                   const StateRequest& request, double max_speed);

}  // namespace flapsim
