#include "flapsim_ros/warning_limiter.h"

#include <iterator>

namespace flapsim_ros {

bool WarningLimiter::allow(const std::string& kind, const std::string& creature, double now) {
  // The creature name is cut short: a name is a cause, not a place to store text.
  const std::string key = kind + '\0' + creature.substr(0, 64);
  auto it = last_.find(key);
  if (it != last_.end()) {
    if (now - it->second < period_) return false;
    it->second = now;
    return true;
  }
  if (last_.size() >= max_causes_) {
    for (auto old = last_.begin(); old != last_.end();) {
      old = now - old->second >= period_ ? last_.erase(old) : std::next(old);
    }
    // Still full: a new cause waits until old ones age out (clearing the table would let a
    // stream of distinct causes through, one line each).
    if (last_.size() >= max_causes_) return false;
  }
  last_.emplace(key, now);
  return true;
}

std::string WarningLimiter::kindOf(const std::string& message) {
  constexpr std::size_t kMaxKind = 160;
  std::string kind;
  bool quoted = false;
  for (char c : message) {
    if (kind.size() >= kMaxKind) break;
    if (c == '\'') {
      quoted = !quoted;
      kind += c;
    } else if (!quoted && !(c >= '0' && c <= '9') && c != '.' && c != '-' && c != '+') {
      kind += c;
    }
  }
  return kind;
}

}  // namespace flapsim_ros
