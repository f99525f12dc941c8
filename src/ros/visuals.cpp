#include "flapsim_ros/visuals.h"

#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdio>

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {

namespace {

void setColour(visualization_msgs::Marker* m, const urdf::VisualSharedPtr& visual) {
  if (visual && visual->material) {
    const urdf::Color& c = visual->material->color;
    m->color.r = c.r;
    m->color.g = c.g;
    m->color.b = c.b;
    m->color.a = c.a > 0.0f ? c.a : 1.0f;
  } else {
    m->color.r = m->color.g = m->color.b = 0.7f;
    m->color.a = 1.0f;
  }
}

/// A marker of one URDF geometry at `origin` in the link frame; false for unknown shapes and
/// for a mesh by a relative path, which rviz cannot resolve (not drawn). A mesh is drawn from
/// its URI (package:// or file://, an absolute path made a file:// one), scaled as the URDF says.
bool shapeMarker(const urdf::Geometry& g, const urdf::Pose& origin, visualization_msgs::Marker* m) {
  switch (g.type) {
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(g);
      if (!mesh.filename.empty() && mesh.filename[0] == '/') {
        m->mesh_resource = "file://" + mesh.filename;
      } else if (mesh.filename.find("://") != std::string::npos) {
        m->mesh_resource = mesh.filename;
      } else {
        return false;
      }
      m->type = visualization_msgs::Marker::MESH_RESOURCE;
      m->scale.x = mesh.scale.x;
      m->scale.y = mesh.scale.y;
      m->scale.z = mesh.scale.z;
      break;
    }
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(g);
      m->type = visualization_msgs::Marker::CUBE;
      m->scale.x = box.dim.x;
      m->scale.y = box.dim.y;
      m->scale.z = box.dim.z;
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cyl = static_cast<const urdf::Cylinder&>(g);
      m->type = visualization_msgs::Marker::CYLINDER;
      m->scale.x = m->scale.y = 2.0 * cyl.radius;
      m->scale.z = cyl.length;
      break;
    }
    case urdf::Geometry::SPHERE: {
      const auto& sphere = static_cast<const urdf::Sphere&>(g);
      m->type = visualization_msgs::Marker::SPHERE;
      m->scale.x = m->scale.y = m->scale.z = 2.0 * sphere.radius;
      break;
    }
    default:
      return false;
  }
  m->pose.position.x = origin.position.x;
  m->pose.position.y = origin.position.y;
  m->pose.position.z = origin.position.z;
  m->pose.orientation.x = origin.rotation.x;
  m->pose.orientation.y = origin.rotation.y;
  m->pose.orientation.z = origin.rotation.z;
  m->pose.orientation.w = origin.rotation.w;
  return true;
}

}  // namespace

std::vector<visualization_msgs::Marker> creatureMarkers(const std::string& creature,
                                                        const std::string& urdf_xml,
                                                        const std::string& source) {
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(urdf_xml);
  if (!urdf) throw flapsim::InputError(source + ": URDF does not parse");
  std::vector<visualization_msgs::Marker> out;
  for (const auto& [name, link] : urdf->links_) {
    visualization_msgs::Marker m;
    m.header.frame_id = linkFrame(creature, name);
    m.ns = creature;
    m.action = visualization_msgs::Marker::ADD;
    m.frame_locked = true;
    if (!link->visual_array.empty()) {
      for (const urdf::VisualSharedPtr& v : link->visual_array) {
        if (!v->geometry || !shapeMarker(*v->geometry, v->origin, &m)) continue;
        setColour(&m, v);
        m.id = static_cast<int>(out.size());
        out.push_back(m);
      }
    } else {
      for (const urdf::CollisionSharedPtr& c : link->collision_array) {
        if (!c->geometry || !shapeMarker(*c->geometry, c->origin, &m)) continue;
        setColour(&m, nullptr);
        m.id = static_cast<int>(out.size());
        out.push_back(m);
      }
    }
  }
  return out;
}

