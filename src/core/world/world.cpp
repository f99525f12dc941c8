#include "flapsim/world.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <thread>
#include <utility>

#include "dynamics/body_builder.h"
#include "dynamics/creature_body.h"
#include "flapsim/air_model.h"
#include "fluid/surface.h"
#include "world/joint_drives.h"
#include "world/power.h"
#include "world/world_air.h"

namespace flapsim {

namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

std::string checkAir(const AirParams& a) {
  if (!std::isfinite(a.density) || a.density < 0.0 || a.density > kMaxDensity) {
    return "air density must be in [0, 1e5] kg/m^3";
  }
  if (!std::isfinite(a.drag_coefficient) || a.drag_coefficient < 0.0 ||
      a.drag_coefficient > kMaxDragCoefficient) {
    return "air drag_coefficient must be in [0, 1000]";
  }
  if (!finite(a.wind) || a.wind.cwiseAbs().maxCoeff() > 1e3) {
    return "air wind must be finite, each component within +-1000 m/s";
  }
  if (!makeAirModel(a.model)) return unknownAirModelMessage(a.model);
  const QuasiSteadyCoefficients& q = a.quasi_steady;
  for (double c : {q.lift_mean, q.lift_amplitude, q.lift_frequency, q.lift_phase, q.drag_mean,
                   q.drag_amplitude, q.drag_frequency, q.drag_phase}) {
    if (!std::isfinite(c) || std::abs(c) > 1e3) {
      return "air quasi_steady coefficients must be finite and within +-1000";
    }
  }
  if (a.subdivisions_u < 1 || a.subdivisions_v < 1 || a.subdivisions_u > 1000 ||
      a.subdivisions_v > 1000) {
    return "air subdivisions must be in 1..1000";
  }
  return "";
}

// An external wrench while it acts: the force's point in the link's COM frame.
struct ActiveWrench {
  int link = 0;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero(), offset = Vec3::Zero();
  std::int64_t steps_left = -1;  // < 0: until cleared
};

// What the user asked for: enough to rebuild a creature bit-for-bit.
struct CreatureRecord {
  std::string name;
  CreatureModelPtr model;
  Pose pose;
  Twist twist;
  std::vector<JointDrive> drives;         // per model joint
  std::optional<Divergence> divergence;   // set by the watchdog: not stepped until reset
  bool reported = false;                  // handed out by takeDivergences()
  std::vector<ActiveWrench> wrenches;     // external, in the order applied
  Vec3 root_acceleration = Vec3::Zero();  // of the root's COM over the last step
  PowerMeter power;                       // its motors' work
};

// What a step may change in a multibody: enough to put it back bit for bit.
struct BodySnapshot {
  btVector3 position, velocity, omega;
  btQuaternion orientation;
  std::vector<double> q, qdot;

  void take(const btMultiBody& mb) {
    position = mb.getBasePos();
    orientation = mb.getWorldToBaseRot();
    velocity = mb.getBaseVel();
    omega = mb.getBaseOmega();
    q.resize(static_cast<size_t>(mb.getNumLinks()));
    qdot.resize(q.size());
    for (int k = 0; k < mb.getNumLinks(); ++k) {
      q[k] = mb.getJointPos(k);
      qdot[k] = mb.getJointVel(k);
    }
  }

  void restore(btMultiBody& mb) const {
    mb.setBasePos(position);
    mb.setWorldToBaseRot(orientation);
    mb.setBaseVel(velocity);
    mb.setBaseOmega(omega);
    for (int k = 0; k < mb.getNumLinks(); ++k) {
      mb.setJointPos(k, q[k]);
      mb.setJointVel(k, qdot[k]);
    }
  }
};

// Empty if every link of `b` has a finite pose and velocity and no point of it moves faster
// than `max_speed`, else what is wrong (naming the link).
std::string checkMotion(const CreatureModel& m, const CreatureBody& b, double max_speed) {
  const LinkFrames& f = b.frames;
  for (size_t k = 0; k < m.links.size(); ++k) {
    const int i = static_cast<int>(k);
    // Named only on a fault: this runs every step.
    auto link = [&m, k] { return "link '" + m.links[k].name + "'"; };
    const btQuaternion& q = f.world_to_local[i];
    if (!std::isfinite(f.local_origin[i].x() + f.local_origin[i].y() + f.local_origin[i].z()) ||
        !std::isfinite(q.x() + q.y() + q.z() + q.w())) {
      return link() + " has a non-finite pose";
    }
    // The fastest point of the link: its COM's speed plus the spin times its reach, at most
    // the square root of 2 (v^2 + (w reach)^2): well below the limit (as almost always), no
    // square roots.
    const double v2 = f.vel[k].length2(), w2r2 = f.omega[k].length2() * b.reach[k] * b.reach[k];
    if (max_speed > 0.0 && 2.0 * (v2 + w2r2) < 0.99 * max_speed * max_speed) continue;
    const double v = f.vel[k].length(), w = f.omega[k].length();
    if (!std::isfinite(v) || !std::isfinite(w)) return link() + " has a non-finite velocity";
    const double speed = v + w * b.reach[k];
    if (speed > max_speed) {
      std::ostringstream msg;
      msg.precision(4);
      msg << link() << " moves at " << speed << " m/s (max_speed " << max_speed << " m/s)";
      return msg.str();
    }
  }
  return "";
}

// Empty if creature `name` has at most `max_cells` air cells under `air`, else a message naming
// it, its count and its largest link.
std::string checkCells(const std::string& name, const CreatureModel& m, const AirParams& air,
                       int max_cells) {
  double total = 0.0, largest = 0.0;
  std::string largest_link;
  for (const LinkModel& l : m.links) {
    if (!l.aero.enabled || l.boxes.empty()) continue;
    const double cells =
        6.0 * static_cast<double>(l.boxes.size()) * subdivisionsU(l, air) * subdivisionsV(l, air);
    total += cells;
    if (cells > largest) {
      largest = cells;
      largest_link = l.name;
    }
  }
  if (total <= max_cells) return "";
  std::ostringstream msg;
  msg.precision(10);
  msg << "creature '" << name << "' would have " << total << " air cells (link '" << largest_link
      << "' alone " << largest << "), over max_cells " << max_cells
      << " (boxes x 6 faces x subdivisions)";
  return msg.str();
}

}  // namespace

