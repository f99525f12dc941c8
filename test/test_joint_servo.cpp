// JointServoSolver against closed forms, conservation, mirror symmetry and a dense solve of
// the joint-space equations H dq = B lambda built from Jacobians.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "doc_figure.h"
#include "dynamics/joint_servo.h"

namespace flapsim {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
constexpr double kHuge = 1e6;

ServoDemand drive(double velocity_change, double max_impulse = kHuge) {
  return ServoDemand{true, velocity_change, max_impulse};
}

// Column of each movable joint in the generalized velocity (6 root columns first unless
// the root is fixed); -1 for the root and fixed joints.
std::vector<int> dofIndex(const std::vector<ServoLink>& links, bool fixed_root, int* ndof) {
  std::vector<int> dof(links.size(), -1);
  *ndof = fixed_root ? 0 : 6;
  for (size_t k = 1; k < links.size(); ++k) {
    if (links[k].joint != ServoJointType::kFixed) dof[k] = (*ndof)++;
  }
  return dof;
}

struct Dense {
  VectorXd dq;                  // generalized velocity change
  std::vector<double> impulse;  // per link
};

// Dense solve: joints with an active demand are driven (dq = demand, impulse unknown); the
// others push with known[k] (zero on fixed joints).
Dense denseSolve(const std::vector<ServoLink>& links, bool fixed_root,
                 const std::vector<ServoDemand>& demands,
                 const std::vector<double>& known = std::vector<double>(7, 0.0),
                 const ServoLoads& loads = ServoLoads()) {
  int ndof = 0;
  const std::vector<int> dof = dofIndex(links, fixed_root, &ndof);
  MatrixXd h = MatrixXd::Zero(ndof, ndof);
  VectorXd f = VectorXd::Zero(ndof);
  for (size_t k = 0; k < links.size(); ++k) {
    MatrixXd j = MatrixXd::Zero(6, ndof);
    if (!fixed_root) j.leftCols(6).setIdentity();
    for (int a = static_cast<int>(k); a > 0; a = links[a].parent) {
      if (dof[a] >= 0) j.col(dof[a]) = motionSubspace(links[a]);
    }
    const ServoLink& l = links[k];
    h += j.transpose() * spatialInertia(l.mass, l.com, l.inertia) * j;
    if (!loads.extra_inertia.empty()) h += j.transpose() * loads.extra_inertia[k] * j;
    if (!loads.impulse.empty()) f += j.transpose() * loads.impulse[k];
  }
  std::vector<int> driven;
  for (size_t k = 1; k < links.size(); ++k) {
    if (dof[k] < 0) continue;
    if (demands[k].active) {
      driven.push_back(static_cast<int>(k));
    } else {
      f(dof[k]) += known[k];
    }
  }
  const int nd = static_cast<int>(driven.size());
  MatrixXd kkt = MatrixXd::Zero(ndof + nd, ndof + nd);
  VectorXd rhs = VectorXd::Zero(ndof + nd);
  kkt.topLeftCorner(ndof, ndof) = h;
  rhs.head(ndof) = f;
  for (int i = 0; i < nd; ++i) {
    const int c = dof[driven[i]];
    kkt(c, ndof + i) = -1.0;
    kkt(ndof + i, c) = 1.0;
    rhs(ndof + i) = demands[driven[i]].velocity_change;
  }
  const VectorXd x = kkt.fullPivLu().solve(rhs);
  Dense out{x.head(ndof), known};
  for (int i = 0; i < nd; ++i) out.impulse[driven[i]] = x(ndof + i);
  return out;
}

// Returns the largest difference.
double expectMatchesDense(const std::vector<ServoLink>& links, bool fixed_root,
                          const ServoSolution& s, const Dense& d, double tol) {
  int ndof = 0;
  const std::vector<int> dof = dofIndex(links, fixed_root, &ndof);
  double most = 0.0;
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(s.root_velocity_change(i), fixed_root ? 0.0 : d.dq(i), tol) << "root " << i;
    most = std::max(most, std::abs(s.root_velocity_change(i) - (fixed_root ? 0.0 : d.dq(i))));
  }
  for (size_t k = 1; k < links.size(); ++k) {
    EXPECT_NEAR(s.impulse[k], d.impulse[k], tol) << "link " << k;
    EXPECT_NEAR(s.velocity_change[k], dof[k] < 0 ? 0.0 : d.dq(dof[k]), tol) << "link " << k;
    most = std::max({most, std::abs(s.impulse[k] - d.impulse[k]),
                     std::abs(s.velocity_change[k] - (dof[k] < 0 ? 0.0 : d.dq(dof[k])))});
  }
  return most;
}

