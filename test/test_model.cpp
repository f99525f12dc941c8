// URDF -> CreatureModel: contents of the shipped creatures, the generator, and errors that
// name the file and the link or joint at fault.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/make_creature.h"
#include "fluid/surface.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::loadUrdf;
using test::sourcePath;

TEST(Model, PlateIsOneBoxOfTenGrams) {
  auto m = loadUrdf("plate.urdf");
  ASSERT_EQ(m->links.size(), 1u);
  EXPECT_EQ(m->name, "plate");
  EXPECT_DOUBLE_EQ(m->links[0].mass, 0.01);
  ASSERT_EQ(m->links[0].boxes.size(), 1u);
  EXPECT_TRUE(m->links[0].boxes[0].size.isApprox(Vec3(0.2, 0.2, 0.002)));
  EXPECT_EQ(m->links[0].aero.subdivisions_u, 4);
  EXPECT_TRUE(m->wing_joints.empty());
}

TEST(Model, FlapUnitHasTwoWingHinges) {
  auto m = loadUrdf("flap_unit.urdf");
  ASSERT_EQ(m->links.size(), 3u);
  EXPECT_EQ(m->links[0].name, "unit0_body");  // root first
  ASSERT_EQ(m->wing_joints.size(), 2u);
  const JointModel& left = m->joints[m->wing_joints[0]];
  const JointModel& right = m->joints[m->wing_joints[1]];
  EXPECT_EQ(left.name, "unit0_wing_left_joint");
  EXPECT_EQ(right.name, "unit0_wing_right_joint");
  EXPECT_EQ(left.type, JointType::kRevolute);
  EXPECT_TRUE(left.axis.isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(right.axis.isApprox(Vec3(-1, 0, 0)));
  EXPECT_DOUBLE_EQ(left.upper, 1.4);
  EXPECT_DOUBLE_EQ(left.effort, 8.0);  // one pair: kOnePairWingEffort
  EXPECT_NEAR(m->totalMass(), 0.023, 1e-12);
  EXPECT_TRUE(m->links[m->findLink("unit0_wing_left")].com.isApprox(Vec3(0, 0.175, 0)));
}

TEST(Model, BambooCopterBladesAreFixedAndTiltedOpposite) {
  auto m = loadUrdf("bamboo_copter.urdf");
  ASSERT_EQ(m->links.size(), 3u);
  const JointModel& l = m->joints[m->findJoint("blade_left_joint")];
  const JointModel& r = m->joints[m->findJoint("blade_right_joint")];
  EXPECT_EQ(l.type, JointType::kFixed);
  const Vec3 nl = l.origin.orientation * Vec3::UnitZ();
  const Vec3 nr = r.origin.orientation * Vec3::UnitZ();
  EXPECT_NEAR(nl.x(), std::sin(M_PI / 6), 1e-9);
  EXPECT_NEAR(nr.x(), -std::sin(M_PI / 6), 1e-9);
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Generator, ChainsOfUnitsLoad) {
  for (int n : {1, 4, 6, 12}) {
    auto m = parseCreatureModel(makeCreatureUrdf(n, "afc"));
    EXPECT_EQ(m->links.size(), 3u * n) << n;
    EXPECT_EQ(m->joints.size(), 3u * n - 1) << n;
    EXPECT_EQ(m->wing_joints.size(), 2u * n) << n;
    EXPECT_NEAR(m->totalMass(), 0.023 * n, 1e-12) << n;
    if (n > 1) {
      const JointModel& link = m->joints[m->findJoint("unit1_link_joint")];
      EXPECT_FALSE(link.wing);
      EXPECT_TRUE(link.axis.isApprox(Vec3::UnitX()));  // roll, the default
      EXPECT_GT(link.damping, 0.0);
      EXPECT_EQ(link.stiffness, 2.0);  // sprung, the default
    }
  }
  FlapUnitParams pitch;
  pitch.link_axis = linkAxisFromString("pitch");
  pitch.link_stiffness = 0.5;
  auto m = parseCreatureModel(makeCreatureUrdf(2, "afc", pitch));
  const JointModel& link = m->joints[m->findJoint("unit1_link_joint")];
  EXPECT_TRUE(link.axis.isApprox(Vec3::UnitY()));
  EXPECT_EQ(link.stiffness, 0.5);
  EXPECT_THROW(makeCreatureUrdf(0), std::invalid_argument);
  EXPECT_THROW(linkAxisFromString("yaw"), std::invalid_argument);
}

// One pair gets 8 N m hinge motors, every unit of a chain 2 N m, unless the effort is given.
TEST(Generator, WingEffortDefaultsByPairCountUnlessGiven) {
  FlapUnitParams given;
  given.wing_effort = 5.0;
  for (int pairs : {1, 4}) {
    const auto defaults = parseCreatureModel(makeCreatureUrdf(pairs, "d"));
    const auto set = parseCreatureModel(makeCreatureUrdf(pairs, "s", given));
    ASSERT_EQ(defaults->wing_joints.size(), 2u * pairs);
    for (int w : defaults->wing_joints) {
      EXPECT_DOUBLE_EQ(defaults->joints[w].effort, pairs == 1 ? 8.0 : 2.0) << pairs;
    }
    for (int w : set->wing_joints) EXPECT_DOUBLE_EQ(set->joints[w].effort, 5.0) << pairs;
  }
}

TEST(Generator, FeatheringWingsHangFromPitchJoints) {
  FlapUnitParams p;
  p.feathering = true;
  p.body_com_drop = 0.0;  // make_creature --feathering --com-drop 0
  auto m = parseCreatureModel(makeCreatureUrdf(2, "f", p));
  EXPECT_EQ(m->links.size(), 2u * 5u);  // body, 2 roots, 2 wings per unit
  ASSERT_EQ(m->wing_joints.size(), 4u);
  const JointModel& hinge = m->joints[m->wing_joints[1]];
  EXPECT_EQ(hinge.name, "unit0_wing_right_joint");
  ASSERT_GE(hinge.feather_joint, 0);
  EXPECT_EQ(m->joints[hinge.feather_joint].name, "unit0_wing_right_pitch");
  EXPECT_TRUE(m->joints[hinge.feather_joint].axis.isApprox(Vec3(0, -1, 0)));
  EXPECT_EQ(readFile(sourcePath("urdf/feather_unit.urdf")), makeCreatureUrdf(1, "feather_unit", p));
}

// The open-loop creatures (the paper's Fig. 5 unit, the swimmer, the feathering unit) carry
// no ballast; the controlled afc_<n> creatures carry the default 2 cm.
TEST(Generator, CommittedUrdfsAreItsOutput) {
  FlapUnitParams swimmer;
  swimmer.body_mass = 0.3;
  swimmer.wing_mass = 0.076;
  swimmer.wing_effort = 100;
  swimmer.body_com_drop = 0.0;
  EXPECT_EQ(readFile(sourcePath("urdf/swimmer.urdf")), makeCreatureUrdf(1, "swimmer", swimmer))
      << "make_creature --name swimmer --body-mass 0.3 --wing-mass 0.076 --wing-effort 100 "
         "--com-drop 0";
  FlapUnitParams unit;
  unit.body_com_drop = 0.0;
  EXPECT_EQ(readFile(sourcePath("urdf/flap_unit.urdf")), makeCreatureUrdf(1, "flap_unit", unit))
      << "make_creature --name flap_unit --com-drop 0";
  for (int n : {1, 4, 6, 12}) {
    EXPECT_EQ(readFile(sourcePath("urdf/afc_" + std::to_string(n) + ".urdf")),
              makeCreatureUrdf(n, "afc" + std::to_string(n)))
        << "regenerate with make_creature --pairs " << n;
  }
}

// ---- errors ---------------------------------------------------------------------------

const char* kLink = R"(
  <link name="body">
    <inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <link name="wing">
    <inertial><mass value="0.01"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
    <collision><geometry><box size="0.1 0.3 0.002"/></geometry></collision>
  </link>)";

