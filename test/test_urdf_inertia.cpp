// The URDF a robot has: full inertia tensors and rotated <inertial> origins (the link frame
// becomes the principal frame inside, users keep seeing URDF frames), and massless links on
// fixed joints lumped into the link they are fixed to (a CAD model's base_link).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "flapsim/creature_model.h"
#include "flapsim/world.h"
#include "test_util.h"

using namespace flapsim;

namespace {

// One link of the flap unit (urdf/flap_unit.urdf), in its principal frame.
struct LinkSpec {
  std::string name;
  double mass;
  Vec3 com, moments, box_size, box_at;
};

const LinkSpec kBody{
    "body",      0.015, Vec3::Zero(), Vec3(5.625e-06, 9.125e-06, 1.25e-05), Vec3(0.08, 0.06, 0.03),
    Vec3::Zero()};
const LinkSpec kLeft{"wing_left",
                     0.004,
                     Vec3(0, 0.175, 0),
                     Vec3(4.083466667e-05, 1.613466667e-05, 5.696666667e-05),
                     Vec3(0.22, 0.35, 0.002),
                     Vec3(0, 0.175, 0)};
const LinkSpec kRight{"wing_right",  kLeft.mass,     -kLeft.com,
                      kLeft.moments, kLeft.box_size, -kLeft.box_at};

std::string num(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

std::string triple(const Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

// URDF's rpy (fixed axes X, Y, Z) of `q`.
Vec3 rpy(const Quat& q) {
  const Vec3 ypr = q.toRotationMatrix().eulerAngles(2, 1, 0);
  return Vec3(ypr[2], ypr[1], ypr[0]);
}

std::string origin(const Pose& p) {
  return "<origin xyz=\"" + triple(p.position) + "\" rpy=\"" + triple(rpy(p.orientation)) + "\"/>";
}

Pose turn(const Quat& q) { return Pose{Vec3::Zero(), q}; }

// `l` with its URDF frame turned by `q` (the principal frame seen from it: q^-1): the inertia
// as a full tensor (`tensor`) or as its moments in a rotated <inertial><origin>.
std::string linkXml(const LinkSpec& l, const Quat& q, bool tensor) {
  const Pose to_new = turn(q.conjugate());  // principal frame -> the turned URDF frame
  std::string inertia;
  Pose inertial{to_new.apply(l.com), tensor ? Quat::Identity() : q.conjugate()};
  Mat3 i = l.moments.asDiagonal();
  if (tensor) {
    const Mat3 r = q.toRotationMatrix();
    i = r.transpose() * i * r;
  }
  std::ostringstream x;
  x << "<link name=\"" << l.name << "\"><inertial>" << origin(inertial) << "<mass value=\""
    << num(l.mass) << "\"/><inertia ixx=\"" << num(i(0, 0)) << "\" ixy=\"" << num(i(0, 1))
    << "\" ixz=\"" << num(i(0, 2)) << "\" iyy=\"" << num(i(1, 1)) << "\" iyz=\"" << num(i(1, 2))
    << "\" izz=\"" << num(i(2, 2)) << "\"/></inertial><collision>"
    << origin(to_new * Pose{l.box_at, Quat::Identity()}) << "<geometry><box size=\""
    << triple(l.box_size) << "\"/></geometry></collision></link>";
  return x.str();
}

// A wing joint from the body (turned by qp) to a wing (turned by qc).
std::string wingJoint(const std::string& wing, double y, double axis, const Quat& qp,
                      const Quat& qc) {
  const Pose o = turn(qp.conjugate()) * Pose{Vec3(0, y, 0), Quat::Identity()} * turn(qc);
  return "<joint name=\"" + wing +
         "_joint\" type=\"revolute\"><parent link=\"body\"/><child link=\"" + wing + "\"/>" +
         origin(o) + "<axis xyz=\"" + triple(qc.conjugate() * Vec3(axis, 0, 0)) +
         "\"/><limit lower=\"-1.4\" upper=\"1.4\" effort=\"8\" velocity=\"200\"/></joint>";
}

// The flap unit with its links' URDF frames turned by q[0] (body, full tensor), q[1], q[2]
// (wings, rotated <inertial><origin>).
std::string flapUnit(const Quat (&q)[3]) {
  return "<robot name=\"u\">" + linkXml(kBody, q[0], true) + linkXml(kLeft, q[1], false) +
         linkXml(kRight, q[2], false) + wingJoint("wing_left", 0.03, 1, q[0], q[1]) +
         wingJoint("wing_right", -0.03, -1, q[0], q[2]) +
         "<wing joint=\"wing_left_joint\"/><wing joint=\"wing_right_joint\"/></robot>";
}

Quat fromRpy(double r, double p, double y) {
  return poseFromXyzRpy(Vec3::Zero(), Vec3(r, p, y)).orientation;
}

double angle(const Quat& a, const Quat& b) { return a.angularDistance(b); }

// Largest difference of position (m) or angle (rad) between two poses.
double poseError(const Pose& a, const Pose& b) {
  return std::max((a.position - b.position).norm(), angle(a.orientation, b.orientation));
}

const Quat kIdentity[3] = {Quat::Identity(), Quat::Identity(), Quat::Identity()};
const Quat kTurned[3] = {fromRpy(0.3, -0.5, 1.1), fromRpy(-0.7, 0.2, 2.5), fromRpy(1.3, 0.9, -0.4)};
const Pose kStart = test::at(0.1, -0.2, 5.0, fromRpy(0.05, -0.1, 0.2));
constexpr double kBound = 1e-9;  // m and rad

// Flaps `world`'s creatures for 1 s (1000 steps) at the same stroke.
void flap(World& world, const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    world.setWingCommands(n, {}, {StrokeCommand{30, 10, 0.8}, StrokeCommand{30, 10, 0.8}});
  }
  world.step(1000);
}

}  // namespace

// The principal decomposition: the turned body's moments are the plain one's, each link frame
// is turned from its URDF frame, and the plain file's frames are its URDF frames exactly.
TEST(UrdfInertia, ATurnedTensorHasThePlainMoments) {
  const auto plain = parseCreatureModel(flapUnit(kIdentity));
  const auto turned = parseCreatureModel(flapUnit(kTurned));
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_FALSE(plain->links[k].rotated());
    EXPECT_TRUE(turned->links[k].rotated()) << k;
    Vec3 a = plain->links[k].inertia, b = turned->links[k].inertia;
    std::sort(a.data(), a.data() + 3);
    std::sort(b.data(), b.data() + 3);
    EXPECT_LT((a - b).norm(), 1e-15 * a.norm()) << k;
    // The COM in the URDF frame is the file's.
    const Vec3 com = Quat(kTurned[k]).conjugate() * plain->links[k].com;
    EXPECT_LT((turned->links[k].urdfCom() - com).norm(), 1e-15) << k;
  }
}