// Seven links, floating or fixed root; link 1 and the root have two children each.
std::vector<ServoLink> randomTree(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&] {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v(i) = u(rng);
    return v;
  };
  using T = ServoJointType;
  const int parents[] = {-1, 0, 1, 1, 0, 4, 3};
  const T types[] = {T::kFixed,    T::kRevolute, T::kPrismatic, T::kRevolute,
                     T::kRevolute, T::kFixed,    T::kRevolute};
  std::vector<ServoLink> links(7);
  for (size_t k = 0; k < links.size(); ++k) {
    ServoLink& l = links[k];
    l.parent = parents[k];
    l.joint = types[k];
    l.mass = 1.0 + 0.8 * u(rng);
    l.com = 0.4 * vec();
    Mat3 a;
    for (int c = 0; c < 3; ++c) a.col(c) = vec();
    l.inertia = 0.02 * (a * a.transpose() + 0.1 * Mat3::Identity());
    l.axis = vec().normalized();
    l.anchor = 0.4 * vec();
  }
  return links;
}

// Links 1 (revolute), 2 (prismatic) and 6 (revolute) driven; 3 and 4 passive; the demand
// on the fixed link 5 must be ignored.
std::vector<ServoDemand> treeDemands() {
  std::vector<ServoDemand> d(7);
  d[1] = drive(1.3);
  d[2] = drive(-0.7);
  d[5] = drive(2.0);
  d[6] = drive(-2.1);
  return d;
}

TEST(JointServo, PendulumImpulseIsInertiaAboutAxisTimesRate) {
  const Vec3 axis = Vec3(1.0, 2.0, 2.0) / 3.0;
  const Vec3 perp = Vec3(2.0, -1.0, 0.0).normalized();
  const double m = 0.7, dist = 0.15, rate = 1.5;
  std::vector<ServoLink> links(2);
  links[0].mass = 3.0;
  links[0].inertia = Mat3::Identity();
  ServoLink& p = links[1];
  p.parent = 0;
  p.joint = ServoJointType::kRevolute;
  p.mass = m;
  p.axis = axis;
  p.anchor = Vec3(0.1, -0.2, 0.3);
  p.com = p.anchor + dist * perp + 0.05 * axis;  // the offset along the axis is irrelevant
  p.inertia << 0.02, 0.003, -0.001, 0.003, 0.015, 0.002, -0.001, 0.002, 0.01;
  const std::vector<ServoDemand> demands = {ServoDemand{}, drive(rate)};
  JointServoSolver solver;
  ServoSolution s;
  solver.solve(links, true, demands, s);
  const double i_axis = axis.dot(p.inertia * axis) + m * dist * dist;
  EXPECT_NEAR(s.impulse[1], i_axis * rate, 1e-14);
  EXPECT_DOUBLE_EQ(s.velocity_change[1], rate);
  EXPECT_FALSE(s.saturated[1]);
  EXPECT_TRUE(s.root_velocity_change.isZero());
}

TEST(JointServo, FloatingPairConservesMomentum) {
  std::vector<ServoLink> links = randomTree(3);
  links.resize(2);
  JointServoSolver solver;
  ServoSolution s;
  solver.solve(links, false, {ServoDemand{}, drive(0.9)}, s);
  EXPECT_DOUBLE_EQ(s.velocity_change[1], 0.9);
  const Vec6 dv0 = s.root_velocity_change;
  const Vec6 dv1 = dv0 + motionSubspace(links[1]) * s.velocity_change[1];
  const Vec6 p0 = spatialInertia(links[0].mass, links[0].com, links[0].inertia) * dv0;
  const Vec6 p1 = spatialInertia(links[1].mass, links[1].com, links[1].inertia) * dv1;
  ASSERT_GT(p1.norm(), 1e-3);
  EXPECT_LT((p0 + p1).norm(), 1e-12 * (p0.norm() + p1.norm()));
  // The child's momentum change is the joint's spatial impulse; along the axis it is the
  // servo impulse.
  EXPECT_NEAR(motionSubspace(links[1]).dot(p1), s.impulse[1], 1e-12 * p1.norm());
}