std::string validateWorldParams(const WorldParams& p) {
  if (!std::isfinite(p.step_size) || p.step_size < 1e-6 || p.step_size > 0.1) {
    return "step_size must be in [1e-6, 0.1] s";
  }
  if (!std::isfinite(p.turn_substep) || p.turn_substep < 0.0) {
    return "turn_substep must be finite and >= 0 s";
  }
  if (!finite(p.gravity) || p.gravity.norm() > kMaxGravity) {
    return "gravity must be finite and at most 1e4 m/s^2";
  }
  if (!std::isfinite(p.ground_friction) || p.ground_friction < 0.0 || p.ground_friction > 1e3) {
    return "ground_friction must be in [0, 1000]";
  }
  if (p.solver_iterations < 1 || p.solver_iterations > 1000) {
    return "solver_iterations must be in 1..1000";
  }
  if (p.threads < 1 || p.threads > 256) return "threads must be in 1..256";
  if (!std::isfinite(p.default_wing_effort) || p.default_wing_effort <= 0.0 ||
      p.default_wing_effort > 1e9) {
    return "default_wing_effort must be in (0, 1e9] N m";
  }
  if (p.max_cells < 1) return "max_cells must be >= 1";
  if (!std::isfinite(p.max_speed) || p.max_speed <= 0.0 || p.max_speed > 3e8) {
    return "max_speed must be in (0, 3e8] m/s";
  }
  return checkAir(p.air);
}

// The creatures (records and bodies, in spawn order), the air stage and the clock. World
// checks its arguments and calls these.
class World::Impl {
 public:
  explicit Impl(const WorldParams& p) : params_(p), air_(p.air.model) {}
  ~Impl() { bodies_.clear(); }

  const WorldParams& params() const { return params_; }
  std::uint64_t stepCount() const { return time_steps_; }

  // ---- creatures -----------------------------------------------------------------
  bool has(const std::string& name) const {
    for (const auto& r : records_) {
      if (r.name == name) return true;
    }
    return false;
  }

  std::vector<std::string> names() const {
    std::vector<std::string> names;
    for (const auto& r : records_) names.push_back(r.name);
    return names;
  }

  // The frames, colliders, contacts, servo history and momentum bookkeeping of a body whose
  // state was set from outside a step: what comes next depends on the new state alone, as
  // for a body just built.
  static void settle(CreatureBody& b) {
    b.updateKinematics();
    ServoWorld& world = b.scene->world();
    world.placeColliders();
    for (auto& col : b.colliders) {
      world.updateSingleAabb(col.get());
      if (col->getBroadphaseHandle()) {
        world.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(
            col->getBroadphaseHandle(), world.getDispatcher());
      }
    }
    b.solution = ServoSolution();
    b.last_step = 1.0;
    b.forgetMomentum();
  }

  const CreatureModelPtr& model(const std::string& name) const {
    return records_[index(name)].model;
  }

  void spawn(const std::string& name, const CreatureModelPtr& model, const Pose& pose,
             const Twist& twist) {
    CreatureRecord r;
    r.name = name;
    r.model = model;
    r.pose = Pose{pose.position, pose.orientation.normalized()};
    r.twist = twist;
    r.drives.resize(model->joints.size());
    r.power.reset(model->joints.size());
    auto body = makeBody(r);
    records_.push_back(std::move(r));
    bodies_.push_back(std::move(body));
    snapshots_.emplace_back();
  }

