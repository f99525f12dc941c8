// URDF meshes: read through assimp (STL ascii and binary, OBJ, DAE, <mesh scale>), their URIs
// resolved as ROS does, refused by name when unreadable; colliding as their convex hull; in
// the air as cells of their triangles (test/meshes/make_meshes.py writes the meshes).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "flapsim/world.h"
#include "fluid/creature_fluid.h"
#include "fluid/mesh_surface.h"
#include "fluid/pressure.h"
#include "fluid/surface.h"
#include "model/mesh_loader.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::sourcePath;

std::string meshPath(const std::string& name) { return sourcePath("test/meshes/" + name); }

// package:// URIs of this package resolve through ROS_PACKAGE_PATH: the source tree.
void usePackagePath() { ::setenv("ROS_PACKAGE_PATH", FLAPSIM_SOURCE_DIR, 1); }

// A one-link robot of mass 0.015 kg whose collision is `geometry`.
std::string oneLink(const std::string& geometry, const std::string& link = "shell") {
  return "<robot name=\"m\"><link name=\"" + link +
         "\"><inertial><mass value=\"0.015\"/><inertia ixx=\"5.625e-06\" ixy=\"0\" ixz=\"0\" "
         "iyy=\"9.125e-06\" iyz=\"0\" izz=\"1.25e-05\"/></inertial><collision><geometry>" +
         geometry + "</geometry></collision></link></robot>";
}

std::string meshXml(const std::string& uri, const std::string& scale = "") {
  return "<mesh filename=\"" + uri + "\"" + (scale.empty() ? "" : " scale=\"" + scale + "\"") +
         "/>";
}

// The first mesh of the first link (kept alive by the pointer, not by the model).
std::shared_ptr<const MeshData> meshOf(const CreatureModelPtr& m) {
  return m->links.at(0).meshes.at(0).mesh;
}

// A binary STL of `mesh`'s triangles in `path`.
void writeBinaryStl(const std::string& path, const MeshData& mesh) {
  std::ofstream out(path, std::ios::binary);
  char header[80] = "binary stl";
  out.write(header, 80);
  const uint32_t n = static_cast<uint32_t>(mesh.triangles.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : mesh.triangles) {
    float values[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c)
        values[3 + 3 * k + c] = static_cast<float>(mesh.vertices[t[k]][c]);
    }
    out.write(reinterpret_cast<const char*>(values), sizeof values);
    const uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
}

// STL (ascii, binary), OBJ and DAE boxes read as closed 12-triangle meshes of the box's volume
// (vertices are single precision in assimp: 1e-6 relative); <mesh scale> scales them.
TEST(MeshLoad, StlObjDaeBoxesAreClosedWithTheBoxVolume) {
  const auto stl = parseCreatureModel(oneLink(meshXml(meshPath("plate_box.stl"))));
  const MeshData& plate = *meshOf(stl);
  EXPECT_EQ(plate.vertices.size(), 8u);  // welded: STL repeats them per triangle
  EXPECT_EQ(plate.triangles.size(), 12u);
  EXPECT_TRUE(plate.closed);
  EXPECT_NEAR(plate.volume, 0.2 * 0.2 * 0.002, 1e-6 * 8e-5);
  EXPECT_LT((plate.upper - Vec3(0.1, 0.1, 0.001)).norm(), 1e-8);
  const std::string binary = ::testing::TempDir() + "plate_binary.stl";
  writeBinaryStl(binary, plate);
  const auto b = meshOf(parseCreatureModel(oneLink(meshXml(binary))));
  EXPECT_EQ(b->triangles.size(), 12u);
  EXPECT_TRUE(b->closed);
  EXPECT_NEAR(b->volume, plate.volume, 1e-15);
  const auto obj = meshOf(parseCreatureModel(oneLink(meshXml(meshPath("body_box.obj")))));
  EXPECT_TRUE(obj->closed);
  EXPECT_NEAR(obj->volume, 0.08 * 0.06 * 0.03, 1e-6 * 1.44e-4);
  const auto dae = meshOf(parseCreatureModel(oneLink(meshXml(meshPath("cube.dae")))));
  EXPECT_TRUE(dae->closed);
  EXPECT_NEAR(dae->volume, 1e-3, 1e-9);
  EXPECT_LT((dae->upper - Vec3(0.05, 0.05, 0.05)).norm(), 1e-8);  // Z_UP kept as written
  const auto scaled =
      parseCreatureModel(oneLink(meshXml("file://" + meshPath("cube.dae"), "2 1 0.5")));
  EXPECT_NEAR(meshOf(scaled)->volume, 1e-3, 1e-9);
  EXPECT_LT((meshOf(scaled)->upper - Vec3(0.1, 0.05, 0.025)).norm(), 1e-8);
  EXPECT_TRUE(geometryNotes(*scaled).empty());
}