std::string robot(const std::string& body) {
  return std::string("<robot name=\"r\">") + body + "</robot>";
}

std::string hinge(const std::string& name = "hinge", const std::string& type = "revolute",
                  const std::string& child = "wing") {
  return "<joint name=\"" + name + "\" type=\"" + type +
         "\"><parent link=\"body\"/><child link=\"" + child +
         "\"/><axis xyz=\"1 0 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
         "velocity=\"10\"/></joint>";
}

// Expects a ModelError whose message contains every one of `culprits`.
void expectError(const std::string& xml, std::initializer_list<std::string> culprits) {
  try {
    parseCreatureModel(xml, "test.urdf");
    ADD_FAILURE() << "no error for: " << xml;
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("test.urdf"), std::string::npos) << what;
    for (const auto& c : culprits) EXPECT_NE(what.find(c), std::string::npos) << what;
  }
}

// ---- span axes ---------------------------------------------------------------------------

// |dot| = 1: the span's sign does not matter to the air models.
void expectSpan(const std::optional<Vec3>& span, const Vec3& axis, const std::string& what) {
  ASSERT_TRUE(span.has_value()) << what;
  EXPECT_NEAR(span->norm(), 1.0, 1e-12) << what;
  EXPECT_NEAR(std::abs(span->dot(axis)), 1.0, 1e-12) << what;
}

