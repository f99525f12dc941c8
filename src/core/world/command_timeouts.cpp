#include "world/command_timeouts.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flapsim {

void CommandTimeouts::set(const CommandTimeout& timeout, double step_size) {
  if (!(timeout.seconds >= 0.0 && timeout.seconds <= kMaxCommandTimeout)) {
    std::ostringstream what;
    what << "command timeout " << timeout.seconds << " s is not in [0, " << kMaxCommandTimeout
         << "]";
    throw InputError(what.str());
  }
  timeout_ = timeout;
  steps_ = timeout.seconds <= 0.0
               ? 0
               : std::max<std::uint64_t>(
                     1, static_cast<std::uint64_t>(std::llround(timeout.seconds / step_size)));
}

void CommandTimeouts::commanded(const std::string& creature, std::uint64_t now) {
  entries_[creature] = Entry{now, false, 0, {}};
}

std::uint64_t CommandTimeouts::stepsToNext(std::uint64_t now, std::uint64_t limit) const {
  if (steps_ == 0) return limit;
  std::uint64_t steps = limit;
  for (const auto& [name, e] : entries_) {
    if (e.lapsed) continue;
    const std::uint64_t at = e.commanded + steps_;
    steps = std::min(steps, at > now ? at - now : 1);
  }
  return steps;
}

bool CommandTimeouts::due(const std::string& creature, std::uint64_t now) const {
  const auto it = entries_.find(creature);
  return steps_ > 0 && it != entries_.end() && !it->second.lapsed &&
         now >= it->second.commanded + steps_;
}

void CommandTimeouts::lapse(const std::string& creature, const CreatureModel& model,
                            std::vector<JointDrive>& drives, const std::vector<double>& positions,
                            std::uint64_t now) {
  Entry& e = entries_.at(creature);
  e.lapsed = true;
  e.lapsed_at = now;
  e.replaced.clear();
  for (int j : model.wing_joints) {
    e.replaced.emplace_back(j, drives[j]);
    JointDrive& d = drives[j];
    if (timeout_.action == CommandTimeout::Action::kHold) {
      d.mode = JointDrive::Mode::kHold;
      d.position = positions[j];
    } else {
      d = JointDrive();
    }
  }
  reports_.push_back(CommandLapse{creature, e.commanded, now});
}

void CommandTimeouts::restore(const std::string& creature, std::vector<JointDrive>& drives) {
  const auto it = entries_.find(creature);
  if (it == entries_.end() || !it->second.lapsed) return;
  for (auto& [j, d] : it->second.replaced) drives[j] = d;
}

void CommandTimeouts::restart() {
  for (auto& [name, e] : entries_) e = Entry();
  reports_.clear();
}

std::optional<CommandLapse> CommandTimeouts::lapseOf(const std::string& creature) const {
  const auto it = entries_.find(creature);
  if (it == entries_.end() || !it->second.lapsed) return std::nullopt;
  return CommandLapse{creature, it->second.commanded, it->second.lapsed_at};
}

// ---- World's side of it ----------------------------------------------------------------

void World::setCommandTimeout(const CommandTimeout& timeout) {
  timeouts_->set(timeout, params().step_size);
}

std::optional<CommandLapse> World::commandLapse(const std::string& creature) const {
  model(creature);  // InputError if unknown
  return timeouts_->lapseOf(creature);
}

std::vector<CommandLapse> World::takeCommandLapses() { return timeouts_->take(); }

}  // namespace flapsim