// An inside-out file (or a mirror scale) is turned the right way out: positive volume, every
// face's normal away from the centre. An open sheet has no volume and is named in the notes.
TEST(MeshLoad, InsideOutIsTurnedOpenIsNamed) {
  for (const std::string& xml :
       {meshXml(meshPath("inside_out_cube.stl")), meshXml(meshPath("cube.dae"), "-1 1 1")}) {
    const auto m = meshOf(parseCreatureModel(oneLink(xml)));
    EXPECT_TRUE(m->closed);
    EXPECT_NEAR(m->volume, 1e-3, 1e-9);
    const std::vector<MeshFace> faces = meshFaces(*m, 4, 4);
    EXPECT_EQ(faces.size(), 6u);  // six rectangles of two triangles
    for (const MeshFace& f : faces) EXPECT_GT(f.normal.dot(f.cells[0].centre), 0.0);
  }
  const auto sheet = parseCreatureModel(oneLink(meshXml(meshPath("sheet.stl"))));
  EXPECT_FALSE(meshOf(sheet)->closed);
  EXPECT_EQ(meshOf(sheet)->open_edges, 4);
  EXPECT_EQ(meshOf(sheet)->volume, 0.0);
  EXPECT_EQ(geometryNotes(*sheet),
            std::vector<std::string>{"link 'shell': mesh '" + meshPath("sheet.stl") +
                                     "' is not closed (4 edges not run once each way): no volume "
                                     "(buoyancy), its air normals from its triangles' winding"});
}

// URIs as ROS resolves them: package:// through ROS_PACKAGE_PATH, file://, absolute, and a path
// relative to the URDF file's directory (test/meshes/plate_mesh.urdf names "plate_box.stl").
TEST(MeshLoad, UrisResolveAsRosDoes) {
  usePackagePath();
  EXPECT_EQ(findRosPackage("flapsim", FLAPSIM_SOURCE_DIR), FLAPSIM_SOURCE_DIR);
  EXPECT_EQ(resolveMeshUri("package://flapsim/test/meshes/cube.dae", ""), meshPath("cube.dae"));
  EXPECT_EQ(resolveMeshUri("file:///a/b.stl", ""), "/a/b.stl");
  EXPECT_EQ(resolveMeshUri("/a/b.stl", "/c"), "/a/b.stl");
  EXPECT_EQ(resolveMeshUri("b.stl", "/c"), "/c/b.stl");
  const auto plate = loadCreatureModel(meshPath("plate_mesh.urdf"));
  EXPECT_EQ(plate->links[0].meshes[0].uri, "plate_box.stl");
  EXPECT_EQ(meshOf(plate)->triangles.size(), 12u);
  // A resolver of one's own (the node's uses ros::package::getPath).
  std::vector<std::string> asked;
  const auto own = parseCreatureModel(oneLink(meshXml("package://p/x.obj")), "<string>",
                                      [&](const std::string& uri) {
                                        asked.push_back(uri);
                                        return meshPath("body_box.obj");
                                      });
  EXPECT_EQ(asked, std::vector<std::string>{"package://p/x.obj"});
  EXPECT_NEAR(meshOf(own)->volume, 1.44e-4, 1e-9);
}

void expectRefusal(const std::string& urdf, const std::vector<std::string>& parts) {
  try {
    parseCreatureModel(urdf);
    ADD_FAILURE() << "accepted: " << urdf;
  } catch (const ModelError& e) {
    for (const std::string& p : parts) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << p << " not in " << e.what();
    }
  }
}

