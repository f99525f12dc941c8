// bullet_rigid_bench: the flap-unit creatures of flapsim_bench simulated the way a user of plain
// Bullet would, as a side-by-side reference for the cost of flapsim's Featherstone world.
// Prints figures; never passes or fails on time.
//
//   bullet_rigid_bench [--runs 5] [--seconds 2] [--only NAME]
//
// What it measures: for creatures of 1, 4, 6, 12 and 25 flap units (flap_unit, chain_N), the
// median over `runs` fresh worlds of the steps per second of `seconds` simulated seconds of
// flight from z = 50 m (no ground), every wing stroking at 30/10 rad/s with amplitude 0.8 rad.
// The timed loop is all of one step: wing motor targets, passive-joint damping, air forces and
// btDiscreteDynamicsWorld::stepSimulation(0.001, 0, 0.001) (one fixed 1 ms step). Building the
// world is not timed.
//
// How the model is mapped (the creature itself is flapsim's: makeCreatureUrdf ->
// parseCreatureModel, so links, masses, inertias, boxes and joints are identical):
// - One btRigidBody per link, its frame at the link's centre of mass with the link's axes; mass
//   and principal inertia from LinkModel; a btBoxShape per box (full size / 2), in a
//   btCompoundShape when there are several or one is off the COM. Poses from the joint origins
//   at zero angle, root link frame at (0, 0, 50). Default body settings (no damping, implicit
//   gyroscopic term) except DISABLE_DEACTIVATION.
// - btDiscreteDynamicsWorld with btSequentialImpulseConstraintSolver, default solver settings
//   (10 iterations), gravity (0, 0, -9.81), Bullet in double precision.
// - Each revolute joint is a btHingeConstraint (parent = A, child = B) with the pivot at the
//   child link's origin and the frames' z axes along the URDF axis, built with
//   useReferenceFrameA = true: then getHingeAngle(), the motor's target velocity and setLimit()
//   all follow the URDF sign convention (positive turns the child about +axis; verified on a
//   two-body test when this bench was written). URDF limits are set on every limited joint (the
//   passive joints, +-0.35, and the wing hinges, +-1.4, never reached by a 0.8 stroke). Bodies
//   joined by a hinge do not collide (addConstraint(c, true)); other pairs of the creature may.
// - Wing joints: the hinge's angular motor, enableAngularMotor(true, target, effort * dt) with
//   target = flapsim::StrokeGenerator::target(getHingeAngle()) set before every step.
// - Passive joints: damping as an explicit torque -d (w_child - w_parent) . axis about the
//   axis, on the child and its opposite on the parent, before every step (no cap: d dt is well
//   under the links' inertia here).
// - Air: the pressure model F_i = -1/2 rho Cd s_i |u_i| (u_i . n) n on every cell whose face
//   advances into the air (u_i . n > 0), u_i = v_com + w x r_i, rho = 1.204, Cd = 1.15, on the
//   wing plates only: the two large faces of each plate, 4 x 4 cells each (16 advance at a
//   time). Summed per plate and applied as applyCentralForce + applyTorque (the same as
//   applyForce per cell). Unlike flapsim's world there is no drag on the bodies and on the
//   plates' edges, no buoyancy and no wind.
// Sequential impulses with 10 iterations do not converge on these creatures (light body, heavy
// wings): the left and right wings drift apart, printed after the table. When this bench was
// written, 1000 iterations brought the flap unit's 2 s trajectory to within about 1 cm of
// flapsim's World, with the wings in step.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench_common.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/make_creature.h"
#include "flapsim/stroke.h"
#include "fluid/pressure.h"
#include "fluid/surface.h"

