// The convex decomposition of URDF meshes (<collision_mesh link="..."
// optimization="convex_decomposition"/>, HACD): a U-shaped block (test/meshes/u_block.obj)
// splits into its two prongs and its floor, the same bits every time; a ball dropped into its
// notch falls to the floor of the decomposed block and rests on top of its hull; a torus's parts
// against its volume; a decomposed link resting in a world; every bad request refused by name.
#include <LinearMath/btConvexHullComputer.h>
#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "dynamics/bullet_body.h"
#include "fluid/mesh_surface.h"
#include "model/convex_decomposition.h"
#include "model/mesh_loader.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::sourcePath;

std::string uBlockPath() { return sourcePath("test/meshes/u_block.obj"); }

// The U-shaped block: 0.1 x 0.04 x 0.06 m, its notch 0.04 m wide and deep, floor at z = 0.02.
std::shared_ptr<const MeshData> uBlock() { return readMeshFile(uBlockPath(), Vec3::Ones()); }
constexpr double kUVolume = (0.1 * 0.06 - 0.04 * 0.04) * 0.04;
constexpr double kNotchFloor = 0.02, kTop = 0.06;
// assimp's vertices are single precision: a coordinate within 2e-9 m of the file's, a volume
// within 1e-7 of it.
constexpr double kFloat = 2e-9, kFloatVolume = 1e-7 * kUVolume;

// A torus about z (radii 0.05 and 0.015 m) of nu x nv quads, two triangles each.
MeshData torus(int nu, int nv) {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> t;
  const double big = 0.05, small = 0.015;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, w = 2 * M_PI * j / nv;
      v.emplace_back((big + small * std::cos(w)) * std::cos(u),
                     (big + small * std::cos(w)) * std::sin(u), small * std::sin(w));
    }
  }
  auto at = [&](int i, int j) { return (i % nu) * nv + j % nv; };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return makeMeshData(std::move(v), std::move(t));
}

// A convex hull as its outward face planes (n . p <= d inside) and its volume.
struct Hull {
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  double volume = 0.0;
  bool contains(const Vec3& p) const {
    for (size_t f = 0; f < normals.size(); ++f) {
      if (normals[f].dot(p) > offsets[f] + 1e-12) return false;
    }
    return !normals.empty();
  }
};

Hull hullOf(const std::vector<Vec3>& points) {
  btConvexHullComputer c;
  c.compute(points.data()->data(), static_cast<int>(sizeof(Vec3)), static_cast<int>(points.size()),
            0, 0);
  Hull h;
  Vec3 centre = Vec3::Zero();
  for (int i = 0; i < c.vertices.size(); ++i) centre += fromBt(c.vertices[i]);
  centre /= c.vertices.size();
  for (int f = 0; f < c.faces.size(); ++f) {
    std::vector<Vec3> loop;
    const btConvexHullComputer::Edge* first = &c.edges[c.faces[f]];
    const btConvexHullComputer::Edge* e = first;
    do {
      loop.push_back(fromBt(c.vertices[e->getSourceVertex()]));
      e = e->getNextEdgeOfFace();
    } while (e != first);
    Vec3 n = Vec3::Zero();  // Newell's normal
    for (size_t k = 0; k < loop.size(); ++k) n += loop[k].cross(loop[(k + 1) % loop.size()]);
    if (n.norm() < 1e-18) continue;
    n.normalize();
    if (n.dot(loop[0] - centre) < 0) n = -n;
    h.normals.push_back(n);
    h.offsets.push_back(n.dot(loop[0]));
    for (size_t k = 1; k + 1 < loop.size(); ++k) {
      h.volume += std::abs((loop[0] - centre).dot((loop[k] - centre).cross(loop[k + 1] - centre)));
    }
  }
  h.volume /= 6.0;
  return h;
}

// Whether two decompositions are the same to the bit.
bool identical(const ConvexParts& a, const ConvexParts& b) {
  if (a.size() != b.size()) return false;
  for (size_t p = 0; p < a.size(); ++p) {
    if (a[p].size() != b[p].size()) return false;
    if (std::memcmp(a[p].data(), b[p].data(), a[p].size() * sizeof(Vec3)) != 0) return false;
  }
  return true;
}