TEST(JointServo, MatchesDenseSolveOnRandomTree) {
  const std::vector<ServoLink> links = randomTree(7);
  const std::vector<ServoDemand> demands = treeDemands();
  for (bool fixed_root : {false, true}) {
    SCOPED_TRACE(fixed_root ? "fixed root" : "floating root");
    JointServoSolver solver;
    ServoSolution s;
    solver.solve(links, fixed_root, demands, s);
    const Dense d = denseSolve(links, fixed_root, demands);
    expectMatchesDense(links, fixed_root, s, d, 1e-9);
    EXPECT_EQ(s.velocity_change[5], 0.0);
    EXPECT_EQ(s.impulse[5], 0.0);
    for (int k : {1, 2, 6}) EXPECT_DOUBLE_EQ(s.velocity_change[k], demands[k].velocity_change);
    for (size_t k = 0; k < links.size(); ++k) EXPECT_FALSE(s.saturated[k]);
  }
}

// Extra inertias (w f f^T, as the fluid adds) and known spatial impulses on the links enter
// the joint-space equations as J^T A J and J^T p: the O(links) solve agrees with the dense
// one, with and without servos, and each link's spatial velocity change is J dq.
TEST(JointServo, ExtraInertiaAndImpulsesMatchDenseSolve) {
  const std::vector<ServoLink> links = randomTree(11);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ServoLoads loads;
  for (size_t k = 0; k < links.size(); ++k) {
    Vec6 f, p;
    for (int i = 0; i < 6; ++i) {
      f(i) = u(rng);
      p(i) = u(rng);
    }
    loads.extra_inertia.push_back((k % 2 == 0 ? 5.0 : 0.0) * f * f.transpose());
    loads.impulse.push_back(0.3 * p);
  }
  double most = 0.0;
  for (bool with_servos : {false, true}) {
    for (bool fixed_root : {false, true}) {
      SCOPED_TRACE(std::string(fixed_root ? "fixed root" : "floating root") +
                   (with_servos ? ", servos" : ", no servos"));
      const std::vector<ServoDemand> demands =
          with_servos ? treeDemands() : std::vector<ServoDemand>(links.size());
      JointServoSolver solver;
      ServoSolution s;
      solver.solve(links, fixed_root, demands, loads, s);
      const Dense d = denseSolve(links, fixed_root, demands, std::vector<double>(7, 0.0), loads);
      most = std::max(most, expectMatchesDense(links, fixed_root, s, d, 1e-9));
      ASSERT_EQ(s.link_velocity_change.size(), links.size());
      int ndof = 0;
      const std::vector<int> dof = dofIndex(links, fixed_root, &ndof);
      for (size_t k = 0; k < links.size(); ++k) {
        Vec6 expected = fixed_root ? Vec6::Zero() : Vec6(d.dq.head<6>());
        for (int a = static_cast<int>(k); a > 0; a = links[a].parent) {
          if (dof[a] >= 0) expected += motionSubspace(links[a]) * d.dq(dof[a]);
        }
        EXPECT_LT((s.link_velocity_change[k] - expected).norm(), 1e-9) << "link " << k;
        most = std::max(most, (s.link_velocity_change[k] - expected).norm());
      }
    }
  }
  test::printFigure("largest_difference", most);
}

TEST(JointServo, WrongNumberOfLoadsIsNamed) {
  const std::vector<ServoLink> links = randomTree(7);
  ServoLoads loads;
  loads.impulse.resize(3, Vec6::Zero());
  JointServoSolver solver;
  ServoSolution s;
  try {
    solver.solve(links, false, std::vector<ServoDemand>(links.size()), loads, s);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("3 loads for 7 links"), std::string::npos) << e.what();
  }
}