// A flap-unit wing hinges about x at its root and reaches out along y to its COM: its span is
// y, and every face of its plate that contains y gets it (the tip faces keep their longer
// edge, x). The body hangs from no wing joint and names no span.
TEST(SpanAxis, FlapUnitWingsSpanTheirYAxis) {
  auto m = loadUrdf("flap_unit.urdf");
  for (const char* wing : {"unit0_wing_left", "unit0_wing_right"}) {
    expectSpan(spanAxis(*m, m->findLink(wing)), Vec3::UnitY(), wing);
    const AeroSurface s = linkAeroSurface(*m, m->findLink(wing), AirParams());
    ASSERT_EQ(s.faces.size(), 6u);
    for (const SurfaceFace& f : s.faces) {
      const Vec3 expected = std::abs(f.normal.y()) > 0.5 ? Vec3::UnitX() : Vec3::UnitY();
      EXPECT_NEAR(std::abs(f.span.dot(expected)), 1.0, 1e-12) << wing;
      EXPECT_NEAR(f.chord.dot(f.span), 0.0, 1e-12);
    }
    EXPECT_TRUE(s.pitch_axis_point.isZero(0.0));  // no feather joint: the COM
  }
  EXPECT_FALSE(spanAxis(*m, m->findLink("unit0_body")).has_value());
}

// A feathering wing hangs from its pitch joint: the span is that joint's axis (y), and the
// wing pitches about the joint's line through the link origin, 0.175 m from its COM.
TEST(SpanAxis, FeatheringWingSpansItsPitchAxis) {
  auto m = loadUrdf("feather_unit.urdf");
  const int wing = m->findLink("unit0_wing_left");
  expectSpan(spanAxis(*m, wing), Vec3::UnitY(), "feathering wing");
  EXPECT_TRUE(linkAeroSurface(*m, wing, AirParams()).pitch_axis_point.isApprox(Vec3(0, -0.175, 0)));
  // The root cube's COM is on the flapping axis: no direction out to it.
  EXPECT_FALSE(spanAxis(*m, m->findLink("unit0_wing_left_root")).has_value());
}

TEST(SpanAxis, AeroSpanAttributeNamesALinkAxis) {
  const std::string tail = R"(<aero link="body" span="z"/>)";
  auto m = parseCreatureModel(robot(std::string(kLink) + hinge("hinge", "fixed") + tail));
  expectSpan(spanAxis(*m, m->findLink("body")), Vec3::UnitZ(), "body");
  EXPECT_FALSE(spanAxis(*m, m->findLink("wing")).has_value());
  expectError(robot(std::string(kLink) + hinge() + R"(<aero link="wing" span="w"/>)"),
              {"wing", "span", "'w'"});
}

TEST(ModelErrors, ValidReferenceParses) {
  auto m = parseCreatureModel(robot(std::string(kLink) + hinge() + "<wing joint=\"hinge\"/>"));
  EXPECT_EQ(m->wing_joints.size(), 1u);
}

