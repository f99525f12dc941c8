#include "flapsim/sensors.h"

#include <cmath>
#include <sstream>

namespace flapsim {

std::string validateImuNoise(const ImuNoise& n) {
  const std::pair<const char*, double> values[] = {{"orientation", n.orientation},
                                                   {"angular_velocity", n.angular_velocity},
                                                   {"linear_acceleration", n.linear_acceleration}};
  for (const auto& [name, v] : values) {
    if (!(v >= 0.0 && v <= 1e3)) {
      std::ostringstream msg;
      msg << name << " noise " << v << " is not in [0, 1000]";
      return msg.str();
    }
  }
  return "";
}

Vec3 groundSpeedReading(const Vec3& velocity, double noise, const std::function<double()>& normal) {
  Vec3 v = velocity;
  if (noise > 0.0) {
    for (int a = 0; a < 3; ++a) v[a] += noise * normal();
  }
  return v;
}

ImuReading imuReading(const CreatureState& state, const Vec3& acceleration, const Vec3& gravity,
                      const ImuNoise& noise, const std::function<double()>& normal) {
  ImuReading r;
  const Pose& pose = state.link_poses.at(0);
  const Quat to_body = pose.orientation.conjugate();
  r.orientation = pose.orientation;
  r.angular_velocity = to_body * state.link_twists.at(0).angular;
  r.linear_acceleration = to_body * (acceleration - gravity);
  if (!normal) return r;
  for (int i = 0; i < 3; ++i) {
    if (noise.angular_velocity > 0.0) r.angular_velocity[i] += noise.angular_velocity * normal();
    if (noise.linear_acceleration > 0.0) {
      r.linear_acceleration[i] += noise.linear_acceleration * normal();
    }
  }
  if (noise.orientation > 0.0) {
    Vec3 n;
    for (int i = 0; i < 3; ++i) n[i] = noise.orientation * normal();
    const double angle = n.norm();
    if (angle > 0.0) {
      r.orientation = (r.orientation * Quat(Eigen::AngleAxisd(angle, n / angle))).normalized();
    }
  }
  return r;
}

AttitudeFilter::AttitudeFilter(double time_constant) : time_constant_(time_constant) {
  if (!(time_constant >= 0.0 && time_constant <= 1e3)) {
    std::ostringstream msg;
    msg << "attitude filter: time constant " << time_constant << " s is not in [0, 1000]";
    throw InputError(msg.str());
  }
}

ImuReading AttitudeFilter::update(const ImuReading& reading, double dt) {
  ImuReading out = reading;
  if (time_constant_ <= 0.0) return out;
  if (!estimate_) {
    estimate_ = reading.orientation.normalized();
  } else {
    const Vec3 turn = 0.5 * (rate_ + reading.angular_velocity) * dt;  // body axes
    const double angle = turn.norm();
    Quat predicted = *estimate_;
    if (angle > 0.0) predicted = predicted * Quat(Eigen::AngleAxisd(angle, turn / angle));
    const double a = dt / (time_constant_ + dt);
    estimate_ = predicted.normalized().slerp(a, reading.orientation.normalized()).normalized();
  }
  rate_ = reading.angular_velocity;
  out.orientation = *estimate_;
  return out;
}

ImuReading AttitudeFilter::updateAt(const ImuReading& reading, std::int64_t t_ns) {
  if (time_ && t_ns == *time_) return last_;
  if (time_ && t_ns < *time_) reset();
  // The first update does not step: it takes the reading as it is.
  const double dt = time_ ? static_cast<double>(t_ns - *time_) * 1e-9 : 0.0;
  time_ = t_ns;
  last_ = update(reading, dt);
  return last_;
}

FlapSensing unitSensing(const CreatureModel& model, const std::vector<int>& body_links,
                        const ImuReading& imu, const std::vector<double>& q,
                        const std::vector<double>& qd, double altitude) {
  const size_t joints = model.joints.size();
  if (q.size() != joints || qd.size() != joints) {
    throw InputError("unit sensing: " + std::to_string(q.size()) + " joint positions and " +
                     std::to_string(qd.size()) + " velocities for the " + std::to_string(joints) +
                     " joints of '" + model.name + "'");
  }
  // Links are stored parent before child: one pass from the root.
  std::vector<Quat> orientation(model.links.size());
  std::vector<Vec3> omega(model.links.size());  // world frame
  orientation[0] = imu.orientation;
  omega[0] = imu.orientation * imu.angular_velocity;
  for (size_t l = 1; l < model.links.size(); ++l) {
    const JointModel& j = model.joints.at(model.links[l].parent_joint);
    const size_t ji = static_cast<size_t>(model.links[l].parent_joint);
    const Quat r = j.childPose(q[ji], Pose{Vec3::Zero(), orientation[j.parent_link]}).orientation;
    Vec3 w = omega[j.parent_link];
    if (j.type == JointType::kRevolute || j.type == JointType::kContinuous) {
      w += r * (j.axis * qd[ji]);
    }
    orientation[l] = r.normalized();
    omega[l] = w;
  }
  FlapSensing s;
  s.altitude = altitude;
  for (int b : body_links) {
    if (b < 0 || static_cast<size_t>(b) >= model.links.size()) {
      throw InputError("unit sensing: link " + std::to_string(b) + " is not a link of '" +
                       model.name + "'");
    }
    s.orientations.push_back(orientation[b]);
    s.rates.push_back(orientation[b].conjugate() * omega[b]);
  }
  return s;
}

}  // namespace flapsim