TEST(JointServo, SaturatedJointPushesWithItsBound) {
  const std::vector<ServoLink> links = randomTree(7);
  for (bool fixed_root : {false, true}) {
    SCOPED_TRACE(fixed_root ? "fixed root" : "floating root");
    std::vector<ServoDemand> demands = treeDemands();
    JointServoSolver solver;
    ServoSolution free_run, s;
    solver.solve(links, fixed_root, demands, free_run);
    const double needed = free_run.impulse[6];
    ASSERT_GT(std::abs(needed), 1e-3);

    demands[6].max_impulse = 0.4 * std::abs(needed);
    solver.solve(links, fixed_root, demands, s);
    const double bound = std::copysign(demands[6].max_impulse, needed);
    EXPECT_TRUE(s.saturated[6]);
    EXPECT_DOUBLE_EQ(s.impulse[6], bound);
    EXPECT_FALSE(s.saturated[1]);
    EXPECT_FALSE(s.saturated[2]);
    // Pushing with less than it needs, the joint falls short of its target.
    EXPECT_GT((demands[6].velocity_change - s.velocity_change[6]) * bound, 0.0);
    std::vector<ServoDemand> known = demands;
    known[6].active = false;
    std::vector<double> impulses(7, 0.0);
    impulses[6] = bound;
    expectMatchesDense(links, fixed_root, s, denseSolve(links, fixed_root, known, impulses), 1e-9);

    demands[6].max_impulse = 1.0000001 * std::abs(needed);
    solver.solve(links, fixed_root, demands, s);
    EXPECT_FALSE(s.saturated[6]);
    expectMatchesDense(links, fixed_root, s, denseSolve(links, fixed_root, demands), 1e-9);
  }
}

// Asymmetric bounds (a motor's driving and braking limits differ): a joint that needs an
// impulse beyond the bound on its side pushes with that side's bound, and the other side's
// bound does not limit it; a zero bound on the side it needs leaves it free (impulse 0).
TEST(JointServo, AsymmetricBoundsLimitEachSideWithItsOwn) {
  const std::vector<ServoLink> links = randomTree(7);
  std::vector<ServoDemand> demands = treeDemands();
  JointServoSolver solver;
  ServoSolution free_run, s;
  solver.solve(links, true, demands, free_run);
  const double needed = free_run.impulse[6];
  ASSERT_GT(std::abs(needed), 1e-3);
  const bool positive = needed > 0.0;
  // The bound on the needed side at 40 %, the other side's far above.
  demands[6].max_impulse = positive ? 0.4 * needed : 10.0 * std::abs(needed);
  demands[6].max_negative_impulse = positive ? 10.0 * needed : 0.4 * std::abs(needed);
  solver.solve(links, true, demands, s);
  EXPECT_TRUE(s.saturated[6]);
  EXPECT_DOUBLE_EQ(s.impulse[6], 0.4 * needed);
  // The other side's bound at 40 % does not limit it.
  std::swap(demands[6].max_impulse, demands[6].max_negative_impulse);
  solver.solve(links, true, demands, s);
  EXPECT_FALSE(s.saturated[6]);
  EXPECT_NEAR(s.impulse[6], needed, 1e-12 * std::abs(needed));
  // No bound on the needed side: it is carried along, pushing with nothing.
  (positive ? demands[6].max_impulse : demands[6].max_negative_impulse) = 0.0;
  solver.solve(links, true, demands, s);
  EXPECT_TRUE(s.saturated[6]);
  EXPECT_EQ(s.impulse[6], 0.0);
  std::vector<ServoDemand> passive = demands;
  passive[6].active = false;
  expectMatchesDense(links, true, s, denseSolve(links, true, passive), 1e-9);
}

// Every driven joint bounded below or near its need: the result must satisfy the box
// complementarity conditions and solve the dense equations of its own active set.
TEST(JointServo, TightBoundsSatisfyComplementarity) {
  for (unsigned seed = 1; seed <= 30; ++seed) {
    SCOPED_TRACE(seed);
    const std::vector<ServoLink> links = randomTree(seed);
    const bool fixed_root = seed % 2 == 0;
    std::vector<ServoDemand> demands(7);
    for (int k : {1, 2, 3, 4, 6}) demands[k] = drive(std::sin(seed * 1.7 + k));
    JointServoSolver solver;
    ServoSolution s;
    solver.solve(links, fixed_root, demands, s);
    for (int k : {1, 2, 3, 4, 6}) {
      demands[k].max_impulse = std::abs(s.impulse[k]) * (0.3 + 0.25 * ((seed + k) % 5));
    }
    solver.solve(links, fixed_root, demands, s);
    std::vector<ServoDemand> active = demands;
    std::vector<double> impulses(7, 0.0);
    for (int k : {1, 2, 3, 4, 6}) {
      const ServoDemand& d = demands[k];
      if (s.saturated[k]) {
        EXPECT_DOUBLE_EQ(std::abs(s.impulse[k]), d.max_impulse) << k;
        EXPECT_GE((d.velocity_change - s.velocity_change[k]) * s.impulse[k], -1e-12) << k;
        active[k].active = false;
        impulses[k] = s.impulse[k];
      } else {
        EXPECT_LE(std::abs(s.impulse[k]), d.max_impulse * (1.0 + 1e-12)) << k;
        EXPECT_DOUBLE_EQ(s.velocity_change[k], d.velocity_change) << k;
      }
    }
    expectMatchesDense(links, fixed_root, s, denseSolve(links, fixed_root, active, impulses), 1e-9);
  }
}

