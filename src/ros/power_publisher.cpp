#include "flapsim_ros/power_publisher.h"

namespace flapsim_ros {

flapsim::MotorPower powerMsg(const flapsim::CreatureModel& model,
                             const flapsim::CreaturePower& before,
                             const flapsim::CreaturePower& now, const ros::Time& stamp) {
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
  return m;
}

PowerPublisher::PowerPublisher(ros::NodeHandle& nh, const std::string& creature,
                               flapsim::CreatureModelPtr model, int queue)
    : pub_(nh.advertise<flapsim::MotorPower>(creature + "/power", queue)),
      model_(std::move(model)) {}

void PowerPublisher::publish(const flapsim::CreaturePower& power, const ros::Time& stamp) {
  if (pub_.getNumSubscribers() > 0) pub_.publish(powerMsg(*model_, last_, power, stamp));
  last_ = power;
}

}  // namespace flapsim_ros
