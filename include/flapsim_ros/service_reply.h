// How the simulator node's services answer a request they refuse: `success` false, the
// status message naming the cause, and a throttled warning.
#pragma once

#include <string>

#include "flapsim/types.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/warning_limiter.h"

namespace flapsim_ros {

/// A refused request: `res` says `refusal` + the error, and a throttled warning too (its
/// kind: the service, the first word of `refusal`, and the error's kind).
template <class Response>
void refuse(CreatureRegistry& creatures, Response& res, const std::string& refusal,
            const std::string& creature, const flapsim::InputError& e) {
  res.success = false;
  res.status_message = refusal + e.what();
  creatures.warn(refusal.substr(0, refusal.find(' ')) + "/" + WarningLimiter::kindOf(e.what()),
                 creature, res.status_message);
}

/// Runs `body`, which fills in `res` (but its `success`); an InputError it throws makes the
/// request refused (refuse). Returns true (the call itself is answered).
template <class Response, class Body>
bool serve(CreatureRegistry& creatures, Response& res, const std::string& refusal,
           const std::string& creature, Body body) {
  try {
    body();
    res.success = true;
  } catch (const flapsim::InputError& e) {
    refuse(creatures, res, refusal, creature, e);
  }
  return true;
}

}  // namespace flapsim_ros