TEST(JointServo, MirrorWingsGiveMirrorImpulses) {
  const Mat3 flip = Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();  // y -> -y
  std::vector<ServoLink> links(3);
  links[0].mass = 0.5;
  links[0].com = Vec3(0.01, 0.0, -0.02);
  links[0].inertia << 2e-4, 0.0, 3e-5, 0.0, 3e-4, 0.0, 3e-5, 0.0, 4e-4;
  for (int side : {1, 2}) {
    const Mat3 m = side == 1 ? Mat3::Identity() : flip;
    ServoLink& w = links[side];
    w.parent = 0;
    w.joint = ServoJointType::kRevolute;
    w.axis = Vec3::UnitX();  // mirrors to -x: mirrored motion has the opposite rate
    w.anchor = m * Vec3(0.0, 0.03, 0.0);
    w.mass = 0.02;
    w.com = m * Vec3(0.012, 0.07, 0.004);
    Mat3 i;
    i << 3e-5, 4e-6, -2e-6, 4e-6, 1e-5, 5e-6, -2e-6, 5e-6, 3.5e-5;
    w.inertia = m * i * m;
  }
  JointServoSolver solver;
  ServoSolution s;
  const double rate = 2.0;
  for (int run = 0; run < 2; ++run) {  // unbounded, then both wings saturated
    const double bound = run == 0 ? kHuge : 0.5 * std::abs(s.impulse[1]);
    SCOPED_TRACE(bound);
    solver.solve(links, false, {ServoDemand{}, drive(rate, bound), drive(-rate, bound)}, s);
    ASSERT_GT(std::abs(s.impulse[1]), 1e-6);
    EXPECT_EQ(s.saturated[1], bound != kHuge);
    EXPECT_EQ(s.saturated[2], s.saturated[1]);
    EXPECT_NEAR(s.impulse[1] + s.impulse[2], 0.0, 1e-12 * std::abs(s.impulse[1]));
    EXPECT_NEAR(s.velocity_change[1] + s.velocity_change[2], 0.0, 1e-12 * rate);
    const Vec6& dv = s.root_velocity_change;
    ASSERT_GT(dv.norm(), 1e-3);
    for (int i : {0, 2, 4}) EXPECT_NEAR(dv(i), 0.0, 1e-12 * dv.norm()) << i;  // roll, yaw, y
  }
}

TEST(JointServo, AllPassiveDoesNothing) {
  const std::vector<ServoLink> links = randomTree(11);
  std::vector<ServoDemand> demands(7);
  demands[3] = ServoDemand{false, 1.0, 5.0};  // inactive: its target is ignored
  demands[4] = ServoDemand{true, 1.0, 0.0};   // no authority: passive
  for (bool fixed_root : {false, true}) {
    JointServoSolver solver;
    ServoSolution s;
    solver.solve(links, fixed_root, demands, s);
    EXPECT_TRUE(s.root_velocity_change.isZero(0.0));
    for (size_t k = 0; k < links.size(); ++k) {
      EXPECT_EQ(s.impulse[k], 0.0) << k;
      EXPECT_EQ(s.velocity_change[k], 0.0) << k;
      EXPECT_FALSE(s.saturated[k]) << k;
    }
  }
}

TEST(JointServo, WrongNumberOfDemandsIsNamed) {
  std::vector<ServoLink> links(3);
  links[1].parent = 0;
  links[2].parent = 1;
  JointServoSolver solver;
  ServoSolution out;
  try {
    solver.solve(links, true, std::vector<ServoDemand>(2), out);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2 demands for 3 links"), std::string::npos) << e.what();
  }
  solver.solve({}, false, {}, out);  // an empty tree is nothing to do
  EXPECT_TRUE(out.impulse.empty());
}

}  // namespace
}  // namespace flapsim