// Boxes, cylinders, spheres and meshes collide and feel the air, from a link's collisions (its
// visuals if it has no collision); a link simulating its visuals is named.
TEST(Geometry, CylindersSpheresAndMeshesAreShapes) {
  const auto m =
      flapsim::parseCreatureModel(R"(<robot name="s">
    <link name="a"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <visual><geometry><sphere radius="0.1"/></geometry></visual>
      <collision><origin xyz="0 0 0.5"/><geometry><cylinder radius="0.1" length="0.2"/></geometry></collision>
      <collision><geometry><mesh filename=")" FLAPSIM_SOURCE_DIR
                                  R"(/test/meshes/cube.dae"/></geometry></collision></link>
    <link name="b"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <visual><geometry><sphere radius="0.3"/></geometry></visual></link>
    <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>)");
  ASSERT_EQ(m->links[0].rounds.size(), 1u);  // its visual sphere is drawn, not simulated
  ASSERT_EQ(m->links[0].meshes.size(), 1u);
  EXPECT_EQ(m->links[0].meshes[0].mesh->triangles.size(), 12u);
  const flapsim::RoundShape& c = m->links[0].rounds[0];
  EXPECT_EQ(c.kind, flapsim::RoundShape::Kind::kCylinder);
  EXPECT_EQ(c.radius, 0.1);
  EXPECT_EQ(c.length, 0.2);
  EXPECT_EQ(c.origin.position.z(), 0.5);
  ASSERT_EQ(m->links[1].rounds.size(), 1u);  // no collision: its visual sphere
  EXPECT_EQ(m->links[1].rounds[0].kind, flapsim::RoundShape::Kind::kSphere);
  EXPECT_EQ(m->links[1].rounds[0].radius, 0.3);
  EXPECT_EQ(
      flapsim::geometryNotes(*m),
      (std::vector<std::string>{
          "link 'b' has no <collision>: its <visual> shapes are simulated (contact and air)"}));
  // The lowest point: the sphere's bottom with b 1 m up (the cube's is at 0.95), the cylinder's
  // cap with a turned 90 degrees about x (the cylinder then lies along y, its side 0.1 below
  // its axis; the cube's 0.05).
  const flapsim::Pose up{flapsim::Vec3(0, 0, 1), flapsim::Quat::Identity()};
  EXPECT_NEAR(flapsim::lowestBoxPoint(*m, {up, up}), 0.7, 1e-12);
  const flapsim::Pose turned{flapsim::Vec3::Zero(),
                             flapsim::Quat(Eigen::AngleAxisd(M_PI / 2, flapsim::Vec3::UnitX()))};
  EXPECT_NEAR(flapsim::lowestBoxPoint(*m, {turned, up}), -0.1, 1e-12);
  EXPECT_TRUE(flapsim::geometryNotes(
                  *flapsim::loadCreatureModel(std::string(FLAPSIM_SOURCE_DIR) + "/urdf/afc_4.urdf"))
                  .empty());
}

// A cylinder or sphere with a zero or negative radius or a NaN length is refused, naming the
// link and the value.
TEST(ModelErrors, BadRoundShapesNameTheLink) {
  const std::string head = R"(<robot name="r"><link name="ball"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial><collision><geometry>)";
  const std::string tail = "</geometry></collision></link></robot>";
  expectError(head + R"(<sphere radius="0"/>)" + tail, {"link 'ball'", "radius"});
  expectError(head + R"(<sphere radius="-0.1"/>)" + tail, {"link 'ball'", "radius"});
  expectError(head + R"(<cylinder radius="0.1" length="nan"/>)" + tail, {"link 'ball'", "length"});
  expectError(head + R"(<cylinder radius="-1" length="0.1"/>)" + tail, {"link 'ball'", "radius"});
  expectError(head + R"(<cylinder radius="0.1" length="2000"/>)" + tail, {"link 'ball'", "length"});
}