// A mesh that cannot be had is refused naming the link, the URI and why; a world that was
// refused such a creature goes on bit for bit as one that never saw it.
TEST(MeshLoad, UnreadableMeshesAreRefusedByName) {
  usePackagePath();
  const std::string missing = meshPath("no_such.stl");
  expectRefusal(oneLink(meshXml(missing), "wing"),
                {"link 'wing'", "mesh '" + missing + "'", "no such file"});
  expectRefusal(oneLink(meshXml(meshPath("corrupt.stl"))),
                {"link 'shell'", "corrupt.stl'", "assimp cannot read"});
  expectRefusal(oneLink(meshXml("package://no_such_package/a.stl")),
                {"link 'shell'", "package://no_such_package/a.stl", "unknown package"});
  expectRefusal(oneLink(meshXml("http://host/a.stl")), {"link 'shell'", "unsupported URI"});
  expectRefusal(oneLink(meshXml("a.stl")), {"link 'shell'", "relative path"});
  expectRefusal(oneLink(meshXml(meshPath("cube.dae"), "0 1 1")), {"link 'shell'", "scale"});
  expectRefusal(oneLink(meshXml(sourcePath("test/meshes"))), {"not a regular file"});
  World a(test::openSky()), b(test::openSky());
  for (World* w : {&a, &b}) {
    w->spawn("p", test::loadUrdf("plate.urdf"), test::at(0, 0, 10));
    w->step(50);
  }
  EXPECT_THROW(a.spawn("m", parseCreatureModel(oneLink(meshXml(missing))), test::at(0, 0, 5)),
               ModelError);
  EXPECT_EQ(a.creatureNames(), std::vector<std::string>{"p"});
  a.step(50);
  b.step(50);
  EXPECT_TRUE(test::bitIdentical(a.state("p"), b.state("p")));
}

// The pressure law's wrench on `surface` moving at v, turning at w, in still air.
Wrench wrenchOf(const AeroSurface& surface, const Vec3& v, const Vec3& w) {
  BodyKinematics body;
  body.linear_velocity = v;
  body.angular_velocity = w;
  return PressureAirModel().bodyWrench(body, surface, AirParams(), nullptr);
}

double areaOf(const AeroSurface& s) {
  double area = 0.0;
  for (const SurfaceCell& c : s.cells) area += c.area;
  return area;
}

// A box's 12-triangle mesh is cut into the box's cells (two triangles a rectangle, cut as a box
// face, a plate's rim in one row): the same cells, area, volume, air wrench and added mass to
// the assimp's single precision vertices. Measured: 3e-8 relative.
TEST(MeshSurface, ABoxMeshHasTheBoxsCellsAndAddedMass) {
  usePackagePath();
  const AirParams air;
  const auto box = test::loadUrdf("plate.urdf");
  const auto mesh = loadCreatureModel(meshPath("plate_mesh.urdf"));
  const AeroSurface a = linkAeroSurface(*box, 0, air), b = linkAeroSurface(*mesh, 0, air);
  ASSERT_EQ(a.cells.size(), 2u * 16u + 4u * 4u);
  EXPECT_EQ(b.cells.size(), a.cells.size());
  EXPECT_EQ(b.faces.size(), 6u);
  for (const SurfaceFace& f : b.faces) EXPECT_GT(f.nu, 0);  // all grids
  EXPECT_NEAR(areaOf(b), areaOf(a), 1e-7 * areaOf(a));
  EXPECT_NEAR(b.volume, a.volume, 1e-7 * a.volume);
  double worst = 0.0;
  for (const Vec3& v : {Vec3(0, 0, -3), Vec3(2, 1, -1), Vec3(-1, 3, 0.5)}) {
    for (const Vec3& w : {Vec3(0, 0, 0), Vec3(5, -3, 1)}) {
      const Wrench x = wrenchOf(a, v, w), y = wrenchOf(b, v, w);
      worst = std::max(worst, (y.force - x.force).norm() / x.force.norm());
      worst = std::max(worst, (y.torque - x.torque).norm() / std::max(x.force.norm(), 1e-9));
    }
  }
  std::cout << "box mesh vs box, air wrench: " << worst << " relative\n";
  EXPECT_LT(worst, 1e-6);
  const Mat6 ma = linkAddedMass(box->links[0], air), mb = linkAddedMass(mesh->links[0], air);
  EXPECT_GT(ma.norm(), 0.0);
  EXPECT_LT((mb - ma).norm(), 1e-6 * ma.norm());
}

std::shared_ptr<const MeshData> icosphere() {
  return readMeshFile(meshPath("icosphere.obj"), Vec3::Ones());
}