  void remove(const std::string& name) {
    const size_t i = index(name);
    bodies_.erase(bodies_.begin() + static_cast<long>(i));
    records_.erase(records_.begin() + static_cast<long>(i));
    snapshots_.erase(snapshots_.begin() + static_cast<long>(i));
  }

  // Restarts every stroke and rebuilds every body from its record; time back to zero.
  void reset() {
    for (auto& r : records_) {
      for (auto& d : r.drives) d.stroke.reset();
      r.divergence.reset();
      r.reported = false;
      r.wrenches.clear();
      r.root_acceleration.setZero();
      r.power.reset(r.model->joints.size());
    }
    bodies_.clear();
    for (const auto& r : records_) bodies_.push_back(makeBody(r));
    time_steps_ = 0;
  }

  // ---- stepping ------------------------------------------------------------------
  // Creatures are independent: each thread steps a contiguous share of them through all
  // `steps`, so the result does not depend on the number of threads.
  void step(int steps) {
    const size_t n = bodies_.size();
    const size_t threads = std::min<size_t>(static_cast<size_t>(params_.threads), n);
    auto run = [this, steps](size_t first, size_t last) {
      for (int s = 0; s < steps; ++s) {
        const std::uint64_t number = time_steps_ + static_cast<std::uint64_t>(s) + 1;
        for (size_t i = first; i < last; ++i) stepOne(i, number);
      }
    };
    if (threads <= 1 || static_cast<size_t>(steps) * n < 64) {
      run(0, n);
    } else {
      std::vector<std::thread> pool;
      for (size_t t = 1; t < threads; ++t)
        pool.emplace_back(run, t * n / threads, (t + 1) * n / threads);
      run(0, n / threads);
      for (auto& th : pool) th.join();
    }
    time_steps_ += static_cast<std::uint64_t>(steps);
  }

  std::optional<Divergence> divergence(const std::string& creature) const {
    return records_[index(creature)].divergence;
  }

  std::vector<Divergence> takeDivergences() {
    std::vector<Divergence> out;
    for (auto& r : records_) {
      if (!r.divergence || r.reported) continue;
      r.reported = true;
      out.push_back(*r.divergence);
    }
    return out;
  }

  // ---- air -----------------------------------------------------------------------
  void setAirParams(const AirParams& air) {
    const bool surfaces_changed = air.added_mass != params_.air.added_mass ||
                                  air.subdivisions_u != params_.air.subdivisions_u ||
                                  air.subdivisions_v != params_.air.subdivisions_v ||
                                  air.drag_coefficient != params_.air.drag_coefficient;
    if (air.model != params_.air.model) air_.setDefaultModel(makeAirModel(air.model));
    params_.air = air;
    if (surfaces_changed) {
      // Rebuild the aero surfaces of every creature, keeping its motion state.
      for (size_t i = 0; i < records_.size(); ++i) {
        resurface(bodies_[i]->aero, *records_[i].model, air);
      }
    }
  }

  void setAirModel(AirModelPtr model) { air_.setDefaultModel(std::move(model)); }

  void setGravity(const Vec3& gravity) {
    params_.gravity = gravity;
    for (auto& b : bodies_) b->scene->world().setGravity(toBt(gravity));
  }
  void setRecordCells(bool on) { air_.setRecordCells(on); }

  std::vector<LinkAero> aeroForces(const std::string& creature) const {
    std::vector<LinkAero> out;
    for (const AeroBody& a : bodies_[index(creature)]->aero) out.push_back(a.last);
    return out;
  }

  // ---- drives --------------------------------------------------------------------
  // Strokes on the wing joints `targets` (checked by checkWingCommands).
  void setStrokes(const std::string& creature, const std::vector<int>& targets,
                  const std::vector<StrokeCommand>& commands) {
    CreatureRecord& r = records_[index(creature)];
    for (size_t i = 0; i < commands.size(); ++i) {
      JointDrive& d = r.drives[targets[i]];
      if (d.mode != JointDrive::Mode::kStroke) {
        d.stroke.reset();
        d.mode = JointDrive::Mode::kStroke;
      }
      d.stroke.setCommand(commands[i]);
    }
  }

  void setVelocityTarget(const std::string& creature, const std::string& joint, double velocity) {
    const size_t c = index(creature);
    const int j = jointIndex(c, joint);
    if (!records_[c].model->joints[j].movable()) {
      throw InputError("joint '" + joint + "' of creature '" + creature + "' is fixed");
    }
    if (!std::isfinite(velocity) || std::abs(velocity) > kMaxStrokeRate) {
      throw InputError("joint '" + joint + "': velocity must be finite and within +-1e5");
    }
    JointDrive& d = records_[c].drives[j];
    d.mode = JointDrive::Mode::kVelocity;
    d.velocity = velocity;
  }