// An element urdfdom cannot read is dropped by it with a message on the console and the rest
// parsed: refused instead, naming the link and the element, so no spawned creature differs
// from its file.
TEST(ModelErrors, ElementsTheUrdfParserDropsAreRefusedNamingTheLink) {
  const std::string head = R"(<robot name="r"><link name="wing"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision><collision><geometry>)";
  const std::string tail = "</geometry></collision></link></robot>";
  expectError(head + "<sphere/>" + tail, {"collision element for Link [wing]", "radius"});
  expectError(head + R"(<cylinder radius="0.1"/>)" + tail,
              {"collision element for Link [wing]", "length"});
  expectError(head + R"(<mesh filename="w.stl" scale="a b c"/>)" + tail,
              {"collision element for Link [wing]", "scale"});
  const std::string visual = R"(<robot name="r"><link name="body"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <visual><geometry><sphere/></geometry></visual></link></robot>)";
  expectError(visual, {"visual element for Link [body]"});
}

// A link of kMaxShapesPerLink boxes is read; one more is refused naming the link, the count
// and the limit. Likewise the pairs of boxes overlapping at odd angles.
TEST(ModelErrors, ShapesPerLinkAndTurnedOverlapsBeyondTheirLimitsAreRefused) {
  auto link = [](int boxes, double turn) {
    std::string xml = R"(<robot name="r"><link name="pile"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)";
    for (int k = 0; k < boxes; ++k) {
      xml += "<collision><origin xyz=\"" + std::to_string(0.01 * k) + " 0 0\" rpy=\"0 0 " +
             std::to_string(turn * k) + "\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry>" +
             "</collision>";
    }
    return xml + "</link></robot>";
  };
  EXPECT_EQ(parseCreatureModel(link(kMaxShapesPerLink, 0.0))->links[0].boxes.size(),
            static_cast<size_t>(kMaxShapesPerLink));
  expectError(link(kMaxShapesPerLink + 1, 0.0),
              {"link 'pile' has 257 shapes", "over the limit of 256 per link"});
  // 10 cm cubes 1 cm apart, each turned 0.1 rad more about z: a pair counts when their
  // bounds, 0.05 (|cos t| + |sin t|) either side of each centre, share length along x.
  auto pairs = [](int boxes) {
    int n = 0;
    for (int i = 0; i < boxes; ++i) {
      for (int j = i + 1; j < boxes; ++j) {
        const double wi = 0.05 * (std::abs(std::cos(0.1 * i)) + std::abs(std::sin(0.1 * i)));
        const double wj = 0.05 * (std::abs(std::cos(0.1 * j)) + std::abs(std::sin(0.1 * j)));
        n += 0.01 * (j - i) < wi + wj - 1e-9;
      }
    }
    return n;
  };
  ASSERT_LE(pairs(24), kMaxTurnedOverlaps);
  ASSERT_GT(pairs(32), kMaxTurnedOverlaps);
  EXPECT_EQ(parseCreatureModel(link(24, 0.1))->links[0].boxes.size(), 24u);
  expectError(link(32, 0.1), {"link 'pile': " + std::to_string(pairs(32)) + " pairs",
                              "over the limit of 256 per link"});
}

TEST(ModelErrors, NameTheCulprit) {
  expectError("<robot name=\"r\"><link name=\"a\">", {"malformed XML"});
  expectError("<notarobot/>", {"<robot>"});
  expectError(robot(std::string(kLink) + hinge("hinge", "revolute", "ghost")), {"ghost"});
  expectError(robot(std::string(kLink) + hinge("spin", "floating")), {"spin"});
  expectError(robot(std::string(kLink) + hinge() + "<wing joint=\"elbow\"/>"), {"elbow"});
  expectError(robot(std::string(kLink) + hinge("hinge", "fixed") + "<wing joint=\"hinge\"/>"),
              {"hinge", "revolute"});
  expectError(robot(std::string(kLink) + hinge() + "<aero link=\"tail\"/>"), {"tail"});
  expectError(
      robot(std::string(kLink) + hinge() + "<wing joint=\"hinge\" feather_joint=\"flip\"/>"),
      {"hinge", "flip"});
  expectError(robot(std::string(kLink) + hinge() + "<aero link=\"wing\" model=\"cfd\"/>"),
              {"wing", "cfd"});
  expectError(robot(std::string(kLink) + hinge() + "<aero link=\"wing\" subdivisions=\"4\"/>"),
              {"wing", "subdivisions"});
  expectError(
      robot(std::string(kLink) + hinge() + "<aero link=\"wing\" drag_coefficient=\"abc\"/>"),
      {"wing", "drag_coefficient"});
  expectError(robot(std::string(kLink) + hinge() + "<aero link=\"wing\" enabled=\"maybe\"/>"),
              {"wing", "enabled"});
  expectError(robot(R"(<link name="massless"/>)"), {"massless", "mass"});
  expectError(
      robot(
          R"(<link name="tilted"><inertial><mass value="1"/><inertia ixx="1" ixy="1.5" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>)"),
      {"tilted", "not positive definite"});
}