// The same creature written with its link frames turned flies as the plain one: root pose
// and wing angles after 1 s of flapping in air (gravity on) within 1e-9; each file's reported
// link poses are its own URDF frames. Measured: 7e-15 m/rad.
TEST(UrdfInertia, TurnedLinkFramesFlyAsThePlainOnes) {
  const auto plain = parseCreatureModel(flapUnit(kIdentity));
  const auto turned = parseCreatureModel(flapUnit(kTurned));
  World world(test::openSky());
  world.spawn("plain", plain, kStart);
  world.spawn("turned", turned, kStart * turn(kTurned[0]));
  flap(world, {"plain", "turned"});
  const CreatureState p = world.state("plain"), t = world.state("turned");
  ASSERT_GT((p.link_poses[0].position - kStart.position).norm(), 0.05);  // it flew
  ASSERT_GT(std::abs(p.joint_positions[0]), 0.05);
  double worst =
      poseError(world.rootPose("turned") * turn(kTurned[0].conjugate()), world.rootPose("plain"));
  for (size_t j = 0; j < 2; ++j) {
    worst = std::max(worst, std::abs(p.joint_positions[j] - t.joint_positions[j]));
  }
  for (size_t k = 0; k < 3; ++k) {
    worst = std::max(worst, poseError(t.link_poses[k], p.link_poses[k] * turn(kTurned[k])));
  }
  std::cout << "turned vs plain after 1 s: " << worst << " m/rad\n";
  EXPECT_LT(worst, kBound);
  // The turned left wing in the turned body's frame: the file's joint origin, then the angle
  // about the file's axis.
  const Pose o = turn(kTurned[0].conjugate()) * test::at(0, 0.03, 0) * turn(kTurned[1]);
  const Vec3 axis = kTurned[1].conjugate() * Vec3::UnitX();
  const Pose expect = o * Pose{Vec3::Zero(), Quat(Eigen::AngleAxisd(t.joint_positions[0], axis))};
  EXPECT_LT(poseError(t.link_poses[0].inverse() * t.link_poses[1], expect), 1e-12);
  EXPECT_LT(poseError(urdfJointPose(*turned, turned->joints[0], t.joint_positions[0]), expect),
            1e-12);
}