flapsim::Vec3 centreOfMass(const flapsim::CreatureModel& model, const flapsim::CreatureState& s) {
  flapsim::Vec3 sum = flapsim::Vec3::Zero();
  flapsim::Vec3 origins = flapsim::Vec3::Zero();
  double mass = 0.0;
  for (size_t k = 0; k < model.links.size() && k < s.link_poses.size(); ++k) {
    const flapsim::Pose& p = s.link_poses[k];
    const flapsim::Vec3 com = p.position + p.orientation * model.links[k].urdfCom();
    sum += model.links[k].mass * com;
    mass += model.links[k].mass;
    origins += p.position;
  }
  if (mass > 0.0) return sum / mass;
  return s.link_poses.empty() ? origins : origins / static_cast<double>(s.link_poses.size());
}

geometry_msgs::TransformStamped viewTransform(const flapsim::Vec3& position, const ros::Time& stamp,
                                              const std::string& world_frame) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = world_frame;
  t.child_frame_id = kViewFrame;
  t.transform = toTransformMsg(flapsim::Pose{position, flapsim::Quat::Identity()});
  return t;
}

double cameraDistance(const std::vector<flapsim::Vec3>& points, const flapsim::Vec3& target,
                      const ViewParams& view, double least) {
  const Eigen::Matrix3d axes = cameraPose(target, 1.0, view).orientation.toRotationMatrix();
  const double up = std::tan(0.5 * kCameraFieldOfView), across = kCameraAspect * up;
  double distance = least;
  for (const flapsim::Vec3& p : points) {
    // in the camera's axes: x ahead (towards the target), y left, z up
    const flapsim::Vec3 r = axes.transpose() * (p - target);
    distance = std::max({distance, (std::abs(r.z()) + kCameraMargin) / up - r.x(),
                         (std::abs(r.y()) + kCameraMargin) / across - r.x()});
  }
  return distance;
}

flapsim::Pose cameraPose(const flapsim::Vec3& target, double distance, const ViewParams& view) {
  const flapsim::Vec3 from(std::cos(view.pitch) * std::cos(view.yaw),
                           std::cos(view.pitch) * std::sin(view.yaw), std::sin(view.pitch));
  const flapsim::Vec3 x = -from;
  const flapsim::Vec3 z = (flapsim::Vec3::UnitZ() - x.z() * x).normalized();
  Eigen::Matrix3d axes;
  axes.col(0) = x;
  axes.col(1) = z.cross(x);
  axes.col(2) = z;
  return flapsim::Pose{target + distance * from, flapsim::Quat(axes).normalized()};
}

visualization_msgs::Marker viewReadout(const ros::Time& stamp, const flapsim::Vec3& target) {
  visualization_msgs::Marker m;
  m.header.frame_id = kCameraFrame;
  m.ns = "readout";
  m.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  m.action = visualization_msgs::Marker::ADD;
  m.frame_locked = true;
  // 1 m ahead, near the top of a 45 degree view (its half height there is 0.41 m)
  m.pose.position.x = 1.0;
  m.pose.position.z = 0.34;
  m.pose.orientation.w = 1.0;
  m.scale.z = 0.035;  // m: the height of a capital letter, about 1/23 of the view
  m.color.r = m.color.g = m.color.b = 0.9f;
  m.color.a = 1.0f;
  char text[64];
  std::snprintf(text, sizeof text, "t = %.2f s   z = %.1f m", stamp.toSec(), target.z());
  m.text = text;
  return m;
}

const flapsim::Vec3& ViewFollower::update(const flapsim::Vec3& centroid, double t) {
  if (!started_ || t < t_ || time_constant_ <= 0.0) {
    s1_ = s2_ = centroid;
  } else {
    const double a = 1.0 - std::exp(-(t - t_) / time_constant_);
    s1_ += a * (centroid - s1_);
    s2_ += a * (s1_ - s2_);
  }
  started_ = true;
  t_ = t;
  position_ = 2.0 * s1_ - s2_;
  return position_;
}

}  // namespace flapsim_ros