// HACD's parts of the U block are its three boxes: the prongs (0.03 x 0.04 x 0.06 m) and the
// floor between them (0.04 x 0.04 x 0.02 m), whose volumes sum to the block's to rounding
// (the vertices being single precision, to 2e-9 m).
TEST(ConvexDecomposition, TheUBlockSplitsIntoItsTwoProngsAndItsFloor) {
  const auto mesh = uBlock();
  ASSERT_TRUE(mesh->closed);
  EXPECT_NEAR(mesh->volume, kUVolume, kFloatVolume);
  const ConvexParts parts = decomposeMesh(*mesh, kDefaultMaxConvexHulls);
  ASSERT_EQ(parts.size(), 3u);
  std::vector<std::pair<Vec3, Vec3>> boxes;  // each part's bounds, sorted by their lower x
  double sum = 0.0;
  for (const std::vector<Vec3>& part : parts) {
    Vec3 lo = part[0], hi = part[0];
    for (const Vec3& p : part) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Hull h = hullOf(part);
    EXPECT_NEAR(h.volume, (hi - lo).prod(), 1e-12 * kUVolume);  // the part is its bounding box
    sum += h.volume;
    boxes.emplace_back(lo, hi);
  }
  std::sort(boxes.begin(), boxes.end(),
            [](const auto& a, const auto& b) { return a.first.x() < b.first.x(); });
  const double expected[3][4] = {{-0.05, -0.02, 0.0, kTop},  // x from, x to, z from, z to
                                 {-0.02, 0.02, 0.0, kNotchFloor},
                                 {0.02, 0.05, 0.0, kTop}};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(boxes[k].first.x(), expected[k][0], kFloat) << "part " << k;
    EXPECT_NEAR(boxes[k].second.x(), expected[k][1], kFloat) << "part " << k;
    EXPECT_NEAR(boxes[k].first.z(), expected[k][2], kFloat) << "part " << k;
    EXPECT_NEAR(boxes[k].second.z(), expected[k][3], kFloat) << "part " << k;
    EXPECT_NEAR(boxes[k].second.y() - boxes[k].first.y(), 0.04, kFloat) << "part " << k;
  }
  EXPECT_NEAR(sum, mesh->volume, 1e-12 * kUVolume);
}

// Two decompositions of the same mesh (two HACD runs each, the torus being merged on down to
// max_convex_hulls) are identical to the bit.
TEST(ConvexDecomposition, TheSameMeshGivesTheSamePartsBitForBit) {
  const auto u = uBlock();
  EXPECT_TRUE(identical(decomposeMesh(*u, 16), decomposeMesh(*u, 16)));
  const MeshData ring = torus(24, 8);
  const ConvexParts a = decomposeMesh(ring, 6), b = decomposeMesh(ring, 6);
  EXPECT_EQ(a.size(), 6u);
  EXPECT_TRUE(identical(a, b));
}

// An open flat sheet (two triangles, test_mesh's) is one flat part of its four corners.
TEST(ConvexDecomposition, AFlatSheetIsOneFlatPart) {
  const auto sheet = readMeshFile(sourcePath("test/meshes/sheet.stl"), Vec3::Ones());
  const ConvexParts flat = decomposeMesh(*sheet, kDefaultMaxConvexHulls);
  ASSERT_EQ(flat.size(), 1u);
  EXPECT_EQ(flat[0].size(), 4u);
}

// Of samples on a 32^3 grid over `mesh`'s bounds: those inside it, those of them inside a part
// of `parts`, and those inside a part.
struct Coverage {
  int inside = 0, covered = 0, in_union = 0;
};
Coverage coverage(const MeshData& mesh, const ConvexParts& parts) {
  std::vector<Hull> hulls;
  for (const auto& p : parts) hulls.push_back(hullOf(p));
  const int n = 32;
  const Vec3 size = mesh.upper - mesh.lower;
  Coverage c;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Vec3 p = mesh.lower + size.cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5) / n);
        const bool in_mesh = insideMesh(mesh, p, 0.0);
        bool in_parts = false;
        for (const Hull& h : hulls) in_parts = in_parts || h.contains(p);
        c.inside += in_mesh;
        c.covered += in_mesh && in_parts;
        c.in_union += in_parts;
      }
    }
  }
  return c;
}

