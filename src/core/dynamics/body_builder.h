// Building a creature's body: its multibody, colliders, aero bodies, joint limits and
// servos, in a Bullet scene of its own. Private to flapsim_core.
#pragma once

#include <memory>

#include "dynamics/creature_body.h"
#include "flapsim/creature_model.h"
#include "flapsim/types.h"
#include "flapsim/world.h"

namespace flapsim {

// The body of creature `m` with its root link frame at `pose` moving with `twist`. The body
// keeps a pointer to `m`, which must outlive it.
std::unique_ptr<CreatureBody> buildBody(const CreatureModel& m, const Pose& pose,
                                        const Twist& twist, const WorldParams& params);

}  // namespace flapsim