namespace {

using flapsim::CreatureModel;
using flapsim::CreatureModelPtr;
using flapsim::JointModel;
using flapsim::JointType;
using flapsim::LinkModel;
using flapsim::Pose;
using flapsim::Quat;
using flapsim::Vec3;

constexpr double kStep = 0.001;        // s
constexpr double kSpawnHeight = 50.0;  // m
constexpr double kDensity = 1.204;     // kg/m^3
constexpr double kDragCoefficient = 1.15;
constexpr int kCellsPerEdge = 4;        // 4 x 4 cells per large face of a plate
constexpr double kDefaultEffort = 5.0;  // N m, flapsim's default for a wing without effort
const flapsim::StrokeCommand kStroke{30.0, 10.0, 0.8};

btVector3 toBt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
btQuaternion toBt(const Quat& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
btTransform toBt(const Pose& p) { return btTransform(toBt(p.orientation), toBt(p.position)); }
Vec3 fromBt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// One air cell of a plate, in its body's (COM) frame.
struct AirCell {
  Vec3 centre;
  Vec3 normal;
  double area;
};

struct Plate {
  btRigidBody* body;
  std::vector<AirCell> cells;
};

struct WingDrive {
  btHingeConstraint* hinge;
  flapsim::StrokeGenerator stroke;
  double max_impulse;
};

struct Damper {
  btRigidBody* parent;
  btRigidBody* child;
  btVector3 axis_in_parent;  // the hinge axis in the parent's COM frame
  double damping;
};

// The cells of the two large faces of a box (size, pose in the body's COM frame): the faces
// normal to its thinnest edge, each split into kCellsPerEdge x kCellsPerEdge cells (as
// flapsim's surfaces split them: boxSurfaceCells gives face after face, + then -, per axis).
void appendPlateCells(const Vec3& size, const Pose& origin, std::vector<AirCell>& cells) {
  int thin = 0;
  size.minCoeff(&thin);
  const std::vector<flapsim::SurfaceCell> all =
      flapsim::boxSurfaceCells(size, origin, kCellsPerEdge, kCellsPerEdge);
  const size_t per_face = kCellsPerEdge * kCellsPerEdge;
  for (size_t k = 2 * thin * per_face; k < (2 * thin + 2) * per_face; ++k) {
    cells.push_back(AirCell{all[k].centre, all[k].normal, all[k].area});
  }
}

// A creature as btRigidBody links and btHingeConstraint joints in a world of its own.
class RigidCreature {
 public:
  explicit RigidCreature(const CreatureModel& m)
      : dispatcher_(&config_), world_(&dispatcher_, &broadphase_, &solver_, &config_) {
    if (m.fixed_base) throw std::invalid_argument(m.name + ": fixed-base creatures unsupported");
    world_.setGravity(btVector3(0, 0, -9.81));

    // Bodies, parent before child: link frames from the joint origins at zero angle.
    std::vector<Pose> link_pose(m.links.size());
    link_pose[0] = Pose{Vec3(0, 0, kSpawnHeight), Quat::Identity()};
    for (size_t k = 0; k < m.links.size(); ++k) {
      const LinkModel& l = m.links[k];
      if (k > 0) {
        const JointModel& j = m.joints[l.parent_joint];
        link_pose[k] = link_pose[j.parent_link] * j.origin;
      }
      if (l.mass <= 0.0) throw std::invalid_argument(l.name + ": massless link unsupported");
      bodies_.push_back(makeBody(l, link_pose[k] * Pose{l.com, Quat::Identity()}));
    }

    // Joints.
    for (size_t ji = 0; ji < m.joints.size(); ++ji) {
      const JointModel& j = m.joints[ji];
      const LinkModel& parent = m.links[j.parent_link];
      const LinkModel& child = m.links[j.child_link];
      btRigidBody* a = bodies_[j.parent_link].get();
      btRigidBody* b = bodies_[j.child_link].get();
      // The joint frame: origin at the child link's origin, z along the axis (child axes).
      btVector3 z = toBt(j.axis).normalized(), x, y;
      btPlaneSpace1(z, x, y);
      const btMatrix3x3 in_child(x.x(), y.x(), z.x(), x.y(), y.y(), z.y(), x.z(), y.z(), z.z());
      const btTransform frame_b(in_child, toBt(-child.com));
      const btTransform frame_a(btMatrix3x3(toBt(j.origin.orientation)) * in_child,
                                toBt(j.origin.position - parent.com));
      switch (j.type) {
        case JointType::kRevolute:
        case JointType::kContinuous: {
          auto hinge = std::make_unique<btHingeConstraint>(*a, *b, frame_a, frame_b, true);
          if (j.type == JointType::kRevolute && j.limited && j.lower < j.upper) {
            hinge->setLimit(j.lower, j.upper);
          }
          if (j.wing) {
            WingDrive drive{hinge.get(), flapsim::StrokeGenerator(),
                            (j.effort > 0.0 ? j.effort : kDefaultEffort) * kStep};
            drive.stroke.setCommand(kStroke);
            wings_.push_back(drive);
          } else if (j.damping > 0.0) {
            dampers_.push_back(Damper{a, b, frame_a.getBasis().getColumn(2), j.damping});
          }
          hinges_by_joint_.push_back(hinge.get());
          constraints_.push_back(std::move(hinge));
          break;
        }
        case JointType::kFixed:
          constraints_.push_back(std::make_unique<btFixedConstraint>(*a, *b, frame_a, frame_b));
          hinges_by_joint_.push_back(nullptr);
          break;
        default:
          throw std::invalid_argument(j.name + ": only revolute and fixed joints supported");
      }
      world_.addConstraint(constraints_.back().get(), true);
    }

    // Air cells on the wing plates (the child links of the wing joints).
    for (int wj : m.wing_joints) {
      const LinkModel& l = m.links[m.joints[wj].child_link];
      Plate plate{bodies_[m.joints[wj].child_link].get(), {}};
      const Pose com_inv{-l.com, Quat::Identity()};
      for (const flapsim::Box& box : l.boxes) {
        appendPlateCells(box.size, com_inv * box.origin, plate.cells);
      }
      plates_.push_back(std::move(plate));
    }
  }

  ~RigidCreature() {
    for (auto& c : constraints_) world_.removeConstraint(c.get());
    for (auto& b : bodies_) world_.removeRigidBody(b.get());
  }

  RigidCreature(const RigidCreature&) = delete;
  RigidCreature& operator=(const RigidCreature&) = delete;

  // One 1 ms step: drives, damping and air, then Bullet (which clears the forces after it).
  void step() {
    for (WingDrive& w : wings_) {
      w.hinge->enableAngularMotor(true, w.stroke.target(w.hinge->getHingeAngle()), w.max_impulse);
    }
    for (const Damper& d : dampers_) {
      const btVector3 axis = d.parent->getWorldTransform().getBasis() * d.axis_in_parent;
      const btScalar rate =
          axis.dot(d.child->getAngularVelocity() - d.parent->getAngularVelocity());
      const btVector3 torque = -d.damping * rate * axis;
      d.child->applyTorque(torque);
      d.parent->applyTorque(-torque);
    }
    applyAir();
    world_.stepSimulation(kStep, 0, kStep);
    for (int i = 0; i < dispatcher_.getNumManifolds(); ++i) {
      if (dispatcher_.getManifoldByIndexInternal(i)->getNumContacts() > 0) {
        ++contact_steps_;
        break;
      }
    }
  }

  // The URDF angle of joint `ji` (a hinge).
  double jointAngle(int ji) const { return hinges_by_joint_.at(ji)->getHingeAngle(); }
  // World position of the link's COM.
  Vec3 linkCom(int link) const { return fromBt(bodies_.at(link)->getWorldTransform().getOrigin()); }
  // Steps that ended with a contact point between two links of the creature.
  int contactSteps() const { return contact_steps_; }

 private:
  std::unique_ptr<btRigidBody> makeBody(const LinkModel& l, const Pose& com_pose) {
    btCollisionShape* shape = nullptr;
    const Pose com_inv{-l.com, Quat::Identity()};
    if (l.boxes.empty()) {
      shapes_.push_back(std::make_unique<btEmptyShape>());
      shape = shapes_.back().get();
    } else {
      const Pose first = com_inv * l.boxes[0].origin;
      if (l.boxes.size() == 1 && first.position.isZero(1e-12) &&
          first.orientation.isApprox(Quat::Identity(), 1e-12)) {
        shapes_.push_back(std::make_unique<btBoxShape>(toBt(0.5 * l.boxes[0].size)));
        shape = shapes_.back().get();
      } else {
        auto compound = std::make_unique<btCompoundShape>();
        for (const flapsim::Box& b : l.boxes) {
          shapes_.push_back(std::make_unique<btBoxShape>(toBt(0.5 * b.size)));
          compound->addChildShape(toBt(com_inv * b.origin), shapes_.back().get());
        }
        shape = compound.get();
        shapes_.push_back(std::move(compound));
      }
    }
    btRigidBody::btRigidBodyConstructionInfo info(l.mass, nullptr, shape, toBt(l.inertia));
    info.m_startWorldTransform = toBt(com_pose);
    auto body = std::make_unique<btRigidBody>(info);
    body->setActivationState(DISABLE_DEACTIVATION);
    world_.addRigidBody(body.get());
    return body;
  }

  // The pressure model per cell, in each plate's COM frame (cells and normals are constant
  // there): u_i = v + w x c_i; force and torque about the COM summed, then turned to world.
  void applyAir() {
    for (const Plate& p : plates_) {
      const btMatrix3x3& rot = p.body->getWorldTransform().getBasis();
      const Vec3 v = fromBt(p.body->getLinearVelocity() * rot);  // rot^T v
      const Vec3 w = fromBt(p.body->getAngularVelocity() * rot);
      Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
      for (const AirCell& c : p.cells) {
        const Vec3 f = flapsim::pressureForce(v + w.cross(c.centre), c.normal, c.area, kDensity,
                                              kDragCoefficient);
        force += f;
        torque += c.centre.cross(f);
      }
      p.body->applyCentralForce(rot * toBt(force));
      p.body->applyTorque(rot * toBt(torque));
    }
  }

  // Declared in construction order; the destructor empties the world before they go.
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;  // per model link
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
  std::vector<btHingeConstraint*> hinges_by_joint_;  // per model joint, null if not a hinge
  std::vector<WingDrive> wings_;
  std::vector<Damper> dampers_;
  std::vector<Plate> plates_;
  int contact_steps_ = 0;
};

// What one run leaves behind, for the report after the table.
struct EndState {
  double root_height = 0.0;
  double wing_difference = 0.0;  // unit 0: left minus right wing joint angle, rad
  int contact_steps = 0;
};

// Steps per second of one run of `steps` steps in a fresh world.
double timeRun(const CreatureModel& m, int steps, EndState* end) {
  RigidCreature creature(m);
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) creature.step();
  const auto t1 = std::chrono::steady_clock::now();
  end->root_height = creature.linkCom(0).z() - m.links[0].com.z();
  const int left = m.findJoint("unit0_wing_left_joint");
  const int right = m.findJoint("unit0_wing_right_joint");
  end->wing_difference =
      left >= 0 && right >= 0 ? creature.jointAngle(left) - creature.jointAngle(right) : 0.0;
  end->contact_steps = creature.contactSteps();
  return steps / std::chrono::duration<double>(t1 - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  flapsim_bench::BenchOptions o;
  if (!flapsim_bench::parseBenchOptions(argc, argv, &o)) {
    return flapsim_bench::referenceUsage("bullet_rigid_bench");
  }
  const int steps = std::max(1, static_cast<int>(std::lround(o.seconds / kStep)));
  std::printf(
      "bullet_rigid_bench: btRigidBody + btHingeConstraint, sequential impulses; %d runs of %g s "
      "simulated (%d steps of %g ms), medians\n",
      o.runs, o.seconds, steps, kStep * 1e3);
  flapsim_bench::printTableHeader();
  std::string reported;
  EndState report;
  for (const flapsim_bench::BenchCreature& c : flapsim_bench::benchCreatures()) {
    const std::string& name = c.name;
    if (!o.only.empty() && name != o.only) continue;
    CreatureModelPtr model = flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(c.units, "c"));
    const int bodies = static_cast<int>(model->links.size());
    std::vector<double> sps;
    EndState end;
    for (int r = 0; r < o.runs; ++r) sps.push_back(timeRun(*model, steps, &end));
    flapsim_bench::printTableRow(name, bodies, flapsim_bench::median(sps), kStep);
    if (reported.empty()) {
      reported = name;
      report = end;
    }
  }
  std::printf(
      "%s after %g s: root height %.4f m (spawned at %g), unit0 wing angle left - right "
      "%.3e rad, %d steps with self-contacts\n",
      reported.c_str(), steps * kStep, report.root_height, kSpawnHeight, report.wing_difference,
      report.contact_steps);
  return 0;
}
