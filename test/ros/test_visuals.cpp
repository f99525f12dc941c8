// What rviz is given, without a master: creature geometry as markers, the view frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "flapsim/creature_model.h"
#include "flapsim_ros/visuals.h"

namespace {

using flapsim::Vec3;

std::string readSource(const std::string& relative) {
  std::ifstream in(std::string(FLAPSIM_SOURCE_DIR) + "/" + relative);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(CreatureMarkers, FlapUnitIsThreeColouredBoxesInItsLinkFrames) {
  const auto markers =
      flapsim_ros::creatureMarkers("fu", readSource("urdf/flap_unit.urdf"), "flap_unit.urdf");
  ASSERT_EQ(markers.size(), 3u);
  std::map<std::string, visualization_msgs::Marker> by_frame;
  for (const auto& m : markers) {
    EXPECT_EQ(m.ns, "fu");
    EXPECT_EQ(m.type, visualization_msgs::Marker::CUBE);
    EXPECT_TRUE(m.frame_locked);
    EXPECT_EQ(m.header.stamp.toNSec(), 0u);  // drawn at the latest transform
    by_frame[m.header.frame_id] = m;
  }
  ASSERT_EQ(by_frame.count("fu/unit0_body"), 1u);
  ASSERT_EQ(by_frame.count("fu/unit0_wing_left"), 1u);
  ASSERT_EQ(by_frame.count("fu/unit0_wing_right"), 1u);
  const auto& body = by_frame["fu/unit0_body"];
  EXPECT_DOUBLE_EQ(body.scale.x, 0.08);  // <box size="0.08 0.06 0.03"/>
  EXPECT_DOUBLE_EQ(body.scale.y, 0.06);
  EXPECT_DOUBLE_EQ(body.scale.z, 0.03);
  EXPECT_FLOAT_EQ(body.color.b, 0.45f);  // material "body": 0.25 0.3 0.45
  const auto& left = by_frame["fu/unit0_wing_left"];
  EXPECT_DOUBLE_EQ(left.pose.position.y, 0.175);  // the visual's origin in the link frame
  EXPECT_DOUBLE_EQ(left.scale.y, 0.35);
  EXPECT_FLOAT_EQ(left.color.r, 0.95f);  // material "wing": 0.95 0.8 0.3
  EXPECT_NE(markers[0].id, markers[1].id);
}

// A CAD-style robot drawn from its meshes: each mesh a MESH_RESOURCE marker of its URI, scaled
// as the URDF says; a mesh by a relative path is not drawn (rviz could not find it).
TEST(CreatureMarkers, MeshesAreDrawnFromTheirUris) {
  const auto markers = flapsim_ros::creatureMarkers(
      "cad", readSource("test/ros/cad_mesh_unit.urdf"), "cad_mesh_unit.urdf");
  std::map<std::string, visualization_msgs::Marker> by_frame;
  for (const auto& m : markers) by_frame[m.header.frame_id] = m;
  ASSERT_EQ(by_frame.count("cad/base_link"), 1u);
  const auto& body = by_frame["cad/base_link"];
  EXPECT_EQ(body.type, visualization_msgs::Marker::MESH_RESOURCE);
  EXPECT_EQ(body.mesh_resource, "package://flapsim/test/meshes/body_box.obj");
  EXPECT_DOUBLE_EQ(body.scale.x, 1.0);
  EXPECT_DOUBLE_EQ(body.pose.position.z, 0.02);  // the visual's origin in base_link
  ASSERT_EQ(by_frame.count("cad/wing_left"), 1u);
  EXPECT_EQ(by_frame["cad/wing_left"].mesh_resource, "package://flapsim/test/meshes/wing_box.stl");
  const std::string scaled = R"(<robot name="m"><link name="a"><visual><geometry>
      <mesh filename="/tmp/x.stl" scale="2 3 4"/></geometry></visual></link></robot>)";
  const auto absolute = flapsim_ros::creatureMarkers("m", scaled, "m.urdf");
  ASSERT_EQ(absolute.size(), 1u);
  EXPECT_EQ(absolute[0].mesh_resource, "file:///tmp/x.stl");
  EXPECT_DOUBLE_EQ(absolute[0].scale.z, 4.0);
  const std::string relative = R"(<robot name="m"><link name="a"><visual><geometry>
      <mesh filename="meshes/x.stl"/></geometry></visual></link></robot>)";
  EXPECT_TRUE(flapsim_ros::creatureMarkers("m", relative, "m.urdf").empty());
}

