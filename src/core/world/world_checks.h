// Every argument check of World in one place, each a rule of a table that names the value,
// its bounds and its unit: an empty string if the argument is valid, else the message that
// World's InputError carries. Private to flapsim_core (validateWorldParams is public, in
// flapsim/world.h).
#pragma once

#include <string>
#include <vector>

#include "flapsim/world.h"

namespace flapsim {

std::string checkAir(const AirParams& air);
std::string checkGravity(const Vec3& gravity);
// A creature's pose: a finite position within +-kMaxPosition, a quaternion of usable norm.
std::string checkPose(const Pose& pose);
// A creature's twist: linear at most `max_speed`, angular at most kMaxSpin.
std::string checkTwist(const Twist& twist, double max_speed);
// `values` (named `what`, one per model joint or none): finite, 0 for fixed joints, within
// a joint's limits (positions) or +-kMaxSpin (velocities).
std::string checkJointValues(const CreatureModel& m, const std::vector<double>& values,
                             const std::string& what, bool positions);
// An external wrench's force, torque, point, duration and start time.
std::string checkWrench(const ExternalWrench& wrench);
// At most `max_cells` air cells on creature `name` under `air`, else a message naming it, its
// count and its largest link.
std::string checkCells(const std::string& name, const CreatureModel& m, const AirParams& air,
                       int max_cells);

// `p` if valid (validateWorldParams), else InputError naming the bad parameter.
WorldParams checked(const WorldParams& p);
// Throws InputError("creature 'name': " + err) unless `err` is empty.
void refuse(const std::string& name, const std::string& err);

}  // namespace flapsim