  void clearDrive(const std::string& creature, const std::string& joint) {
    const size_t c = index(creature);
    records_[c].drives[jointIndex(c, joint)] = JointDrive();
  }

  StrokeCommand wingCommand(const std::string& creature, const std::string& joint) const {
    const size_t c = index(creature);
    const JointDrive& d = records_[c].drives[jointIndex(c, joint)];
    return d.mode == JointDrive::Mode::kStroke ? d.stroke.command() : StrokeCommand();
  }

  // ---- state ---------------------------------------------------------------------
  // Reads the body without changing it (the link frames are computed into locals).
  CreatureState state(const std::string& creature) const {
    const size_t c = index(creature);
    const CreatureModel& m = *records_[c].model;
    const CreatureBody& b = *bodies_[c];
    const LinkFrames frames = b.currentFrames();
    CreatureState s;
    const size_t n = m.links.size();
    s.link_poses.resize(n);
    s.link_twists.resize(n);
    for (size_t k = 0; k < n; ++k) {
      const BodyKinematics kin = frames.kinematics(static_cast<int>(k));
      const Quat q = kin.orientation.normalized();
      const Vec3 origin = kin.com - q * m.links[k].com;
      s.link_poses[k] = Pose{origin, q};
      s.link_twists[k] = Twist{kin.linear_velocity + kin.angular_velocity.cross(origin - kin.com),
                               kin.angular_velocity};
    }
    jointState(m, b, s);
    return s;
  }

  // `request` checked by World::setState, but for what needs the body: the link, a fixed
  // base, the speed limit.
  void setState(const std::string& creature, const StateRequest& request) {
    const size_t c = index(creature);
    CreatureRecord& r = records_[c];
    const CreatureModel& m = *r.model;
    CreatureBody& b = *bodies_[c];
    const int k = request.link.empty() ? 0 : m.findLink(request.link);
    if (k < 0) {
      throw InputError("creature '" + creature + "' has no link '" + request.link + "'");
    }
    if (m.fixed_base &&
        (k != 0 || request.twist.linear != Vec3::Zero() || request.twist.angular != Vec3::Zero())) {
      throw InputError("creature '" + creature +
                       "' has a fixed base: only its root's pose can be set, with a zero twist");
    }
    BodySnapshot before;
    before.take(*b.mb);
    for (size_t j = 0; j < m.joints.size(); ++j) {
      if (!m.joints[j].movable()) continue;
      const int l = m.joints[j].child_link - 1;
      if (!request.joint_positions.empty()) b.mb->setJointPos(l, request.joint_positions[j]);
      if (!request.joint_velocities.empty()) b.mb->setJointVel(l, request.joint_velocities[j]);
    }
    // Link k relative to the root (base at the origin, at rest): the base follows from it,
    // and the result does not depend on where the creature was.
    b.mb->setBaseWorldTransform(toBt(Pose()));
    b.mb->setBaseVel(btVector3(0, 0, 0));
    b.mb->setBaseOmega(btVector3(0, 0, 0));
    b.updateKinematics();
    const BodyKinematics rel = b.frames.kinematics(k);
    const Quat q = request.pose.orientation.normalized();
    const Pose wanted{request.pose.position + q * m.links[k].com, q};  // link k's COM frame
    const Pose base = k == 0 ? wanted : wanted * Pose{rel.com, rel.orientation}.inverse();
    b.mb->setBaseWorldTransform(toBt(base));
    b.updateKinematics();
    // Velocities are linear in the base twist and the joint rates: the base twist is what
    // the wanted one lacks after the joints' share (base at rest).
    const BodyKinematics now = b.frames.kinematics(k);
    const Vec3 omega = request.twist.angular - now.angular_velocity;
    const Vec3 com_velocity =
        request.twist.linear + request.twist.angular.cross(now.com - request.pose.position);
    const Vec3 velocity = com_velocity - omega.cross(now.com - base.position) - now.linear_velocity;
    if (!m.fixed_base) {
      b.mb->setBaseVel(toBt(velocity));
      b.mb->setBaseOmega(toBt(omega));
    }
    b.updateKinematics();
    const std::string fault = checkMotion(m, b, params_.max_speed);
    if (!fault.empty()) {
      before.restore(*b.mb);
      settle(b);
      throw InputError("creature '" + creature + "': state refused, " + fault);
    }
    settle(b);
    r.divergence.reset();
    r.reported = false;
    r.root_acceleration.setZero();
  }