// An icosphere of radius 0.1 (1280 triangles, vertices on the sphere) against the law's
// integral over the sphere, 1/2 rho Cd v^2 2/3 pi r^2 (test_round_shapes), and the faceted
// RoundShape sphere (12 x 6 cells): its triangles are single cells (about 0.012 m across, under
// the cell size h = 0.05), its volume the inscribed polyhedron's. Measured: drag -0.48 % along
// each of the three directions (the RoundShape sphere's: +1.34, -0.67, +0.62 %), volume -0.86 %.
TEST(MeshSurface, IcosphereDragIsTheLawsIntegralWithinTheFacetError) {
  const auto ball = icosphere();
  ASSERT_TRUE(ball->closed);
  EXPECT_EQ(ball->triangles.size(), 1280u);
  const double r = 0.1, v = 3.0;
  const AirParams air;
  MeshShape shape;
  shape.mesh = ball;
  const AeroSurface s = buildSurface({}, 4, 4, std::nullopt, {}, {shape});
  EXPECT_EQ(s.cells.size(), 1280u);
  EXPECT_EQ(meshCellCount(*ball, 4, 4), 1280);
  const double exact = 0.5 * air.density * air.drag_coefficient * v * v * 2.0 / 3.0 * M_PI * r * r;
  const AeroSurface round =
      buildSurface({}, 4, 4, std::nullopt, {RoundShape{RoundShape::Kind::kSphere, r, 0.0, Pose()}});
  for (const Vec3& dir : {Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(1, 2, -3).normalized()}) {
    const Vec3 f = wrenchOf(s, v * dir, Vec3::Zero()).force;
    const double error = -f.dot(dir) / exact - 1.0;
    const double round_error = -wrenchOf(round, v * dir, Vec3::Zero()).force.dot(dir) / exact - 1.0;
    std::cout << "icosphere drag " << 100 * error << " %, RoundShape sphere " << 100 * round_error
              << " % along " << dir.transpose() << "\n";
    EXPECT_LT(std::abs(error), 0.015) << dir.transpose();
    EXPECT_LT((f + f.dot(dir) * -dir).norm(), 0.001 * exact) << dir.transpose();
  }
  const double volume = 4.0 / 3.0 * M_PI * r * r * r;
  std::cout << "icosphere volume " << 100 * (s.volume / volume - 1.0) << " %\n";
  EXPECT_NEAR(s.volume, volume, 0.02 * volume);
  EXPECT_LT(s.centroid.norm(), 1e-9);
}

// A cell of a link's shape inside another of its shapes feels no air: a box inside a closed
// mesh loses all its cells, a mesh's triangles flush against a box face are dropped.
TEST(MeshSurface, CellsInsideOtherShapesAreHidden) {
  MeshShape cube;
  cube.mesh = readMeshFile(meshPath("cube.dae"), Vec3::Ones());  // 0.1 m edges, centred
  const Box inner{Vec3(0.05, 0.05, 0.05), Pose()};
  const AeroSurface s = buildSurface({inner}, 4, 4, std::nullopt, {}, {cube});
  EXPECT_EQ(s.cells.size(), 6u * 16u);  // the cube's own cells only
  // A box on the cube's top face (z = 0.05): the cube's top cells under it are hidden.
  const Box lid{Vec3(0.1, 0.1, 0.02), test::at(0, 0, 0.06)};
  const AeroSurface t = buildSurface({lid}, 4, 4, std::nullopt, {}, {cube});
  // The cube keeps 5 faces of 16; the lid (a plate: its rims one row of 4) 16 on top, 4 x 4.
  EXPECT_EQ(t.cells.size(), 5u * 16u + 16u + 4u * 4u);
  EXPECT_TRUE(insideMesh(*cube.mesh, Vec3(0.01, -0.02, 0.03), 0.0));
  EXPECT_FALSE(insideMesh(*cube.mesh, Vec3(0.01, -0.02, 0.06), 0.0));
  EXPECT_TRUE(insideMesh(*cube.mesh, Vec3(0.01, -0.02, 0.05 + 1e-9), 1e-8));
}

