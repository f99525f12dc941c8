#include "flapsim_ros/conversions.h"

#include <cmath>
#include <sstream>

namespace flapsim_ros {

namespace {

// Any message with x, y, z fields (Point, Vector3).
template <typename Msg>
Msg toXyz(const flapsim::Vec3& v) {
  Msg m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}
geometry_msgs::Point toPoint(const flapsim::Vec3& v) { return toXyz<geometry_msgs::Point>(v); }
geometry_msgs::Vector3 toVector(const flapsim::Vec3& v) { return toXyz<geometry_msgs::Vector3>(v); }

geometry_msgs::Quaternion toQuaternion(const flapsim::Quat& q) {
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

flapsim::Vec3 fromVector(const geometry_msgs::Vector3& v) { return flapsim::Vec3(v.x, v.y, v.z); }

visualization_msgs::Marker arrow(const std::string& ns, int id, const flapsim::Vec3& from,
                                 const flapsim::Vec3& to, double width, float r, float g, float b,
                                 const ros::Time& stamp, const std::string& frame) {
  visualization_msgs::Marker m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.ns = ns;
  m.id = id;
  m.type = visualization_msgs::Marker::ARROW;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.points = {toPoint(from), toPoint(to)};
  m.scale.x = width;
  m.scale.y = 2.0 * width;
  m.scale.z = 3.0 * width;
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = 1.0f;
  return m;
}

constexpr double kMinArrow = 1e-6;  // m: no zero-length arrows

}  // namespace

geometry_msgs::Pose toMsg(const flapsim::Pose& pose) {
  geometry_msgs::Pose m;
  m.position = toPoint(pose.position);
  m.orientation = toQuaternion(pose.orientation);
  return m;
}

geometry_msgs::Transform toTransformMsg(const flapsim::Pose& pose) {
  geometry_msgs::Transform m;
  m.translation = toVector(pose.position);
  m.rotation = toQuaternion(pose.orientation);
  return m;
}

geometry_msgs::Twist toMsg(const flapsim::Twist& twist) {
  geometry_msgs::Twist m;
  m.linear = toVector(twist.linear);
  m.angular = toVector(twist.angular);
  return m;
}

flapsim::Pose fromMsg(const geometry_msgs::Pose& pose) {
  flapsim::Pose p;
  p.position = flapsim::Vec3(pose.position.x, pose.position.y, pose.position.z);
  const auto& q = pose.orientation;
  if (q.x == 0.0 && q.y == 0.0 && q.z == 0.0 && q.w == 0.0) {
    p.orientation = flapsim::Quat::Identity();
  } else {
    p.orientation = flapsim::Quat(q.w, q.x, q.y, q.z);
  }
  return p;
}

flapsim::Twist fromMsg(const geometry_msgs::Twist& twist) {
  return flapsim::Twist{fromVector(twist.linear), fromVector(twist.angular)};
}

std::string formatTime(const ros::Time& t) {
  std::ostringstream os;
  os.precision(9);
  os << std::fixed << t.toSec();
  return os.str();
}

std::uint64_t stepNanoseconds(double step_size) {
  const double ns = std::round(step_size * 1e9);
  return ns < 1.0 ? 1 : static_cast<std::uint64_t>(ns);
}

ros::Time simTime(std::uint64_t steps, std::uint64_t step_ns) {
  ros::Time t;
  t.fromNSec(steps * step_ns);
  return t;
}

std::string linkFrame(const std::string& creature, const std::string& link) {
  return creature + "/" + link;
}

WingCommandRequest fromMsg(const flapsim::WingCommand& msg) {
  const size_t n = msg.downstroke_rate.size();
  if (msg.upstroke_rate.size() != n || msg.amplitude.size() != n) {
    throw flapsim::InputError("wing command arrays differ in length: downstroke_rate has " +
                              std::to_string(n) + " entries, upstroke_rate " +
                              std::to_string(msg.upstroke_rate.size()) + ", amplitude " +
                              std::to_string(msg.amplitude.size()));
  }
  // An optional array: empty, or one entry per stroke.
  auto optional = [n](size_t size, const char* name) {
    if (size != 0 && size != n) {
      throw flapsim::InputError("wing command has " + std::to_string(size) + " " + name +
                                " entries for " + std::to_string(n) + " strokes");
    }
  };
  optional(msg.feather_angle.size(), "feather_angle");
  optional(msg.downstroke_feather_angle.size(), "downstroke_feather_angle");
  optional(msg.offset.size(), "offset");
  optional(msg.shape.size(), "shape");
  if (!msg.joint_names.empty() && msg.joint_names.size() != n) {
    throw flapsim::InputError("wing command has " + std::to_string(msg.joint_names.size()) +
                              " joint_names but " + std::to_string(n) + " strokes");
  }
  WingCommandRequest r;
  r.joints = msg.joint_names;
  for (size_t i = 0; i < n; ++i) {
    flapsim::StrokeCommand c{msg.downstroke_rate[i], msg.upstroke_rate[i], msg.amplitude[i],
                             msg.feather_angle.empty() ? 0.0 : msg.feather_angle[i]};
    if (!msg.downstroke_feather_angle.empty())
      c.downstroke_feather = msg.downstroke_feather_angle[i];
    if (!msg.offset.empty()) c.offset = msg.offset[i];
    if (!msg.shape.empty()) {
      try {
        c.shape = flapsim::strokeShapeFromString(msg.shape[i]);
      } catch (const std::invalid_argument& e) {
        throw flapsim::InputError("wing command shape[" + std::to_string(i) + "]: " + e.what());
      }
    }
    r.strokes.push_back(c);
  }
  return r;
}

flapsim::WingCommand toMsg(const WingCommandRequest& request) {
  flapsim::WingCommand m;
  m.joint_names = request.joints;
  bool feather = false, downstroke_feather = false, offset = false, shape = false;
  for (const auto& s : request.strokes) {
    m.downstroke_rate.push_back(s.downstroke_rate);
    m.upstroke_rate.push_back(s.upstroke_rate);
    m.amplitude.push_back(s.amplitude);
    feather = feather || s.feather != 0.0;
    downstroke_feather = downstroke_feather || s.downstroke_feather != 0.0;
    offset = offset || s.offset != 0.0;
    shape = shape || s.shape != flapsim::StrokeShape::kTriangle;
  }
  // The optional arrays only where a stroke differs from their default.
  for (const auto& s : request.strokes) {
    if (feather) m.feather_angle.push_back(s.feather);
    if (downstroke_feather) m.downstroke_feather_angle.push_back(s.downstroke_feather);
    if (offset) m.offset.push_back(s.offset);
    if (shape) m.shape.push_back(flapsim::toString(s.shape));
  }
  return m;
}

std::vector<flapsim::CreatureWingCommand> stepCommands(
    const std::vector<std::string>& creatures, const std::vector<flapsim::WingCommand>& commands) {
  if (creatures.size() != commands.size()) {
    throw flapsim::InputError("step request has " + std::to_string(creatures.size()) +
                              " creatures but " + std::to_string(commands.size()) +
                              " wing_commands");
  }
  std::vector<flapsim::CreatureWingCommand> out;
  for (size_t i = 0; i < creatures.size(); ++i) {
    try {
      WingCommandRequest r = fromMsg(commands[i]);
      out.push_back(flapsim::CreatureWingCommand{creatures[i], r.joints, r.strokes});
    } catch (const flapsim::InputError& e) {
      throw flapsim::InputError("creature '" + creatures[i] + "': " + e.what());
    }
  }
  return out;
}

sensor_msgs::JointState jointStateMsg(const flapsim::CreatureModel& model,
                                      const flapsim::CreatureState& state, const ros::Time& stamp) {
  sensor_msgs::JointState m;
  m.header.stamp = stamp;
  for (size_t j = 0; j < model.joints.size(); ++j) {
    if (!model.joints[j].movable()) continue;
    m.name.push_back(model.joints[j].name);
    m.position.push_back(state.joint_positions.at(j));
    m.velocity.push_back(state.joint_velocities.at(j));
    m.effort.push_back(state.joint_efforts.at(j));
  }
  return m;
}

nav_msgs::Odometry odometryMsg(const std::string& creature, const flapsim::CreatureModel& model,
                               const flapsim::CreatureState& state, const ros::Time& stamp,
                               const std::string& world_frame) {
  nav_msgs::Odometry m;
  m.header.stamp = stamp;
  m.header.frame_id = world_frame;
  m.child_frame_id = linkFrame(creature, model.links.at(0).name);
  const flapsim::Pose& pose = state.link_poses.at(0);
  const flapsim::Twist& twist = state.link_twists.at(0);
  m.pose.pose = toMsg(pose);
  const flapsim::Quat to_body = pose.orientation.conjugate();
  m.twist.twist = toMsg(flapsim::Twist{to_body * twist.linear, to_body * twist.angular});
  return m;  // covariances: zero (exact simulation state)
}

flapsim::StateRequest stateRequest(const flapsim::CreatureModel& model,
                                   const flapsim::CreatureState& current,
                                   const flapsim::SetState::Request& req) {
  flapsim::StateRequest r;
  r.link = req.link;
  r.pose = fromMsg(req.pose);
  r.twist = fromMsg(req.twist);
  const size_t n = req.joint_names.size();
  for (const auto* list : {&req.joint_positions, &req.joint_velocities}) {
    if (!list->empty() && list->size() != n) {
      throw flapsim::InputError(
          std::to_string(list->size()) +
          (list == &req.joint_positions ? " joint_positions" : " joint_velocities") + " for " +
          std::to_string(n) + " joint_names (give one per name, or none)");
    }
  }
  if (n == 0) return r;
  r.joint_positions = current.joint_positions;
  r.joint_velocities = current.joint_velocities;
  std::vector<bool> named(model.joints.size(), false);
  for (size_t i = 0; i < n; ++i) {
    const int j = model.findJoint(req.joint_names[i]);
    if (j < 0) throw flapsim::InputError("no joint '" + req.joint_names[i] + "'");
    if (!model.joints[j].movable()) {
      throw flapsim::InputError("joint '" + req.joint_names[i] + "' is fixed");
    }
    if (named[j]) throw flapsim::InputError("joint '" + req.joint_names[i] + "' is named twice");
    named[j] = true;
    if (!req.joint_positions.empty()) r.joint_positions[j] = req.joint_positions[i];
    if (!req.joint_velocities.empty()) r.joint_velocities[j] = req.joint_velocities[i];
  }
  return r;
}

flapsim::ExternalWrench fromMsg(const flapsim::ApplyWrench::Request& req) {
  flapsim::ExternalWrench w;
  w.link = req.link;
  w.point = flapsim::Vec3(req.reference_point.x, req.reference_point.y, req.reference_point.z);
  w.force = flapsim::Vec3(req.wrench.force.x, req.wrench.force.y, req.wrench.force.z);
  w.torque = flapsim::Vec3(req.wrench.torque.x, req.wrench.torque.y, req.wrench.torque.z);
  w.duration = req.duration.toSec();
  w.start_time = req.start_time.toSec();
  return w;
}

FrameMotion toFrame(const FrameMotion& frame, const FrameMotion& body) {
  const flapsim::Quat to_frame = frame.pose.orientation.conjugate();
  return FrameMotion{frame.pose.inverse() * body.pose,
                     flapsim::Twist{to_frame * (body.twist.linear - frame.twist.linear),
                                    to_frame * (body.twist.angular - frame.twist.angular)}};
}

FrameMotion fromFrame(const FrameMotion& frame, const FrameMotion& relative) {
  const flapsim::Quat& to_world = frame.pose.orientation;
  // Not normalised: a bad quaternion stays bad for the world's check.
  const flapsim::Pose pose{frame.pose.apply(relative.pose.position),
                           to_world * relative.pose.orientation};
  return FrameMotion{pose, flapsim::Twist{to_world * relative.twist.linear + frame.twist.linear,
                                          to_world * relative.twist.angular + frame.twist.angular}};
}

flapsim::ExternalWrench toWorld(const flapsim::ExternalWrench& wrench, const flapsim::Pose& frame) {
  flapsim::ExternalWrench w = wrench;
  w.force = frame.orientation * wrench.force;
  w.torque = frame.orientation * wrench.torque;
  w.point = frame.apply(wrench.point);
  return w;
}

sensor_msgs::Imu imuMsg(const std::string& creature, const flapsim::CreatureModel& model,
                        const flapsim::CreatureState& state, const flapsim::Vec3& acceleration,
                        const flapsim::Vec3& gravity, const ros::Time& stamp,
                        const flapsim::ImuNoise& noise, const std::function<double()>& draw) {
  const flapsim::ImuReading r = flapsim::imuReading(state, acceleration, gravity, noise, draw);
  sensor_msgs::Imu m;
  m.header.stamp = stamp;
  m.header.frame_id = linkFrame(creature, model.links.at(0).name);
  m.orientation = toQuaternion(r.orientation);
  m.angular_velocity = toVector(r.angular_velocity);
  m.linear_acceleration = toVector(r.linear_acceleration);
  for (int i = 0; i < 3; ++i) {
    m.orientation_covariance[4 * i] = noise.orientation * noise.orientation;
    m.angular_velocity_covariance[4 * i] = noise.angular_velocity * noise.angular_velocity;
    m.linear_acceleration_covariance[4 * i] = noise.linear_acceleration * noise.linear_acceleration;
  }
  return m;
}

flapsim::ImuReading fromMsg(const sensor_msgs::Imu& msg) {
  flapsim::ImuReading r;
  const auto& q = msg.orientation;
  r.orientation = flapsim::Quat(q.w, q.x, q.y, q.z);
  r.angular_velocity = fromVector(msg.angular_velocity);
  r.linear_acceleration = fromVector(msg.linear_acceleration);
  const double n = r.orientation.norm();
  if (!std::isfinite(n) || n == 0.0 || !r.angular_velocity.allFinite() ||
      !r.linear_acceleration.allFinite()) {
    throw flapsim::InputError("imu: a non-finite value or a zero quaternion");
  }
  r.orientation.normalize();
  return r;
}

void jointVectors(const sensor_msgs::JointState& msg, const flapsim::CreatureModel& model,
                  std::vector<double>& positions, std::vector<double>& velocities) {
  const size_t n = msg.name.size();
  if (msg.position.size() != n || msg.velocity.size() != n) {
    throw flapsim::InputError("joint_states: " + std::to_string(msg.position.size()) +
                              " positions and " + std::to_string(msg.velocity.size()) +
                              " velocities for " + std::to_string(n) + " names");
  }
  positions.assign(model.joints.size(), 0.0);
  velocities.assign(model.joints.size(), 0.0);
  std::vector<bool> named(model.joints.size(), false);
  for (size_t i = 0; i < n; ++i) {
    const int j = model.findJoint(msg.name[i]);
    if (j < 0) {
      throw flapsim::InputError("joint_states: '" + model.name + "' has no joint '" + msg.name[i] +
                                "'");
    }
    if (!std::isfinite(msg.position[i]) || !std::isfinite(msg.velocity[i])) {
      throw flapsim::InputError("joint_states: joint '" + msg.name[i] + "' is not finite");
    }
    positions[j] = msg.position[i];
    velocities[j] = msg.velocity[i];
    named[j] = true;
  }
  for (size_t j = 0; j < model.joints.size(); ++j) {
    if (model.joints[j].movable() && !named[j]) {
      throw flapsim::InputError("joint_states: joint '" + model.joints[j].name + "' is missing");
    }
  }
}

std::vector<visualization_msgs::Marker> aeroMarkers(const std::string& creature,
                                                    const std::vector<flapsim::LinkAero>& aero,
                                                    const MarkerParams& params,
                                                    const ros::Time& stamp,
                                                    const std::string& world_frame) {
  std::vector<visualization_msgs::Marker> out;
  int cell_id = 0;
  for (const flapsim::LinkAero& a : aero) {
    const flapsim::Vec3 tip = a.com + params.scale * a.wrench.force;
    if ((tip - a.com).norm() >= kMinArrow) {
      out.push_back(
          arrow(creature, a.link, a.com, tip, params.width, 1.0f, 0.5f, 0.0f, stamp, world_frame));
    }
    if (!params.per_cell) continue;
    const size_t n = std::min(a.cell_centres.size(), a.cell_forces.size());
    for (size_t i = 0; i < n; ++i, ++cell_id) {
      const flapsim::Vec3 cell_tip = a.cell_centres[i] + params.scale * a.cell_forces[i];
      if ((cell_tip - a.cell_centres[i]).norm() < kMinArrow) continue;
      out.push_back(arrow(creature + "/cells", cell_id, a.cell_centres[i], cell_tip,
                          0.5 * params.width, 0.0f, 0.7f, 1.0f, stamp, world_frame));
    }
  }
  return out;
}

}  // namespace flapsim_ros