  void applyWrench(const std::string& creature, const ExternalWrench& w) {
    const size_t c = index(creature);
    CreatureRecord& r = records_[c];
    const CreatureModel& m = *r.model;
    const int k = w.link.empty() ? 0 : m.findLink(w.link);
    if (k < 0) throw InputError("creature '" + creature + "' has no link '" + w.link + "'");
    const double steps = w.duration < 0.0 ? -1.0 : std::round(w.duration / params_.step_size);
    if (w.duration >= 0.0 && steps < 1.0) {
      throw InputError("creature '" + creature + "': wrench duration " +
                       std::to_string(w.duration) + " s is shorter than half a step");
    }
    const BodyKinematics kin = bodies_[c]->frames.kinematics(k);
    ActiveWrench a;
    a.link = k;
    a.force = w.force;
    a.torque = w.torque;
    a.offset = kin.orientation.conjugate() * (w.point - kin.com);
    a.steps_left = static_cast<std::int64_t>(steps);
    r.wrenches.push_back(a);
  }

  int clearWrenches(const std::string& creature, const std::string& link) {
    int removed = 0;
    for (size_t c = 0; c < records_.size(); ++c) {
      CreatureRecord& r = records_[c];
      if (!creature.empty() && r.name != creature) continue;
      const int k = link.empty() ? -1 : r.model->findLink(link);
      const size_t before = r.wrenches.size();
      r.wrenches.erase(std::remove_if(r.wrenches.begin(), r.wrenches.end(),
                                      [k](const ActiveWrench& w) { return k < 0 || w.link == k; }),
                       r.wrenches.end());
      removed += static_cast<int>(before - r.wrenches.size());
    }
    return removed;
  }

  int wrenchCount(const std::string& creature) const {
    return static_cast<int>(records_[index(creature)].wrenches.size());
  }

  Vec3 rootAcceleration(const std::string& creature) const {
    return records_[index(creature)].root_acceleration;
  }

  CreaturePower power(const std::string& creature) const {
    const CreatureRecord& r = records_[index(creature)];
    return r.power.report(r.model->totalMass());
  }

 private:
  std::unique_ptr<CreatureBody> makeBody(const CreatureRecord& r) const {
    return buildBody(*r.model, r.pose, r.twist, params_);
  }

  // One step of creature i: drives, air, then Bullet's step (with the servos and the
  // fluid's implicit part inside), then the momentum correction. The link frames of the
  // start of the step (for the air, the servos and the ground check) are those the last
  // step ended with, or the body was built with.
  // A step in which a wing reverses is taken in substeps of at most turn_substep, the
  // first ending where the first stroke turns. A creature whose step ends non-finite or too
  // fast is put back as it was before the step and frozen (the watchdog).
  void stepOne(size_t i, std::uint64_t number) {
    CreatureRecord& r = records_[i];
    if (r.divergence) return;
    CreatureBody& b = *bodies_[i];
    snapshots_[i].take(*b.mb);
    r.power.beginStep();
    const double dt = params_.step_size, most = params_.turn_substep;
    const StrokeTurn turn = most > 0.0 ? strokeTurn(*r.model, r.drives, b, dt) : StrokeTurn();
    if (!turn.reversing) {
      subStep(i, dt);
    } else {
      // Pieces shorter than this are merged into the next: a turn at the very start or end.
      const double shortest = 1e-6 * dt;
      const double first =
          turn.first_turn < shortest || turn.first_turn > dt - shortest ? 0.0 : turn.first_turn;
      for (double length : {first, dt - first}) {
        if (length <= 0.0) continue;
        const int pieces = static_cast<int>(std::ceil(length / most * (1.0 - 1e-12)));
        for (int s = 0; s < pieces; ++s) subStep(i, length / pieces);
      }
    }
    countDown(r.wrenches);
    std::string fault = checkMotion(*r.model, b, params_.max_speed);
    if (fault.empty()) {
      r.root_acceleration = fromBt(b.mb->getBaseVel() - snapshots_[i].velocity) / dt;
      r.power.endStep(dt);
      return;
    }
    r.power.undoStep();
    snapshots_[i].restore(*b.mb);
    b.updateKinematics();
    b.forgetMomentum();
    r.root_acceleration.setZero();
    r.divergence = Divergence{r.name, number, std::move(fault)};
  }

  // One step of every wrench taken; those whose time is up removed.
  static void countDown(std::vector<ActiveWrench>& wrenches) {
    for (ActiveWrench& w : wrenches) {
      if (w.steps_left > 0) --w.steps_left;
    }
    wrenches.erase(std::remove_if(wrenches.begin(), wrenches.end(),
                                  [](const ActiveWrench& w) { return w.steps_left == 0; }),
                   wrenches.end());
  }