TEST(CreatureMarkers, UnparsableUrdfIsAnInputErrorNamingItsSource) {
  try {
    flapsim_ros::creatureMarkers("x", "<robot name='x'><link", "broken.urdf");
    FAIL() << "no exception";
  } catch (const flapsim::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.urdf"), std::string::npos) << e.what();
  }
}

TEST(CentreOfMass, IsTheMassWeightedLinkCentres) {
  const auto model = flapsim::parseCreatureModel(readSource("urdf/flap_unit.urdf"));
  flapsim::CreatureState s;
  s.link_poses.resize(model->links.size());
  for (auto& p : s.link_poses) p.position = Vec3(1, 2, 3);
  // all link frames at (1, 2, 3), unrotated: the body's COM is its origin, the wings' COMs
  // are 0.175 m out on either side, so their mass-weighted mean is the origin
  const Vec3 com = flapsim_ros::centreOfMass(*model, s);
  EXPECT_NEAR((com - Vec3(1, 2, 3)).norm(), 0.0, 1e-12);
  s.link_poses[0].position = Vec3(1, 2, 4.15);  // the body (0.015 of 0.023 kg) 1.15 m up
  EXPECT_NEAR(flapsim_ros::centreOfMass(*model, s).z(), 3.0 + 1.15 * 0.015 / 0.023, 1e-12);
}

TEST(ViewFollower, FirstSampleIsTakenAsItIs) {
  flapsim_ros::ViewFollower v(0.5);
  EXPECT_EQ(v.update(Vec3(1, 2, 3), 4.0), Vec3(1, 2, 3));
}

TEST(ViewFollower, FollowsAClimbAtConstantSpeedWithoutLag) {
  flapsim_ros::ViewFollower v(0.5);
  const Vec3 velocity(0.3, 0.0, 1.5);  // m/s
  for (int k = 0; k <= 1000; ++k) v.update(velocity * (0.01 * k), 0.01 * k);
  // after 10 s (20 time constants) it sits on the ramp; one-stage smoothing would lag by
  // velocity * 0.5 s = 0.77 m
  EXPECT_LT((v.position() - velocity * 10.0).norm(), 1e-6);
}

TEST(ViewFollower, ShrinksAFlappingBobToLessThanHalf) {
  flapsim_ros::ViewFollower v(0.5);
  v.update(Vec3::Zero(), 0.0);
  double worst = 0.0;
  for (int k = 1; k <= 1000; ++k) {
    const double t = 0.01 * k;
    // a 0.05 m, 5 Hz bob around a height of 1 m
    v.update(Vec3(0, 0, 1.0 + 0.05 * std::sin(2 * M_PI * 5 * t)), t);
    if (t > 5.0) worst = std::max(worst, std::abs(v.position().z() - 1.0));
  }
  EXPECT_LT(worst, 0.02);  // the bob is at most 0.05 m; smoothed, less than half of it
  EXPECT_GT(worst, 0.0);
}

TEST(ViewFollower, GoingBackInTimeStartsAfresh) {
  flapsim_ros::ViewFollower v(0.5);
  v.update(Vec3(0, 0, 0), 0.0);
  v.update(Vec3(0, 0, 5), 1.0);
  EXPECT_EQ(v.update(Vec3(7, 0, 1), 0.0), Vec3(7, 0, 1));  // a reset to t = 0
}

