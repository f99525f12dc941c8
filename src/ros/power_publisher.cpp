#include "flapsim_ros/power_publisher.h"

namespace flapsim_ros {

flapsim::MotorPower powerMsg(const flapsim::CreatureModel& model,
                             const flapsim::CreaturePower& before,
                             const flapsim::CreaturePower& now, const ros::Time& stamp,
                             const flapsim::CreaturePower& average_from) {
  // A window that would start after `now` started at the counters' zero.
  const bool restarted = before.time > now.time || before.work.size() != now.work.size();
  const double window = restarted ? now.time : now.time - before.time;
  auto since = [&](const std::vector<double>& a, const std::vector<double>& b, size_t j) {
    return restarted ? a[j] : a[j] - b[j];
  };
  flapsim::MotorPower m;
  m.header.stamp = stamp;
  m.window = window;
  for (size_t j = 0; j < model.joints.size() && j < now.work.size(); ++j) {
    if (!model.joints[j].movable()) continue;
    m.joint_names.push_back(model.joints[j].name);
    const double work = since(now.work, before.work, j);
    const double positive = since(now.positive_work, before.positive_work, j);
    m.power.push_back(window > 0.0 ? work / window : 0.0);
    m.positive_power.push_back(window > 0.0 ? positive / window : 0.0);
    m.positive_work.push_back(now.positive_work[j]);
    m.total_power += m.power.back();
    m.total_positive_power += m.positive_power.back();
  }
  m.work = now.totalWork();
  m.total_positive_work = now.totalPositiveWork();
  m.time = now.time;
  m.mass = now.mass;
  m.specific_positive_power = now.mass > 0.0 ? m.total_positive_power / now.mass : 0.0;
  const bool whole = average_from.time > now.time || average_from.work.size() != now.work.size();
  m.average_window = whole ? now.time : now.time - average_from.time;
  const double positive =
      now.totalPositiveWork() - (whole ? 0.0 : average_from.totalPositiveWork());
  m.average_positive_power = m.average_window > 0.0 ? positive / m.average_window : 0.0;
  m.average_specific_positive_power = now.mass > 0.0 ? m.average_positive_power / now.mass : 0.0;
  return m;
}

PowerPublisher::PowerPublisher(ros::NodeHandle& nh, const std::string& creature,
                               flapsim::CreatureModelPtr model, int queue, Current current)
    : model_(std::move(model)), current_(std::move(current)) {
  pub_ = nh.advertise<flapsim::MotorPower>(
      creature + "/power", queue, [this](const ros::SingleSubscriberPublisher& p) {
        const auto [now, stamp] = current_();
        p.publish(powerMsg(*model_, last_, now, stamp, averageFrom(now)));
      });
}

const flapsim::CreaturePower& PowerPublisher::averageFrom(const flapsim::CreaturePower& now) const {
  static const flapsim::CreaturePower kNone;
  // The latest reading at least kPowerAverageWindow before `now` (within 1 ns: sim times are
  // sums of steps), else the earliest kept.
  for (auto it = history_.rbegin(); it != history_.rend(); ++it) {
    if (it->time <= now.time - kPowerAverageWindow + 1e-9) return *it;
  }
  return history_.empty() ? kNone : history_.front();
}

void PowerPublisher::publish(const flapsim::CreaturePower& power, const ros::Time& stamp) {
  if (!history_.empty() && history_.back().time > power.time) history_.clear();  // a reset
  if (pub_.getNumSubscribers() > 0) {
    pub_.publish(powerMsg(*model_, last_, power, stamp, averageFrom(power)));
  }
  last_ = power;
  history_.push_back(power);
  // Keep one reading at or before the window's start, none older.
  while (history_.size() > 1 && history_[1].time <= power.time - kPowerAverageWindow + 1e-9) {
    history_.pop_front();
  }
}

}  // namespace flapsim_ros