  // The external wrenches of a creature on its links (frames of the start of the step), and
  // in its momentum balance.
  static void applyWrenches(const std::vector<ActiveWrench>& wrenches, CreatureBody& b) {
    for (const ActiveWrench& w : wrenches) {
      const BodyKinematics kin = b.frames.kinematics(w.link);
      const Vec3 arm = kin.orientation * w.offset;
      const Wrench about_com{w.force, w.torque + arm.cross(w.force)};
      b.addExternal(kin.com, about_com);
      if (w.link == 0) {
        b.mb->addBaseForce(toBt(about_com.force));
        b.mb->addBaseTorque(toBt(about_com.torque));
      } else {
        b.mb->addLinkForce(w.link - 1, toBt(about_com.force));
        b.mb->addLinkTorque(w.link - 1, toBt(about_com.torque));
      }
    }
  }

  void subStep(size_t i, double h) {
    CreatureBody& b = *bodies_[i];
    CreatureRecord& r = records_[i];
    r.power.beginSubStep(*r.model, b);
    b.beginStep(params_.air.enabled ? params_.air.density : 0.0);
    applyDrives(*r.model, r.drives, b, h);
    b.fluid_active = false;
    if (params_.air.enabled) air_.apply(b, params_, h);
    applyWrenches(r.wrenches, b);
    b.scene->world().step(h);
    b.endStep(params_.gravity, h);
    r.power.endSubStep(*r.model, r.drives, b, h);
  }

  void jointState(const CreatureModel& m, const CreatureBody& b, CreatureState& s) const {
    s.joint_positions.assign(m.joints.size(), 0.0);
    s.joint_velocities.assign(m.joints.size(), 0.0);
    s.joint_efforts.assign(m.joints.size(), 0.0);
    const std::vector<double>& impulse = b.solution.impulse;
    for (size_t j = 0; j < m.joints.size(); ++j) {
      if (!m.joints[j].movable()) continue;
      const int k = m.joints[j].child_link;
      s.joint_positions[j] = b.mb->getJointPos(k - 1);
      s.joint_velocities[j] = b.mb->getJointVel(k - 1);
      if (static_cast<size_t>(k) < impulse.size()) {
        s.joint_efforts[j] = impulse[k] / b.last_step;
      }
    }
  }

  size_t index(const std::string& name) const {
    for (size_t i = 0; i < records_.size(); ++i) {
      if (records_[i].name == name) return i;
    }
    throw InputError("unknown creature '" + name + "'");
  }

  int jointIndex(size_t c, const std::string& joint) const {
    const CreatureModel& m = *records_[c].model;
    int j = m.findJoint(joint);
    if (j < 0) throw InputError("creature '" + records_[c].name + "' has no joint '" + joint + "'");
    return j;
  }

  WorldParams params_;
  AirStage air_;
  std::vector<CreatureRecord> records_;
  std::vector<std::unique_ptr<CreatureBody>> bodies_;
  std::vector<BodySnapshot> snapshots_;  // per creature: its state before the current step
  std::uint64_t time_steps_ = 0;
};

// ---- World ---------------------------------------------------------------------------

namespace {
WorldParams checked(const WorldParams& p) {
  std::string err = validateWorldParams(p);
  if (!err.empty()) throw InputError(err);
  return p;
}
}  // namespace

World::World(const WorldParams& params) : impl_(std::make_unique<Impl>(checked(params))) {}
World::~World() = default;

void World::spawn(const std::string& name, CreatureModelPtr model, const Pose& pose,
                  const Twist& twist) {
  if (name.empty()) throw InputError("creature name is empty");
  if (!model) throw InputError("creature '" + name + "': no model");
  if (has(name)) throw InputError("creature name '" + name + "' is taken");
  if (!finite(pose.position) || pose.position.cwiseAbs().maxCoeff() > kMaxPosition) {
    throw InputError("creature '" + name + "': position must be finite, each coordinate within " +
                     "+-1e6 m");
  }
  const double norm = pose.orientation.coeffs().allFinite() ? pose.orientation.norm() : NAN;
  if (!(norm >= 1e-6 && norm <= 1e6)) {
    std::ostringstream msg;
    msg << "creature '" << name << "': orientation quaternion has norm " << norm
        << " (must be finite and between 1e-6 and 1e6; it is normalised)";
    throw InputError(msg.str());
  }
  const double max_speed = impl_->params().max_speed;
  if (!finite(twist.linear) || twist.linear.norm() > max_speed) {
    throw InputError("creature '" + name +
                     "': linear twist must be finite and at most max_speed (" +
                     std::to_string(max_speed) + " m/s)");
  }
  if (!finite(twist.angular) || twist.angular.norm() > kMaxSpin) {
    throw InputError("creature '" + name + "': angular twist must be finite and at most 1e5 rad/s");
  }
  const std::string cells =
      checkCells(name, *model, impl_->params().air, impl_->params().max_cells);
  if (!cells.empty()) throw InputError(cells);
  try {
    impl_->spawn(name, model, pose, twist);
  } catch (const std::bad_alloc&) {
    throw InputError("creature '" + name + "': out of memory while building it");
  }
}