namespace {

const Pose kBodyInBase = test::at(0.01, 0.02, -0.03, fromRpy(0.1, 0.2, 0.3));
const Pose kImuInBody = test::at(0.02, 0.0, 0.01, fromRpy(0.0, 0.0, 1.5));
const Pose kTipInWing = test::at(0.0, 0.35, 0.0);

std::string fixedJoint(const std::string& name, const std::string& parent, const std::string& child,
                       const Pose& o) {
  return "<joint name=\"" + name + "\" type=\"fixed\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/>" + origin(o) + "</joint>";
}

// The flap unit as CAD exports it: a massless base_link root carrying the body's box, fixed
// to the body; a massless imu_link on the body and tip on the left wing, frames only.
std::string cadUnit() {
  std::string body = linkXml(kBody, Quat::Identity(), false);
  body.erase(body.find("<collision>"), body.find("</link>") - body.find("<collision>"));
  const std::string base = "<link name=\"base_link\"><collision>" + origin(kBodyInBase) +
                           "<geometry><box size=\"" + triple(kBody.box_size) +
                           "\"/></geometry></collision></link>";
  return "<robot name=\"u\">" + base + body + linkXml(kLeft, Quat::Identity(), false) +
         linkXml(kRight, Quat::Identity(), false) +
         "<link name=\"imu_link\"/><link name=\"tip\"/>" +
         fixedJoint("base_joint", "base_link", "body", kBodyInBase) +
         wingJoint("wing_left", 0.03, 1, Quat::Identity(), Quat::Identity()) +
         wingJoint("wing_right", -0.03, -1, Quat::Identity(), Quat::Identity()) +
         fixedJoint("imu_joint", "body", "imu_link", kImuInBody) +
         fixedJoint("tip_joint", "wing_left", "tip", kTipInWing) +
         "<wing joint=\"wing_left_joint\"/><wing joint=\"wing_right_joint\"/></robot>";
}

Pose frameAt(const CreatureModel& m, const CreatureState& s, const std::string& name) {
  Pose p;
  EXPECT_TRUE(frameMotion(m, s, name, &p, nullptr)) << name;
  return p;
}

}  // namespace

// The massless links are lumped: the body is the root, base_link's box is the body's, the
// lumped links are frames fixed where the file puts them.
TEST(UrdfLumping, ACadBaseLinkIsLumpedIntoTheBody) {
  const auto m = parseCreatureModel(cadUnit());
  ASSERT_EQ(m->links.size(), 3u);
  EXPECT_EQ(m->links[0].name, "body");
  EXPECT_EQ(m->joints.size(), 2u);
  EXPECT_EQ(m->wing_joints, (std::vector<int>{0, 1}));
  ASSERT_EQ(m->links[0].boxes.size(), 1u);
  EXPECT_LT(poseError(m->links[0].boxes[0].origin, Pose()), 1e-15);
  ASSERT_EQ(m->lumped.size(), 3u);
  EXPECT_EQ(m->lumped[0].name, "base_link");
  EXPECT_LT(poseError(m->lumped[0].pose, kBodyInBase.inverse()), 1e-15);
  const FrameOnLink tip = m->findFrame("tip");
  EXPECT_EQ(tip.link, m->findLink("wing_left"));
  EXPECT_LT(poseError(tip.pose, kTipInWing), 1e-15);
  EXPECT_EQ(m->findFrame("nothing").link, -1);
}

// It flies as the same creature with the body as root (1 s of flapping in air: root pose and
// wing angles within 1e-9; measured 0), and its lumped frames move with their links.
TEST(UrdfLumping, ACadUnitFliesAsThePlainOne) {
  const auto cad = parseCreatureModel(cadUnit());
  World world(test::openSky());
  world.spawn("plain", parseCreatureModel(flapUnit(kIdentity)), kStart);
  world.spawn("cad", cad, kStart * kBodyInBase.inverse());  // base_link's frame: body at kStart
  flap(world, {"plain", "cad"});
  const CreatureState p = world.state("plain"), c = world.state("cad");
  ASSERT_GT((p.link_poses[0].position - kStart.position).norm(), 0.05);
  double worst = poseError(c.link_poses[0], p.link_poses[0]);
  for (size_t j = 0; j < 2; ++j) {
    worst = std::max(worst, std::abs(p.joint_positions[j] - c.joint_positions[j]));
  }
  std::cout << "CAD vs plain after 1 s: " << worst << " m/rad\n";
  EXPECT_LT(worst, kBound);
  EXPECT_LT(poseError(frameAt(*cad, c, "base_link"), c.link_poses[0] * kBodyInBase.inverse()),
            1e-12);
  EXPECT_LT(poseError(frameAt(*cad, c, "imu_link"), c.link_poses[0] * kImuInBody), 1e-12);
  EXPECT_LT(poseError(frameAt(*cad, c, "tip"), c.link_poses[1] * kTipInWing), 1e-12);
  Twist tip;
  ASSERT_TRUE(frameMotion(*cad, c, "tip", nullptr, &tip));
  const Vec3 arm = frameAt(*cad, c, "tip").position - c.link_poses[1].position;
  EXPECT_LT((tip.linear - c.link_twists[1].linear - c.link_twists[1].angular.cross(arm)).norm(),
            1e-12);
}

