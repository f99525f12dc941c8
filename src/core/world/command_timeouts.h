// The wing-command timeout (World::setCommandTimeout): when each creature's wings were last
// commanded, whose command timed out, and the drives a lapse replaced, which a reset gives
// back (World::reset keeps the commands). The world asks it how far it may step before the
// next lapse falls due, so a lapse lands on its step whatever the steps asked at a time.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "flapsim/world.h"
#include "world/joint_drives.h"

namespace flapsim {

class CommandTimeouts {
 public:
  /// From now on (InputError unless 0 <= seconds <= kMaxCommandTimeout).
  void set(const CommandTimeout& timeout, double step_size);
  /// Whether any creature's timeout may fall due (else the world need not ask).
  bool active() const { return steps_ > 0 && !entries_.empty(); }
  /// A wing command for `creature` at step `now`: its timeout starts again, a lapse ends.
  void commanded(const std::string& creature, std::uint64_t now);
  void forget(const std::string& creature) { entries_.erase(creature); }
  /// Steps from `now` until the first timeout falls due, at most `limit` (at least 1).
  std::uint64_t stepsToNext(std::uint64_t now, std::uint64_t limit) const;
  /// Whether `creature`'s timeout fell due at or before `now` and has not lapsed yet.
  bool due(const std::string& creature, std::uint64_t now) const;
  /// Lapses `creature`'s command at `now`: its wing joints (of `model`) held at `positions`
  /// (its joint positions now) or released, the drives they had kept for restore().
  void lapse(const std::string& creature, const CreatureModel& model,
             std::vector<JointDrive>& drives, const std::vector<double>& positions,
             std::uint64_t now);
  /// At a reset: gives a lapsed creature's wing joints the drives its lapse replaced.
  void restore(const std::string& creature, std::vector<JointDrive>& drives);
  /// After a reset: every timeout starts again at step 0, none lapsed.
  void restart();
  std::optional<CommandLapse> lapseOf(const std::string& creature) const;
  std::vector<CommandLapse> take() { return std::exchange(reports_, {}); }

 private:
  struct Entry {
    std::uint64_t commanded = 0;  // step count of the last wing command
    bool lapsed = false;
    std::uint64_t lapsed_at = 0;                       // step count of the lapse
    std::vector<std::pair<int, JointDrive>> replaced;  // by the lapse: (joint, its drive)
  };
  CommandTimeout timeout_;
  std::uint64_t steps_ = 0;                         // the timeout in steps (0: none)
  std::unordered_map<std::string, Entry> entries_;  // the creatures ever commanded
  std::vector<CommandLapse> reports_;               // lapses not taken yet
};

}  // namespace flapsim