void World::remove(const std::string& name) { impl_->remove(name); }
bool World::has(const std::string& name) const { return impl_->has(name); }
std::vector<std::string> World::creatureNames() const { return impl_->names(); }
CreatureModelPtr World::model(const std::string& name) const { return impl_->model(name); }
void World::reset() { impl_->reset(); }

void World::step(int steps) {
  if (steps < 0) throw InputError("step count must be >= 0");
  impl_->step(steps);
}

double World::time() const {
  return static_cast<double>(impl_->stepCount()) * impl_->params().step_size;
}
std::uint64_t World::stepCount() const { return impl_->stepCount(); }
const WorldParams& World::params() const { return impl_->params(); }

std::optional<Divergence> World::divergence(const std::string& creature) const {
  return impl_->divergence(creature);
}
std::vector<Divergence> World::takeDivergences() { return impl_->takeDivergences(); }

void World::setAirParams(const AirParams& air) {
  std::string err = checkAir(air);
  if (!err.empty()) throw InputError(err);
  for (const std::string& name : impl_->names()) {
    err = checkCells(name, *impl_->model(name), air, impl_->params().max_cells);
    if (!err.empty()) throw InputError("air change refused: " + err);
  }
  impl_->setAirParams(air);
}

void World::setGravity(const Vec3& gravity) {
  if (!finite(gravity) || gravity.norm() > kMaxGravity) {
    throw InputError("gravity must be finite and at most 1e4 m/s^2");
  }
  impl_->setGravity(gravity);
}

void World::setAirModel(AirModelPtr model) {
  if (!model) throw InputError("air model is null");
  impl_->setAirModel(std::move(model));
}

std::vector<int> checkWingCommands(const CreatureModel& model,
                                   const std::vector<std::string>& joints,
                                   const std::vector<StrokeCommand>& commands) {
  std::vector<int> targets;
  if (joints.empty()) {
    targets = model.wing_joints;
  } else {
    for (const std::string& name : joints) {
      const int j = model.findJoint(name);
      if (j < 0) throw InputError("no joint '" + name + "'");
      if (!model.joints[j].wing) throw InputError("joint '" + name + "' is not a wing joint");
      if (std::find(targets.begin(), targets.end(), j) != targets.end()) {
        throw InputError("joint '" + name + "' is named twice");
      }
      targets.push_back(j);
    }
  }
  if (targets.size() != commands.size()) {
    throw InputError(std::to_string(commands.size()) + " commands for " +
                     std::to_string(targets.size()) + " wing joints");
  }
  for (size_t i = 0; i < commands.size(); ++i) {
    const JointModel& j = model.joints[targets[i]];
    const std::string err = validateStroke(commands[i]);
    if (!err.empty()) throw InputError("joint '" + j.name + "': " + err);
    // The stroke turns where the wing reaches offset -+ amplitude: beyond a limit the wing
    // would rest on its stop with the motor pushing, and never turn.
    const double amplitude = commands[i].amplitude, offset = commands[i].offset;
    if (j.limited && j.lower < j.upper &&
        (offset + amplitude >= j.upper || offset - amplitude <= j.lower)) {
      std::ostringstream msg;
      msg << "joint '" << j.name << "': amplitude " << amplitude;
      if (offset != 0.0) msg << " about offset " << offset;
      msg << " rad does not fit inside its limits [" << j.lower << ", " << j.upper << "]";
      throw InputError(msg.str());
    }
  }
  return targets;
}

void World::setWingCommands(const std::string& creature, const std::vector<std::string>& joints,
                            const std::vector<StrokeCommand>& commands) {
  const CreatureModelPtr& model = impl_->model(creature);
  std::vector<int> targets;
  try {
    targets = checkWingCommands(*model, joints, commands);
  } catch (const InputError& e) {
    throw InputError("creature '" + creature + "': " + e.what());
  }
  impl_->setStrokes(creature, targets, commands);
}

void World::setJointVelocityTarget(const std::string& creature, const std::string& joint,
                                   double velocity) {
  impl_->setVelocityTarget(creature, joint, velocity);
}

void World::clearJointCommand(const std::string& creature, const std::string& joint) {
  impl_->clearDrive(creature, joint);
}

StrokeCommand World::wingCommand(const std::string& creature, const std::string& joint) const {
  return impl_->wingCommand(creature, joint);
}

CreatureState World::state(const std::string& creature) const { return impl_->state(creature); }