// The spawn pose is the URDF root's frame, as Gazebo's model frame, also when the root is a
// massless base_link lumped into the body; the spawn twist is that frame origin's.
TEST(UrdfLumping, TheSpawnPoseIsTheMasslessRootsFrame) {
  const auto cad = parseCreatureModel(cadUnit());
  World world(test::vacuum());
  Twist twist;
  twist.linear = Vec3(0.1, 0.2, 0.3);
  twist.angular = Vec3(0.5, -1.0, 2.0);
  const Pose at = test::at(1, 2, 3, fromRpy(0.4, -0.2, 0.9));
  world.spawn("cad", cad, at, twist);
  const CreatureState s = world.state("cad");
  EXPECT_LT(poseError(frameAt(*cad, s, "base_link"), at), 1e-12);
  EXPECT_LT(poseError(s.link_poses[0], at * kBodyInBase), 1e-12);
  const Vec3 body = twist.linear + twist.angular.cross(s.link_poses[0].position - at.position);
  EXPECT_LT((s.link_twists[0].linear - body).norm(), 1e-12);
  EXPECT_LT((s.link_twists[0].angular - twist.angular).norm(), 1e-12);
}

// setState and applyWrench take a lumped link's name: base_link placed at a pose puts the
// body at pose * (body in base_link); a wrench on imu_link acts on the body.
TEST(UrdfLumping, StateAndWrenchesNameLumpedLinks) {
  const auto cad = parseCreatureModel(cadUnit());
  World world(test::vacuum());
  world.spawn("cad", cad, Pose());
  StateRequest r;
  r.link = "base_link";
  r.pose = test::at(1, 2, 3, fromRpy(0.4, -0.2, 0.9));
  r.twist.angular = Vec3(0, 0, 2);
  world.setState("cad", r);
  const CreatureState s = world.state("cad");
  EXPECT_LT(poseError(s.link_poses[0], r.pose * kBodyInBase), 1e-12);
  EXPECT_LT(poseError(frameAt(*cad, s, "base_link"), r.pose), 1e-12);
  const Vec3 body_velocity = r.twist.angular.cross(s.link_poses[0].position - r.pose.position);
  EXPECT_LT((s.link_twists[0].linear - body_velocity).norm(), 1e-12);
  ExternalWrench w;
  w.link = "imu_link";
  w.force = Vec3(0, 0, 1);
  w.point = frameAt(*cad, s, "imu_link").position;
  world.applyWrench("cad", w);
  EXPECT_EQ(world.wrenchCount("cad"), 1);
  EXPECT_EQ(world.clearWrenches("cad", "imu_link"), 1);
  r.link = "no_such_link";
  try {
    world.setState("cad", r);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_link"), std::string::npos) << e.what();
  }
}