// The camera frame stands `distance` from the target in the direction of yaw and pitch (as
// rviz's orbit camera), its x axis pointing at the target, its y axis level, its z axis up.
TEST(Camera, LooksAtTheTargetFromYawAndPitchWithZUp) {
  flapsim_ros::ViewParams view;
  view.yaw = 0.8;
  view.pitch = 0.35;
  const Vec3 target(1, 2, 3);
  const flapsim::Pose c = flapsim_ros::cameraPose(target, 5.0, view);
  const Vec3 from(std::cos(0.35) * std::cos(0.8), std::cos(0.35) * std::sin(0.8), std::sin(0.35));
  EXPECT_NEAR((c.position - (target + 5.0 * from)).norm(), 0.0, 1e-14);
  const Eigen::Matrix3d axes = c.orientation.toRotationMatrix();
  EXPECT_NEAR((axes.col(0) - (target - c.position) / 5.0).norm(), 0.0, 1e-14);
  EXPECT_NEAR(axes.col(1).z(), 0.0, 1e-15);
  EXPECT_GT(axes.col(2).z(), 0.0);
  EXPECT_NEAR(axes.col(2).dot(axes.col(0)), 0.0, 1e-15);
}

// Looking along -x (yaw 0, pitch 0) at the origin: a point 5 m up needs the view's half
// height tan(22.5 deg) to reach 5 m + the margin; 3 m to the side, its half width (4:3); a
// point 2 m nearer the camera needs 2 m more. Far below all that: the least distance.
TEST(Camera, DistanceKeepsEveryPointInsideTheView) {
  flapsim_ros::ViewParams view;
  view.yaw = 0.0;
  view.pitch = 0.0;
  const double up = std::tan(0.5 * flapsim_ros::kCameraFieldOfView), m = flapsim_ros::kCameraMargin;
  const Vec3 o = Vec3::Zero();
  EXPECT_EQ(flapsim_ros::cameraDistance({Vec3(0, 0, 0.1)}, o, view, 2.5), 2.5);
  EXPECT_NEAR(flapsim_ros::cameraDistance({Vec3(0, 0, 5)}, o, view, 2.5), (5 + m) / up, 1e-12);
  EXPECT_NEAR(flapsim_ros::cameraDistance({Vec3(0, 3, 0)}, o, view, 2.5),
              (3 + m) / (4.0 / 3.0 * up), 1e-12);
  EXPECT_NEAR(flapsim_ros::cameraDistance({Vec3(2, 0, 5)}, o, view, 2.5), (5 + m) / up + 2, 1e-12);
  // any points: each lies inside the view of a camera at that distance
  view.yaw = 0.8;
  view.pitch = 0.35;
  const std::vector<Vec3> points = {Vec3(3, -4, 20), Vec3(-6, 2, 18), Vec3(1, 7, 25),
                                    Vec3(0, 0, 21)};
  const Vec3 target(0, 1, 21);
  const double d = flapsim_ros::cameraDistance(points, target, view, 2.5);
  const flapsim::Pose c = flapsim_ros::cameraPose(target, d, view);
  for (const Vec3& p : points) {
    const Vec3 r = c.orientation.conjugate() * (p - c.position);
    EXPECT_GT(r.x(), 0.0);
    EXPECT_LE(std::abs(r.z()) + m, up * r.x() + 1e-9);
    EXPECT_LE(std::abs(r.y()) + m, 4.0 / 3.0 * up * r.x() + 1e-9);
  }
}

TEST(Camera, ReadoutShowsSimTimeAndHeightInTheCameraFrame) {
  const visualization_msgs::Marker m =
      flapsim_ros::viewReadout(ros::Time(12, 300000000), Vec3(1, 2, 30.44));
  EXPECT_EQ(m.text, "t = 12.30 s   z = 30.4 m");
  EXPECT_EQ(m.header.frame_id, "flapsim/camera");
  EXPECT_TRUE(m.frame_locked);
  EXPECT_EQ(m.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_GT(m.pose.position.x, 0.0);  // ahead of the camera
}

}  // namespace