// Dropped from 0.2 m onto the ground, a body whose only shape is a mesh (body_box.obj, 0.08 x
// 0.06 x 0.03 m) rests on its hull's largest face: its centre at half its height plus the hull's
// contact margin (1 mm), as the box body rests at half its height. Measured: mesh 0.0160 m,
// box 0.0150 m; the hull keeps a contact jitter of 3e-3 rad/s (6e-5 m/s), the box none.
TEST(MeshWorld, AMeshOnlyBodyRestsOnItsConvexHull) {
  const auto mesh = parseCreatureModel(oneLink(meshXml(meshPath("body_box.obj"))));
  const auto box = parseCreatureModel(oneLink("<box size=\"0.08 0.06 0.03\"/>"));
  WorldParams p;  // ground and air on
  World w(p);
  w.spawn("mesh", mesh,
          test::at(0, 0, 0.2, Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()))));
  w.spawn("box", box, test::at(1, 0, 0.2));
  w.step(6000);
  const double zm = w.rootPose("mesh").position.z(), zb = w.rootPose("box").position.z();
  std::cout.precision(7);
  std::cout << "resting centre: mesh " << zm << " m, box " << zb << " m; mesh speed "
            << w.rootTwist("mesh").linear.norm() << " m/s, spin "
            << w.rootTwist("mesh").angular.transpose() << " rad/s\n";
  EXPECT_NEAR(zm, 0.015 + 1e-3, 2e-4);
  EXPECT_NEAR(zb, 0.015, 2e-4);
  EXPECT_LT(w.rootTwist("mesh").linear.norm(), 1e-3);
  EXPECT_LT(w.rootTwist("mesh").angular.norm(), 1e-2);
  EXPECT_LT(w.rootTwist("box").linear.norm() + w.rootTwist("box").angular.norm(), 1e-3);
  EXPECT_GT((w.rootPose("mesh").orientation * Vec3::UnitZ()).z(), 0.999);  // on its big face
  EXPECT_NEAR(lowestBoxPoint(*mesh, w.state("mesh").link_poses), 1e-3, 2e-4);
}

// Falling through air (no buoyancy), the icosphere reaches the terminal speed of the law's
// sphere, sqrt(2 m g / (rho 2/3 Cd pi r^2)), within its drag's facet error (-0.48 %: the speed
// +0.24 %). Measured: +0.24 %.
TEST(MeshWorld, AFallingIcosphereReachesTheSpheresTerminalSpeed) {
  WorldParams p = test::openSky();
  p.air.buoyancy = false;
  World w(p);
  const double r = 0.1, m = 0.05;
  const std::string inertia =
      "ixx=\"2e-4\" ixy=\"0\" ixz=\"0\" iyy=\"2e-4\" iyz=\"0\" izz=\"2e-4\"";
  w.spawn("ball",
          parseCreatureModel(
              "<robot name=\"b\"><link name=\"ball\"><inertial><mass value=\"0.05\"/>"
              "<inertia " +
              inertia + "/></inertial><collision><geometry>" + meshXml(meshPath("icosphere.obj")) +
              "</geometry></collision></link></robot>"),
          test::at(0, 0, 100));
  w.step(4000);
  const double vt =
      std::sqrt(2 * m * 9.81 / (p.air.density * 2.0 / 3.0 * p.air.drag_coefficient * M_PI * r * r));
  const double v = -w.rootTwist("ball").linear.z();
  std::cout << "icosphere terminal speed " << 100 * (v / vt - 1.0) << " % of the law's sphere\n";
  EXPECT_NEAR(v, vt, 0.004 * vt);
}

double poseError(const Pose& a, const Pose& b) {
  return (a.position - b.position).norm() + a.orientation.angularDistance(b.orientation);
}

// The plate tilted 0.3 rad glides for 1 s as its 12-triangle mesh (test/meshes/plate_mesh.urdf)
// does: the same cells (MeshSurface above) to single precision vertices. Measured: 2.4e-8 m/rad.
TEST(MeshFlight, AMeshedPlateGlidesAsTheBoxPlate) {
  World w(test::openSky());
  const Pose start = test::at(0, 0, 20, Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())));
  w.spawn("box", test::loadUrdf("plate.urdf"), start);
  w.spawn("mesh", loadCreatureModel(meshPath("plate_mesh.urdf")), start);
  w.step(static_cast<int>(1.0 / w.params().step_size));
  const Pose a = w.rootPose("box"), b = w.rootPose("mesh");
  ASSERT_GT((a.position - start.position).norm(), 1.0);  // it fell and glided
  ASSERT_GT(std::abs(a.position.x()), 0.1);
  std::cout << "meshed plate vs plate after 1 s: " << poseError(a, b) << " m/rad\n";
  EXPECT_LT(poseError(a, b), 1e-6);
}