namespace {

std::string oneLink(const std::string& inertia) {
  return "<robot name=\"r\"><link name=\"lump\"><inertial><mass value=\"1\"/><inertia " + inertia +
         "/></inertial></link></robot>";
}

// The ModelError parsing `urdf` gives ("" if none).
std::string refusal(const std::string& urdf) {
  try {
    parseCreatureModel(urdf, "t.urdf");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

void expectRefusal(const std::string& urdf, const std::vector<std::string>& parts) {
  const std::string err = refusal(urdf);
  ASSERT_FALSE(err.empty()) << "accepted: " << urdf;
  for (const std::string& p : parts) EXPECT_NE(err.find(p), std::string::npos) << err;
}

}  // namespace

// Refused by name: a tensor that is not positive definite, one whose principal moments break
// the triangle inequality (as given, and turned), NaN, a massless link moving on a joint, a
// massless root with nothing with mass fixed to it, <aero> on a lumped link.
TEST(UrdfInertia, BadTensorsAndMasslessMovingLinksAreRefusedByName) {
  EXPECT_EQ(refusal(oneLink(R"(ixx="1" ixy="0.3" ixz="0" iyy="1" iyz="0" izz="1")")), "");
  expectRefusal(oneLink(R"(ixx="1" ixy="1.5" ixz="0" iyy="1" iyz="0" izz="1")"),
                {"t.urdf", "link 'lump'", "not positive definite", "-0.5"});
  expectRefusal(oneLink(R"(ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="0")"),
                {"link 'lump'", "not positive definite"});
  expectRefusal(oneLink(R"(ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="2.1")"),
                {"link 'lump'", "triangle inequality"});
  EXPECT_EQ(refusal(oneLink(R"(ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="2")")), "");  // a plate
  // Moments 1, 1, 2.5 turned 45 degrees about y: off-diagonal, still not a body's.
  expectRefusal(oneLink(R"(ixx="1.75" ixy="0" ixz="0.75" iyy="1" iyz="0" izz="1.75")"),
                {"link 'lump'", "triangle inequality"});
  expectRefusal(oneLink(R"(ixx="1" ixy="nan" ixz="0" iyy="1" iyz="0" izz="1")"),
                {"link 'lump'", "ixy='nan'"});
  std::string moving = cadUnit();
  const size_t wing = moving.find("<inertial>", moving.find("name=\"wing_left\""));
  moving.erase(wing, moving.find("</inertial>", wing) + 11 - wing);
  expectRefusal(moving, {"link 'wing_left' has no positive mass and moves on joint "
                         "'wing_left_joint'"});
  expectRefusal("<robot name=\"r\"><link name=\"base_link\"/><link name=\"frame\"/>" +
                    fixedJoint("j", "base_link", "frame", Pose()) + "</robot>",
                {"link 'base_link' has no positive mass", "no link with mass is fixed to it"});
  std::string aero = cadUnit();
  aero.insert(aero.find("</robot>"), "<aero link=\"base_link\"/>");
  expectRefusal(aero, {"<aero link='base_link'>", "lumped into 'body'"});
}

// A refused URDF changes nothing in a world: its creatures go on as if it never came.
TEST(UrdfInertia, AWorldKeepsItsStateAfterARefusedUrdf) {
  World a(test::openSky()), b(test::openSky());
  for (World* w : {&a, &b}) {
    w->spawn("u", parseCreatureModel(flapUnit(kTurned)), kStart);
    w->setWingCommands("u", {}, {StrokeCommand{30, 10, 0.8}, StrokeCommand{30, 10, 0.8}});
    w->step(50);
  }
  const std::string bad = oneLink(R"(ixx="1" ixy="1.5" ixz="0" iyy="1" iyz="0" izz="1")");
  EXPECT_THROW(a.spawn("v", parseCreatureModel(bad), kStart), ModelError);
  EXPECT_EQ(a.creatureNames(), std::vector<std::string>{"u"});
  EXPECT_TRUE(test::bitIdentical(a.state("u"), b.state("u")));
  a.step(50);
  b.step(50);
  EXPECT_TRUE(test::bitIdentical(a.state("u"), b.state("u")));
}

// A body whose URDF frame is turned (full tensor) falls onto the ground and rests on its
// largest face, its COM at half its height (0.015 m) above it; its reported shapes touch the
// ground (lowestBoxPoint in URDF frames). Measured: COM 0.01500 m, lowest point -2e-5 m.
TEST(UrdfInertia, ATurnedBodyFallsAndRestsOnTheGround) {
  WorldParams params;
  params.air.enabled = false;
  World world(params);
  const std::string urdf = "<robot name=\"b\">" + linkXml(kBody, kTurned[0], true) + "</robot>";
  const auto m = parseCreatureModel(urdf);
  ASSERT_TRUE(m->links[0].rotated());
  world.spawn("b", m, test::at(0, 0, 0.2) * turn(kTurned[0]));
  world.step(2000);
  const CreatureState s = world.state("b");
  const Vec3 com = s.link_poses[0].apply(m->links[0].urdfCom());
  std::cout.precision(10);
  std::cout << "resting COM height " << com.z() << " m, lowest point "
            << lowestBoxPoint(*m, s.link_poses) << " m\n";
  EXPECT_NEAR(com.z(), 0.015, 5e-4);
  EXPECT_NEAR(lowestBoxPoint(*m, s.link_poses), 0.0, 5e-4);
  EXPECT_LT(s.link_twists[0].linear.norm() + s.link_twists[0].angular.norm(), 1e-3);
  // Still level: the URDF frame turned by kTurned[0] from the level principal frame.
  EXPECT_LT(angle(s.link_poses[0].orientation * kTurned[0].conjugate(), Quat::Identity()), 1e-3);
}