// <spring joint stiffness reference>: on a passive or a wing joint (in parallel with its
// motor); refused by name on an unknown or a fixed joint, twice on one joint, without a
// stiffness or with a negative one.
TEST(Spring, SetsAJointsStiffnessAndIsRefusedByName) {
  auto m = parseCreatureModel(robot(std::string(kLink) + hinge() +
                                    R"(<spring joint="hinge" stiffness="0.5" reference="0.1"/>)"));
  const JointModel& j = m->joints[m->findJoint("hinge")];
  EXPECT_EQ(j.stiffness, 0.5);
  EXPECT_EQ(j.reference, 0.1);
  expectError(robot(std::string(kLink) + hinge() + R"(<spring joint="elbow" stiffness="1"/>)"),
              {"elbow"});
  expectError(robot(std::string(kLink) + hinge("hinge", "fixed") +
                    R"(<spring joint="hinge" stiffness="1"/>)"),
              {"hinge", "fixed"});
  auto wing =
      parseCreatureModel(robot(std::string(kLink) + hinge() +
                               R"(<wing joint="hinge"/><spring joint="hinge" stiffness="1"/>)"));
  EXPECT_EQ(wing->joints[0].stiffness, 1.0);
  EXPECT_TRUE(wing->joints[0].wing);
  expectError(
      robot(std::string(kLink) + hinge() +
            R"(<spring joint="hinge" stiffness="1"/><spring joint="hinge" stiffness="2"/>)"),
      {"hinge", "two"});
  expectError(robot(std::string(kLink) + hinge() + R"(<spring joint="hinge"/>)"),
              {"hinge", "stiffness"});
  expectError(robot(std::string(kLink) + hinge() + R"(<spring joint="hinge" stiffness="-1"/>)"),
              {"hinge", "stiffness"});
}

// <motor joint stall_torque no_load_speed max_power>: the stall torque and no-load speed
// default to the joint's <limit effort velocity>; without the element, no motor (the flat
// effort limit). Refused by name: an unknown or fixed joint, two on a joint, a negative value,
// no stall torque at all.
TEST(Motor, ReadsItsLineFromTheLimitUnlessGiven) {
  auto plain = parseCreatureModel(robot(std::string(kLink) + hinge()));
  EXPECT_FALSE(plain->joints[0].motor.has_value());
  auto from_limit =
      parseCreatureModel(robot(std::string(kLink) + hinge() + R"(<motor joint="hinge"/>)"));
  ASSERT_TRUE(from_limit->joints[0].motor.has_value());
  EXPECT_EQ(from_limit->joints[0].motor->stall_torque, 1.0);
  EXPECT_EQ(from_limit->joints[0].motor->no_load_speed, 10.0);
  EXPECT_EQ(from_limit->joints[0].motor->max_power, 0.0);
  auto given = parseCreatureModel(
      robot(std::string(kLink) + hinge() +
            R"(<motor joint="hinge" stall_torque="0.2" no_load_speed="300" max_power="4"/>)"));
  EXPECT_EQ(given->joints[0].motor->stall_torque, 0.2);
  EXPECT_EQ(given->joints[0].motor->no_load_speed, 300.0);
  EXPECT_EQ(given->joints[0].motor->max_power, 4.0);
  expectError(robot(std::string(kLink) + hinge() + R"(<motor joint="elbow"/>)"), {"elbow"});
  expectError(robot(std::string(kLink) + hinge("hinge", "fixed") + R"(<motor joint="hinge"/>)"),
              {"hinge", "fixed"});
  expectError(
      robot(std::string(kLink) + hinge() + R"(<motor joint="hinge"/><motor joint="hinge"/>)"),
      {"hinge", "two"});
  expectError(robot(std::string(kLink) + hinge() + R"(<motor joint="hinge" max_power="-1"/>)"),
              {"hinge", "max_power"});
  expectError(robot(std::string(kLink) + hinge() + R"(<motor joint="hinge" stall_torque="0"/>)"),
              {"hinge", "stall_torque"});
  expectError(robot(std::string(kLink) + hinge() + R"(<motor/>)"), {"<motor>", "joint"});
}

