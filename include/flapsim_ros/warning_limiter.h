// Throttled warnings keyed by cause: one message per (kind, creature) per period, in bounded
// memory whatever the stream of distinct bad inputs. No ROS, no clock: the caller passes the
// time, so it is tested without a master.
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace flapsim_ros {

class WarningLimiter {
 public:
  /// `period`: seconds between two messages of one cause; `max_causes`: causes remembered.
  explicit WarningLimiter(double period = 10.0, std::size_t max_causes = 256)
      : period_(period), max_causes_(max_causes) {}

  /// Whether a warning of cause `kind` about `creature` may be logged at time `now` (s); if
  /// so, the cause is remembered as warned at `now`. When the table is full, causes older
  /// than a period are forgotten; if it is still full, the new cause is not logged: at most
  /// `max_causes` warnings per period, whatever the stream of distinct causes.
  bool allow(const std::string& kind, const std::string& creature, double now);
  std::size_t causes() const { return last_.size(); }

  /// The kind of an error message: its text without what varies (quoted names, numbers),
  /// so that "no joint 'a'" and "no joint 'b'" are one cause and a different check another.
  static std::string kindOf(const std::string& message);

 private:
  double period_;
  std::size_t max_causes_;
  std::map<std::string, double> last_;
};

}  // namespace flapsim_ros