namespace {

// Empty if `values` (named `what`, one per model joint or none) is valid, else why not.
std::string checkJointValues(const CreatureModel& m, const std::vector<double>& values,
                             const std::string& what, bool positions) {
  if (values.empty()) return "";
  if (values.size() != m.joints.size()) {
    return std::to_string(values.size()) + " " + what + " for " + std::to_string(m.joints.size()) +
           " joints (give one per joint, in URDF order, or none)";
  }
  for (size_t j = 0; j < values.size(); ++j) {
    const JointModel& joint = m.joints[j];
    std::ostringstream msg;
    msg << "joint '" << joint.name << "': " << what << " " << values[j];
    if (!std::isfinite(values[j])) return msg.str() + " is not finite";
    if (!joint.movable()) {
      if (values[j] != 0.0) return msg.str() + " must be 0 (a fixed joint)";
      continue;
    }
    if (!positions) {
      if (std::abs(values[j]) > kMaxSpin) return msg.str() + " is beyond +-1e5";
    } else if (joint.limited && joint.lower < joint.upper &&
               (values[j] < joint.lower || values[j] > joint.upper)) {
      msg << " is outside its limits [" << joint.lower << ", " << joint.upper << "]";
      return msg.str();
    } else if (std::abs(values[j]) > kMaxPosition) {
      return msg.str() + " is beyond +-1e6";
    }
  }
  return "";
}

// Empty if the pose is finite, in range and has a usable quaternion, else why not.
std::string checkPose(const Pose& pose) {
  if (!finite(pose.position) || pose.position.cwiseAbs().maxCoeff() > kMaxPosition) {
    return "position must be finite, each coordinate within +-1e6 m";
  }
  const double norm = pose.orientation.coeffs().allFinite() ? pose.orientation.norm() : NAN;
  if (!(norm >= 1e-6 && norm <= 1e6)) {
    std::ostringstream msg;
    msg << "orientation quaternion has norm " << norm
        << " (must be finite and between 1e-6 and 1e6; it is normalised)";
    return msg.str();
  }
  return "";
}

}  // namespace

void World::setState(const std::string& creature, const StateRequest& request) {
  const CreatureModel& m = *impl_->model(creature);  // InputError if unknown
  const std::string prefix = "creature '" + creature + "': ";
  std::string err = checkPose(request.pose);
  if (!err.empty()) throw InputError(prefix + err);
  const double max_speed = impl_->params().max_speed;
  if (!finite(request.twist.linear) || request.twist.linear.norm() > max_speed) {
    throw InputError(prefix + "linear twist must be finite and at most max_speed (" +
                     std::to_string(max_speed) + " m/s)");
  }
  if (!finite(request.twist.angular) || request.twist.angular.norm() > kMaxSpin) {
    throw InputError(prefix + "angular twist must be finite and at most 1e5 rad/s");
  }
  err = checkJointValues(m, request.joint_positions, "joint_positions", true);
  if (err.empty()) err = checkJointValues(m, request.joint_velocities, "joint_velocities", false);
  if (!err.empty()) throw InputError(prefix + err);
  impl_->setState(creature, request);
}

void World::applyWrench(const std::string& creature, const ExternalWrench& wrench) {
  impl_->model(creature);  // InputError if unknown
  const std::string prefix = "creature '" + creature + "': wrench ";
  if (!finite(wrench.force) || wrench.force.norm() > kMaxForce) {
    throw InputError(prefix + "force must be finite and at most 1e6 N");
  }
  if (!finite(wrench.torque) || wrench.torque.norm() > kMaxTorque) {
    throw InputError(prefix + "torque must be finite and at most 1e6 N m");
  }
  if (!finite(wrench.point) || wrench.point.cwiseAbs().maxCoeff() > kMaxPosition) {
    throw InputError(prefix + "point must be finite, each coordinate within +-1e6 m");
  }
  if (!std::isfinite(wrench.duration) || wrench.duration > 1e9) {
    throw InputError(prefix + "duration must be finite and at most 1e9 s (< 0: until cleared)");
  }
  impl_->applyWrench(creature, wrench);
}

int World::clearWrenches(const std::string& creature, const std::string& link) {
  if (!creature.empty()) {
    const CreatureModel& m = *impl_->model(creature);  // InputError if unknown
    if (!link.empty() && m.findLink(link) < 0) {
      throw InputError("creature '" + creature + "' has no link '" + link + "'");
    }
  } else if (!link.empty()) {
    throw InputError("a link ('" + link + "') needs its creature");
  }
  return impl_->clearWrenches(creature, link);
}

int World::wrenchCount(const std::string& creature) const { return impl_->wrenchCount(creature); }

Vec3 World::rootAcceleration(const std::string& creature) const {
  return impl_->rootAcceleration(creature);
}
CreaturePower World::power(const std::string& creature) const { return impl_->power(creature); }
Pose World::rootPose(const std::string& creature) const { return state(creature).link_poses[0]; }
Twist World::rootTwist(const std::string& creature) const { return state(creature).link_twists[0]; }

void World::setRecordCellForces(bool on) { impl_->setRecordCells(on); }

std::vector<LinkAero> World::aeroForces(const std::string& creature) const {
  return impl_->aeroForces(creature);
}

}  // namespace flapsim