// The parts of curved closed meshes, a torus (384 triangles) and test_mesh's icosphere (1280),
// are hulls of patches of their surface: their union covers at least 98 % of the samples inside
// the mesh (a thick body's core may stay partly hollow) and exceeds them by at most 10 % (a
// curved patch's hull fills the chord across it). Measured: torus 14 parts, 100 % covered,
// union 1.028; icosphere 6 parts, 98.55 % covered, union 0.986.
TEST(ConvexDecomposition, CurvedMeshesPartsCoverAtLeast98PercentAndExceedThemByAtMostATenth) {
  const MeshData ring = torus(24, 8);
  const auto sphere = readMeshFile(sourcePath("test/meshes/icosphere.obj"), Vec3::Ones());
  for (const MeshData* mesh : {&ring, sphere.get()}) {
    const ConvexParts parts = decomposeMesh(*mesh, kDefaultMaxConvexHulls);
    const Coverage c = coverage(*mesh, parts);
    std::cout << mesh->triangles.size() << " triangles, " << parts.size()
              << " parts: samples inside " << c.inside << ", of them in a part " << c.covered
              << ", in a part " << c.in_union << " (" << double(c.in_union) / c.inside << ")\n";
    EXPECT_GE(c.covered, 0.98 * c.inside);
    EXPECT_LE(c.in_union, 1.1 * c.inside);
  }
}

// Where a ball (radius 0.01 m) dropped from 0.1 m above the notch of the U block comes to rest:
// its centre's height after 2 s, the block fixed in a Bullet world with `mesh`'s colliders.
double ballRestHeight(const MeshShape& mesh, Vec3* rest_position = nullptr) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, -9.81));
  const auto hulls = meshColliders(mesh);
  btCompoundShape compound;
  for (const auto& h : hulls) compound.addChildShape(btTransform::getIdentity(), h.get());
  btRigidBody block(btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, &compound));
  world.addRigidBody(&block);
  const double radius = 0.01, mass = 0.01;
  btSphereShape sphere(radius);
  btVector3 inertia;
  sphere.calculateLocalInertia(mass, inertia);
  btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, &sphere, inertia);
  info.m_startWorldTransform.setOrigin(btVector3(0, 0, kTop + 0.1));
  btRigidBody ball(info);
  ball.setActivationState(DISABLE_DEACTIVATION);
  world.addRigidBody(&ball);
  for (int i = 0; i < 2000; ++i) world.stepSimulation(1e-3, 0);
  const btVector3 p = ball.getWorldTransform().getOrigin();
  world.removeRigidBody(&ball);
  world.removeRigidBody(&block);
  if (rest_position) *rest_position = fromBt(p);
  return p.z();
}

// Dropped into the notch, the ball rests on the hull's top face (z = 0.06 m) when the block
// collides as its convex hull, and on the notch's floor (z = 0.02 m) when it collides as its
// parts: its centre its radius and the hulls' contact margin (1 mm) above them.
TEST(ConvexDecompositionContact, ABallRestsOnTheHullsTopButFallsToTheNotchFloorOfTheParts) {
  MeshShape shape;
  shape.mesh = uBlock();
  Vec3 on_hull, in_notch;
  const double z_hull = ballRestHeight(shape, &on_hull);
  shape.parts = std::make_shared<const ConvexParts>(decomposeMesh(*shape.mesh, 16));
  ASSERT_EQ(meshColliders(shape).size(), 3u);
  const double z_parts = ballRestHeight(shape, &in_notch);
  std::cout.precision(8);
  std::cout << "ball at rest: on the hull " << on_hull.transpose() << ", in the notch "
            << in_notch.transpose() << " m\n";
  EXPECT_NEAR(z_hull, kTop + kHullMargin + 0.01, 1e-4);
  EXPECT_NEAR(z_parts, kNotchFloor + kHullMargin + 0.01, 1e-4);
  EXPECT_LT(in_notch.head<2>().norm(), 1e-6);  // straight down the middle
}

// A one-link robot of the U block (50 g) with `extra` after its link.
std::string uRobot(const std::string& extra, const std::string& uri = uBlockPath()) {
  return "<robot name=\"u\"><link name=\"block\"><inertial><origin xyz=\"0 0 0.0263636\"/>"
         "<mass value=\"0.05\"/><inertia ixx=\"2.1667e-05\" ixy=\"0\" ixz=\"0\" iyy=\"5.6667e-05\" "
         "iyz=\"0\" izz=\"4.8333e-05\"/></inertial><collision><geometry><mesh filename=\"" +
         uri + "\"/></geometry></collision></link>" + extra + "</robot>";
}

