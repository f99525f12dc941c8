#include "flapsim/control_loop.h"

#include <cmath>
#include <sstream>

#include "flapsim/types.h"

namespace flapsim {

ControlLoop::ControlLoop(double control_period, double step_size)
    : period_(control_period), step_size_(step_size), steps_(0) {
  const double steps = std::isfinite(control_period) && std::isfinite(step_size) && step_size > 0.0
                           ? std::round(control_period / step_size)
                           : 0.0;
  if (!(control_period > 0.0) || steps < 1.0 || steps > 1e9 ||
      std::abs(steps * step_size - control_period) > 1e-9 * control_period) {
    std::ostringstream msg;
    msg << "the control period " << control_period
        << " s is not a whole number of simulator steps of " << step_size << " s";
    throw InputError(msg.str());
  }
  steps_ = static_cast<int>(steps);
}

std::int64_t ControlLoop::periodsIn(double duration) const {
  const double periods =
      std::isfinite(duration) && duration >= 0.0 ? std::round(duration / period_) : -1.0;
  if (periods < 0.0 || periods > static_cast<double>(kMaxPeriods)) {
    std::ostringstream msg;
    msg << "a duration of " << duration << " s is not finite and >= 0, or holds more than "
        << kMaxPeriods << " control periods of " << period_ << " s";
    throw InputError(msg.str());
  }
  return static_cast<std::int64_t>(periods);
}

}  // namespace flapsim
