#include "flapsim/world.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <thread>
#include <utility>

#include "world/command_timeouts.h"
#include "world/creature.h"
#include "world/creature_state.h"
#include "world/creature_step.h"
#include "world/fluid_stage.h"
#include "world/joint_drives.h"
#include "world/world_checks.h"

namespace flapsim {

// The creatures (records and their stages, in spawn order), the air stage and the clock.
// World checks its arguments and calls these.
class World::Impl {
 public:
  explicit Impl(const WorldParams& p) : params_(p), air_(p.air.model) {}
  ~Impl() { sims_.clear(); }

  const WorldParams& params() const { return params_; }
  std::uint64_t stepCount() const { return time_steps_; }

  // ---- creatures -----------------------------------------------------------------
  bool has(const std::string& name) const {
    return std::any_of(records_.begin(), records_.end(),
                       [&name](const CreatureRecord& r) { return r.name == name; });
  }

  std::vector<std::string> names() const {
    std::vector<std::string> names;
    for (const auto& r : records_) names.push_back(r.name);
    return names;
  }

  const CreatureModelPtr& model(const std::string& name) const {
    return records_[index(name)].model;
  }
  std::vector<JointDrive>& drives(const std::string& name) { return records_[index(name)].drives; }
  // Lapses the wing-command timeouts due now, in spawn order.
  void lapseDue(CommandTimeouts& timeouts) {
    for (size_t c = 0; c < records_.size() && timeouts.active(); ++c) {
      CreatureRecord& r = records_[c];
      if (!timeouts.due(r.name, time_steps_)) continue;
      const std::vector<double> q = readState(*r.model, *sims_[c]).joint_positions;
      timeouts.lapse(r.name, *r.model, r.drives, q, time_steps_);
    }
  }

  void spawn(const std::string& name, const CreatureModelPtr& model, const Pose& pose,
             const Twist& twist) {
    CreatureRecord r;
    r.name = name;
    r.model = model;
    r.pose = Pose{pose.position, pose.orientation.normalized()};
    r.twist = twist;
    r.drives.resize(model->joints.size());
    auto sim = build(r);
    records_.push_back(std::move(r));
    sims_.push_back(std::move(sim));
  }

  void remove(const std::string& name) {
    const size_t i = index(name);
    sims_.erase(sims_.begin() + static_cast<long>(i));
    records_.erase(records_.begin() + static_cast<long>(i));
  }

  // Restarts every stroke and rebuilds every creature's stages from its record; time back
  // to zero.
  void reset() {
    for (auto& r : records_) {
      for (auto& d : r.drives) d.stroke.reset();
      r.divergence.reset();
      r.reported = false;
      r.wrenches.clear();
      r.root_acceleration.setZero();
    }
    sims_.clear();
    for (const auto& r : records_) sims_.push_back(build(r));
    time_steps_ = 0;
  }