TEST(ModelErrors, MissingFileIsNamed) {
  try {
    loadCreatureModel("/nonexistent/creature.urdf");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/creature.urdf"), std::string::npos);
  }
}

// The one forward kinematics of a joint (JointModel::childPose) against the arithmetic tf
// (urdfJointPose) and unitSensing had before they shared it: equal to the bit, on every joint
// of the shipped creatures, so neither /tf nor the evolved controllers' inputs moved.
TEST(Model, ChildPoseGivesTheFormerTfAndSensingArithmeticToTheBit) {
  const Quat parents[] = {Quat::Identity(),
                          Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized())),
                          Quat(Eigen::AngleAxisd(-2.5, Vec3(0, 1, 0)))};
  int joints = 0;
  for (const char* file : {"afc_4.urdf", "afc_12.urdf", "feather_unit.urdf", "bamboo_copter.urdf",
                           "hover_1.urdf", "swimmer.urdf", "flap_unit.urdf"}) {
    const CreatureModelPtr m = loadUrdf(file);
    for (const JointModel& j : m->joints) {
      ++joints;
      for (double q : {-0.7, 0.0, 0.3, 1.1}) {
        // urdfJointPose as it was written before childPose.
        Pose motion;
        if (j.type == JointType::kPrismatic) {
          motion.position = q * j.axis;
        } else if (j.movable()) {
          motion.orientation = Quat(Eigen::AngleAxisd(q, j.axis));
        }
        Pose before = j.movable() ? j.origin * motion : j.origin;
        const LinkModel& parent = m->links.at(j.parent_link);
        if (parent.rotated()) before = parent.urdf_frame.inverse() * before;
        before = m->links.at(j.child_link).toUrdf(before);
        const Pose now = urdfJointPose(*m, j, q);
        EXPECT_EQ(now.position, before.position) << file << " " << j.name << " " << q;
        EXPECT_EQ(now.orientation.coeffs(), before.orientation.coeffs()) << file << " " << j.name;
        // unitSensing's step from a parent's orientation, as it was written.
        for (const Quat& r0 : parents) {
          Quat r = r0 * j.origin.orientation;
          if (j.type == JointType::kRevolute || j.type == JointType::kContinuous) {
            r = r * Quat(Eigen::AngleAxisd(q, j.axis));
          }
          const Quat sensed = j.childPose(q, Pose{Vec3::Zero(), r0}).orientation;
          EXPECT_EQ(sensed.coeffs(), r.coeffs()) << file << " " << j.name << " " << q;
        }
      }
    }
  }
  EXPECT_GT(joints, 40);
}

TEST(Model, ChildPoseOfAPrismaticJointSlidesAlongItsAxisAfterTheOrigin) {
  JointModel j;
  j.type = JointType::kPrismatic;
  j.origin = Pose{Vec3(0.1, -0.2, 0.3), Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ()))};
  j.axis = Vec3::UnitX();
  const Pose parent{Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(-0.3, Vec3::UnitY()))};
  const Pose child = j.childPose(0.25, parent);
  const Pose expect = parent * j.origin * Pose{Vec3(0.25, 0, 0), Quat::Identity()};
  EXPECT_LT((child.position - expect.position).norm(), 1e-15);
  EXPECT_LT(child.orientation.angularDistance(expect.orientation), 1e-15);
  // Moved 0.25 m along the origin's x, which the origin turned 0.5 rad about z.
  EXPECT_NEAR((child.position - parent.apply(j.origin.position)).norm(), 0.25, 1e-15);
}

}  // namespace
}  // namespace flapsim