// Through the URDF: the link that asks collides as the three parts, the others as the hull
// (no element, or optimization="convex_hull"); the inertia is the URDF's either way. Dropped
// upside down onto the ground, the decomposed block rests on its prongs' tops: its frame 0.06 m
// plus the contact margin above the ground.
TEST(ConvexDecompositionUrdf, ALinkAsksForItsPartsAndRestsOnThem) {
  const auto parts = parseCreatureModel(
      uRobot("<collision_mesh link=\"block\" optimization=\"convex_decomposition\" "
             "max_convex_hulls=\"8\"/>"));
  const auto hull = parseCreatureModel(uRobot(""));
  const auto hull_asked =
      parseCreatureModel(uRobot("<collision_mesh link=\"block\" optimization=\"convex_hull\"/>"));
  const MeshShape& m = parts->links.at(0).meshes.at(0);
  ASSERT_TRUE(m.parts);
  EXPECT_EQ(m.parts->size(), 3u);
  EXPECT_TRUE(identical(*m.parts, decomposeMesh(*uBlock(), 8)));
  EXPECT_FALSE(hull->links.at(0).meshes.at(0).parts);
  EXPECT_FALSE(hull_asked->links.at(0).meshes.at(0).parts);
  EXPECT_EQ(parts->links[0].inertia, hull->links[0].inertia);
  EXPECT_EQ(parts->links[0].mass, hull->links[0].mass);
  WorldParams p;
  p.air.enabled = false;
  World w(p);
  w.spawn("u", parts, test::at(0, 0, 0.2, Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX()))));
  w.step(3000);
  std::cout.precision(7);
  std::cout << "upside-down block at rest: frame at z = " << w.rootPose("u").position.z()
            << " m, speed " << w.rootTwist("u").linear.norm() << " m/s\n";
  EXPECT_NEAR(w.rootPose("u").position.z(), kTop + kHullMargin, 2e-4);
  EXPECT_LT(w.rootTwist("u").linear.norm(), 1e-3);
}

// `verts` and `tris` as an OBJ file in the test's temporary directory; its path.
std::string writeObj(const std::string& name, const std::vector<Vec3>& verts,
                     const std::vector<std::array<int, 3>>& tris) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream out(path);
  out.precision(17);
  for (const Vec3& v : verts) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : tris) out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  return path;
}

// A 0.1 m cube centred at `centre`, each face an n x n grid of squares (12 n^2 triangles).
void gridCube(int n, const Vec3& centre, std::vector<Vec3>& verts,
              std::vector<std::array<int, 3>>& tris) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = -1; side <= 1; side += 2) {
      const Vec3 normal = side * Vec3::Unit(axis);
      const Vec3 u = Vec3::Unit((axis + 1) % 3), v = normal.cross(u);
      const int base = static_cast<int>(verts.size());
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          verts.push_back(centre + 0.05 * normal + (0.1 * i / n - 0.05) * u +
                          (0.1 * j / n - 0.05) * v);
        }
      }
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const int a = base + i * (n + 1) + j;
          tris.push_back({a, a + n + 1, a + n + 2});
          tris.push_back({a, a + n + 2, a + 1});
        }
      }
    }
  }
}

const std::string kDecompose =
    "<collision_mesh link=\"block\" optimization=\"convex_decomposition\"";

// OBJ files of the refusals: a cube of 5292 triangles; two cubes of 4800 and 192 triangles;
// two cubes of 12 triangles 0.9 m apart.
struct RefusedMeshes {
  std::string fine, near, apart;
  RefusedMeshes() {
    std::vector<Vec3> verts;
    std::vector<std::array<int, 3>> tris;
    gridCube(21, Vec3::Zero(), verts, tris);
    fine = writeObj("fine_cube.obj", verts, tris);
    verts.clear();
    tris.clear();
    gridCube(20, Vec3::Zero(), verts, tris);
    gridCube(4, Vec3(1, 0, 0), verts, tris);
    near = writeObj("near_limit.obj", verts, tris);
    verts.clear();
    tris.clear();
    gridCube(1, Vec3::Zero(), verts, tris);
    gridCube(1, Vec3(1, 0, 0), verts, tris);
    apart = writeObj("two_cubes.obj", verts, tris);
  }
};