  // ---- stepping ------------------------------------------------------------------
  // Creatures are independent: each thread steps a contiguous share of them through all
  // `steps`, so the result does not depend on the number of threads.
  void step(int steps) {
    const size_t n = sims_.size();
    const size_t threads = std::min<size_t>(static_cast<size_t>(params_.threads), n);
    auto run = [this, steps](size_t first, size_t last) {
      for (int s = 0; s < steps; ++s) {
        const std::uint64_t number = time_steps_ + static_cast<std::uint64_t>(s) + 1;
        const double start = static_cast<double>(number - 1) * params_.step_size;
        const StepContext context{params_, air_, energy_audit_, start};
        for (size_t i = first; i < last; ++i) stepCreature(records_[i], *sims_[i], context, number);
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
    const bool geometry = air.added_mass != params_.air.added_mass ||
                          air.subdivisions_u != params_.air.subdivisions_u ||
                          air.subdivisions_v != params_.air.subdivisions_v;
    const bool drag = air.drag_coefficient != params_.air.drag_coefficient;
    const bool turbulence = air.turbulence != params_.air.turbulence;
    if (air.model != params_.air.model) air_.setDefaultModel(makeAirModel(air.model));
    params_.air = air;
    // The aero surfaces of every creature, keeping its motion state.
    for (size_t i = 0; i < records_.size() && (geometry || drag); ++i)
      sims_[i]->fluid.resurface(*records_[i].model, air, geometry);
    for (size_t i = 0; i < records_.size() && turbulence; ++i)
      sims_[i]->turbulence = turbulenceOf(records_[i].name);
  }

  void setAirModel(AirModelPtr model) { air_.setDefaultModel(std::move(model)); }

  void setGravity(const Vec3& gravity) {
    params_.gravity = gravity;
    for (auto& s : sims_) s->body.world().setGravity(toBt(gravity));
  }
  void setRecordCells(bool on) { air_.setRecordCells(on); }
  void setEnergyAudit(bool on) { energy_audit_ = on; }

  Vec3 airVelocity(const std::string& creature) const {
    return creatureAirVelocity(*sims_[index(creature)], params_.air, time());
  }
  double time() const { return static_cast<double>(time_steps_) * params_.step_size; }

  CreatureEnergy energy(const std::string& creature) const {
    const size_t c = index(creature);
    return creatureEnergy(*records_[c].model, *sims_[c], params_);
  }

  std::vector<LinkAero> aeroForces(const std::string& creature) const {
    std::vector<LinkAero> out;
    for (const AeroBody& a : sims_[index(creature)]->fluid.bodies()) out.push_back(a.last);
    return out;
  }
  const StepData& stepData(const std::string& creature) const {
    return sims_[index(creature)]->record.data();
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

  void hold(const std::string& creature, const std::string& joint) {
    const size_t c = index(creature);
    const int j = jointIndex(c, joint);
    if (!records_[c].model->joints[j].movable()) {
      throw InputError("joint '" + joint + "' of creature '" + creature + "' is fixed");
    }
    JointDrive& d = records_[c].drives[j];
    d.mode = JointDrive::Mode::kHold;
    d.position = readState(*records_[c].model, *sims_[c]).joint_positions[j];
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
  CreatureState state(const std::string& creature) const {
    const size_t c = index(creature);
    return readState(*records_[c].model, *sims_[c]);
  }

  void setState(const std::string& creature, const StateRequest& request) {
    const size_t c = index(creature);
    CreatureRecord& r = records_[c];
    placeCreature(creature, *r.model, *sims_[c], request, params_.max_speed);
    r.divergence.reset();
    r.reported = false;
    r.root_acceleration.setZero();
  }

  double applyWrench(const std::string& creature, const ExternalWrench& w) {
    const size_t c = index(creature);
    CreatureRecord& r = records_[c];
    const int k = w.link.empty() ? 0 : r.model->findFrame(w.link).link;
    if (k < 0) throw InputError("creature '" + creature + "' has no link '" + w.link + "'");
    if (r.wrenches.size() >= static_cast<size_t>(kMaxWrenches)) {
      throw InputError("creature '" + creature + "' has " + std::to_string(kMaxWrenches) +
                       " wrenches acting, the limit: clear some first");
    }
    r.wrenches.push_back(
        activeWrench(w, k, sims_[c]->body.frames().kinematics(k), params_.step_size));
    return static_cast<double>(firstWrenchStep(w.start_time, params_.step_size, time_steps_)) *
           params_.step_size;
  }

  int clearWrenches(const std::string& creature, const std::string& link) {
    int removed = 0;
    for (CreatureRecord& r : records_) {
      if (!creature.empty() && r.name != creature) continue;
      const int k = link.empty() ? -1 : r.model->findFrame(link).link;
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
    const size_t c = index(creature);
    return sims_[c]->power.report(records_[c].model->totalMass());
  }

 private:
  std::unique_ptr<CreatureSim> build(const CreatureRecord& r) const {
    auto sim = std::make_unique<CreatureSim>(*r.model, r.pose, r.twist, params_);
    sim->turbulence = turbulenceOf(r.name);
    return sim;
  }
  TurbulenceField turbulenceOf(const std::string& name) const {
    const TurbulenceParams& t = params_.air.turbulence;
    return TurbulenceField(t, turbulenceSeed(t, name));
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
  bool energy_audit_ = false;  // setEnergyAudit
  std::vector<CreatureRecord> records_;
  std::vector<std::unique_ptr<CreatureSim>> sims_;
  std::uint64_t time_steps_ = 0;
};

// ---- World ---------------------------------------------------------------------------

World::World(const WorldParams& params)
    : impl_(std::make_unique<Impl>(checked(params))),
      timeouts_(std::make_unique<CommandTimeouts>()) {}
World::~World() = default;

void World::spawn(const std::string& name, CreatureModelPtr model, const Pose& pose,
                  const Twist& twist) {
  if (name.empty()) throw InputError("creature name is empty");
  if (!model) throw InputError("creature '" + name + "': no model");
  if (has(name)) throw InputError("creature name '" + name + "' is taken");
  refuse(name, checkPose(pose));
  refuse(name, checkTwist(twist, impl_->params().max_speed));
  const std::string cells =
      checkCells(name, *model, impl_->params().air, impl_->params().max_cells);
  if (!cells.empty()) throw InputError(cells);
  // A massless URDF root (a CAD model's base_link) was lumped into the link it is fixed to:
  // the pose is still the root's frame, Gazebo's model frame, and the twist its origin's.
  Motion root{pose, twist};
  for (const LumpedLink& l : model->lumped) {
    if (l.joint.empty()) root = linkMotion(pose, twist, l.pose);
  }
  try {
    impl_->spawn(name, model, root.pose, root.twist);
  } catch (const std::bad_alloc&) {
    throw InputError("creature '" + name + "': out of memory while building it");
  }
}

void World::remove(const std::string& name) {
  impl_->remove(name);
  timeouts_->forget(name);
}
bool World::has(const std::string& name) const { return impl_->has(name); }
std::vector<std::string> World::creatureNames() const { return impl_->names(); }
CreatureModelPtr World::model(const std::string& name) const { return impl_->model(name); }
void World::reset() {
  for (const std::string& name : impl_->names()) timeouts_->restore(name, impl_->drives(name));
  timeouts_->restart();
  impl_->reset();
}

void World::step(int steps) {
  if (steps < 0) throw InputError("step count must be >= 0");
  // In stretches ending where a wing-command timeout falls due: it lapses at its step.
  for (std::uint64_t left = static_cast<std::uint64_t>(steps), k; left > 0; left -= k) {
    k = timeouts_->stepsToNext(stepCount(), left);
    impl_->step(static_cast<int>(k));
    impl_->lapseDue(*timeouts_);
  }
}

double World::time() const { return impl_->time(); }
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
  const std::string err = checkGravity(gravity);
  if (!err.empty()) throw InputError(err);
  impl_->setGravity(gravity);
}

void World::setAirModel(AirModelPtr model) {
  if (!model) throw InputError("air model is null");
  impl_->setAirModel(std::move(model));
}

void World::setWingCommands(const std::vector<CreatureWingCommand>& commands) {
  std::vector<std::vector<int>> targets;
  for (size_t i = 0; i < commands.size(); ++i) {
    const CreatureWingCommand& c = commands[i];
    const CreatureModelPtr& model = impl_->model(c.creature);  // InputError if unknown
    for (size_t k = 0; k < i; ++k) {
      if (commands[k].creature == c.creature) {
        throw InputError("creature '" + c.creature + "' is named twice");
      }
    }
    try {
      targets.push_back(checkWingCommands(*model, c.joints, c.strokes));
    } catch (const InputError& e) {
      throw InputError("creature '" + c.creature + "': " + e.what());
    }
  }
  for (size_t i = 0; i < commands.size(); ++i) {
    impl_->setStrokes(commands[i].creature, targets[i], commands[i].strokes);
    timeouts_->commanded(commands[i].creature, stepCount());
  }
}

void World::setJointVelocityTarget(const std::string& creature, const std::string& joint,
                                   double velocity) {
  impl_->setVelocityTarget(creature, joint, velocity);
}

void World::holdJoint(const std::string& creature, const std::string& joint) {
  impl_->hold(creature, joint);
}

void World::clearJointCommand(const std::string& creature, const std::string& joint) {
  impl_->clearDrive(creature, joint);
}

StrokeCommand World::wingCommand(const std::string& creature, const std::string& joint) const {
  return impl_->wingCommand(creature, joint);
}

CreatureState World::state(const std::string& creature) const { return impl_->state(creature); }

void World::setState(const std::string& creature, const StateRequest& request) {
  const CreatureModel& m = *impl_->model(creature);  // InputError if unknown
  refuse(creature, checkPose(request.pose));
  refuse(creature, checkTwist(request.twist, impl_->params().max_speed));
  std::string err = checkJointValues(m, request.joint_positions, "joint_positions", true);
  if (err.empty()) err = checkJointValues(m, request.joint_velocities, "joint_velocities", false);
  refuse(creature, err);
  impl_->setState(creature, request);
}

double World::applyWrench(const std::string& creature, const ExternalWrench& wrench) {
  impl_->model(creature);  // InputError if unknown
  const std::string err = checkWrench(wrench);
  if (!err.empty()) refuse(creature, "wrench " + err);
  return impl_->applyWrench(creature, wrench);
}

int World::clearWrenches(const std::string& creature, const std::string& link) {
  if (!creature.empty()) {
    const CreatureModel& m = *impl_->model(creature);  // InputError if unknown
    if (!link.empty() && m.findFrame(link).link < 0) {
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
void World::setEnergyAudit(bool on) { impl_->setEnergyAudit(on); }
CreatureEnergy World::energy(const std::string& creature) const { return impl_->energy(creature); }
Vec3 World::airVelocity(const std::string& creature) const { return impl_->airVelocity(creature); }

std::vector<LinkAero> World::aeroForces(const std::string& creature) const {
  return impl_->aeroForces(creature);
}
StepData World::stepData(const std::string& creature) const { return impl_->stepData(creature); }

}  // namespace flapsim