// Flies each creature of `models` from 20 m up at 60/10 rad/s strokes (amplitude 0.8) for
// `seconds`, in one world; their names are their indices.
std::unique_ptr<World> flap(const WorldParams& params, const std::vector<CreatureModelPtr>& models,
                            double seconds) {
  auto w = std::make_unique<World>(params);
  for (size_t k = 0; k < models.size(); ++k) {
    const std::string name = std::to_string(k);
    w->spawn(name, models[k], test::at(0, 0, 20));
    w->setWingCommands(name, {}, {StrokeCommand{60, 10, 0.8}, StrokeCommand{60, 10, 0.8}});
  }
  w->step(static_cast<int>(seconds / w->params().step_size));
  return w;
}

// Issue 43's acceptance: a meshed copy of urdf/flap_unit.urdf (body_box.obj, wing_box.stl)
// climbs within 2 % of the box version in 6 s; after 1 s their poses agree to the vertices'
// single precision (the unit is unstable in roll, test_flight: the difference grows). Measured:
// 1 s 2.2e-9 m/rad; in 6 s the box unit climbs 4.487 m, the meshed one 4.496 m (+0.20 %).
TEST(MeshFlight, AMeshedFlapUnitClimbsAsTheBoxUnit) {
  usePackagePath();
  const auto box = test::loadUrdf("flap_unit.urdf");
  const auto mesh = loadCreatureModel(meshPath("flap_unit_mesh.urdf"));
  ASSERT_EQ(mesh->links[1].meshes.size(), 1u);
  const auto one = flap(test::openSky(), {box, mesh}, 1.0);
  const double one_second = poseError(one->rootPose("0"), one->rootPose("1"));
  const auto six = flap(test::openSky(), {box, mesh}, 6.0);
  const double h_box = six->rootPose("0").position.z() - 20.0;
  const double h_mesh = six->rootPose("1").position.z() - 20.0;
  std::cout << "meshed flap unit vs box: after 1 s " << one_second << " m/rad; in 6 s climbs "
            << h_mesh << " m vs " << h_box << " m (" << 100 * (h_mesh / h_box - 1.0) << " %)\n";
  EXPECT_LT(one_second, 1e-6);
  EXPECT_GT(h_box, 1.0);
  EXPECT_NEAR(h_mesh, h_box, 0.02 * std::abs(h_box));
}

// A robot URDF as CAD exports it (test/ros/cad_mesh_unit.urdf: a massless base_link carrying
// the body's OBJ mesh, a full inertia tensor, STL wings, package:// URIs) spawns, rests on the
// ground on its body's hull, and flaps with the air on its mesh wings: it flies as the box
// version test/ros/cad_unit.urdf. Measured: at rest its lowest point 1.0 mm up (the hull's
// margin), 1e-8 m/s; after 1 s of flapping 2.2e-9 m/rad from the box version, 0.63 m up.
TEST(MeshFlight, ACadMeshRobotSpawnsRestsAndFlaps) {
  usePackagePath();
  const auto cad = loadCreatureModel(sourcePath("test/ros/cad_mesh_unit.urdf"));
  ASSERT_EQ(cad->links[0].name, "body");  // base_link lumped into it, with its mesh
  ASSERT_EQ(cad->links[0].meshes.size(), 1u);
  ASSERT_EQ(cad->links[1].meshes.size(), 1u);
  World ground;  // ground and air on
  ground.spawn("cad", cad, test::at(0, 0, 0.3));
  ground.step(3000);
  const double lowest = lowestBoxPoint(*cad, ground.state("cad").link_poses);
  std::cout << "CAD mesh robot at rest: lowest point " << lowest << " m, speed "
            << ground.rootTwist("cad").linear.norm() << " m/s\n";
  EXPECT_NEAR(lowest, 1e-3, 3e-4);
  EXPECT_LT(ground.rootTwist("cad").linear.norm(), 1e-2);
  const auto air =
      flap(test::openSky(), {cad, loadCreatureModel(sourcePath("test/ros/cad_unit.urdf"))}, 1.0);
  const double up = air->rootPose("0").position.z() - 20.0;
  const double apart = poseError(air->rootPose("0"), air->rootPose("1"));
  std::cout << "CAD mesh robot vs box version after 1 s: " << apart << " m/rad, up " << up
            << " m\n";
  EXPECT_GT(up, 0.1);
  EXPECT_LT(apart, 1e-6);
}

}  // namespace
}  // namespace flapsim