// Each bad request is a ModelError naming the element or the link and mesh, and what is wrong.
TEST(ConvexDecompositionUrdf, BadRequestsAreRefusedByName) {
  const RefusedMeshes files;
  const std::string &fine = files.fine, &near = files.near, &apart = files.apart;
  const std::string& decompose = kDecompose;
  std::string two_meshes = uRobot(decompose + "/>");  // the U block's 36 triangles, then 4992
  two_meshes.insert(two_meshes.find("</link>"), "<collision><geometry><mesh filename=\"" + near +
                                                    "\"/></geometry></collision>");
  const std::string box_robot =
      "<robot name=\"b\"><link name=\"block\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" "
      "ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial><collision><geometry><box "
      "size=\"0.1 0.1 0.1\"/></geometry></collision></link>" +
      decompose + "/></robot>";
  const struct {
    std::string urdf, message;
  } cases[] = {
      {uRobot("<collision_mesh link=\"block\" optimization=\"concave_hull\"/>"),
       "<collision_mesh link='block'>: optimization must be convex_hull or convex_decomposition, "
       "got 'concave_hull'"},
      {uRobot(decompose + " max_convex_hulls=\"65\"/>"),
       "<collision_mesh link='block'>: max_convex_hulls must be an integer in 1..64, got '65'"},
      {uRobot(decompose + " max_convex_hulls=\"0\"/>"), "in 1..64, got '0'"},
      {uRobot(decompose + " max_convex_hull=\"8\"/>"),
       "<collision_mesh link='block'>: unknown attribute 'max_convex_hull' (it has link, "
       "optimization and max_convex_hulls)"},
      {uRobot(decompose + " max_convex_hulls=\"2.5\"/>"), "in 1..64, got '2.5'"},
      {uRobot(decompose + " max_convex_hulls=\"many\"/>"), "in 1..64, got 'many'"},
      {uRobot(
           "<collision_mesh link=\"block\" optimization=\"convex_hull\" max_convex_hulls=\"4\"/>"),
       "<collision_mesh link='block'>: max_convex_hulls is for "
       "optimization='convex_decomposition' only"},
      {uRobot("<collision_mesh link=\"wing\" optimization=\"convex_decomposition\"/>"),
       "<collision_mesh> names unknown link 'wing'"},
      {uRobot("<collision_mesh optimization=\"convex_decomposition\"/>"),
       "<collision_mesh> without a link attribute"},
      {uRobot(decompose + "/>" + decompose + "/>"),
       "two <collision_mesh> elements for link 'block'"},
      {box_robot, "<collision_mesh link='block'>: the link has no mesh to decompose"},
      {uRobot(decompose + "/>", fine),
       "link 'block': mesh '" + fine +
           "': no convex decomposition: 5292 triangles to decompose in "
           "the URDF up to this mesh, over the limit of 5000 (simplify the mesh)"},
      {two_meshes,  // the U block's 36 and 4992: the limit is for all the URDF's meshes
       "link 'block': mesh '" + near + "': no convex decomposition: 5028 triangles to decompose"},
      {uRobot(decompose + " max_convex_hulls=\"1\"/>", apart),
       "link 'block': mesh '" + apart +
           "': no convex decomposition: HACD left 2 parts, more than "
           "max_convex_hulls 1 (pieces of the mesh too far apart to join)"},
  };
  for (const auto& c : cases) {
    try {
      parseCreatureModel(c.urdf);
      ADD_FAILURE() << "accepted; expected: " << c.message;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos)
          << e.what() << "\n  expected: " << c.message;
    }
  }
  // decomposeMesh's own limits, for a mesh alone.
  try {
    decomposeMesh(*readMeshFile(fine, Vec3::Ones()), 16);
    ADD_FAILURE() << "a mesh of 5292 triangles was decomposed";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(),
                 "5292 triangles, over the limit of 5000 for a convex decomposition (simplify the "
                 "mesh)");
  }
  // The two cubes join into one part each when two are allowed.
  const auto two = parseCreatureModel(uRobot(decompose + " max_convex_hulls=\"2\"/>", apart));
  EXPECT_EQ(two->links[0].meshes[0].parts->size(), 2u);
}

}  // namespace
}  // namespace flapsim
