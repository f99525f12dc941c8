#include "world/creature_step.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace flapsim {

CreatureSim::CreatureSim(const CreatureModel& m, const Pose& pose, const Twist& twist,
                         const WorldParams& params)
    : body(m, pose, twist, params),
      servos(m, params),
      fluid(m, params.air),
      momentum(m),
      transmitted(m),
      record(m) {
  power.reset(m.joints.size());
}

CreatureEnergy creatureEnergy(const CreatureModel& m, const CreatureSim& s,
                              const WorldParams& params) {
  CreatureEnergy e;
  stateEnergies(m, s.body, s.fluid, s.servos, params.air, params.gravity, s.last_piece, e);
  e.motor_work = s.power.report(m.totalMass()).totalWork();
  e.air_work = s.energy.airWork();
  e.damping_work = s.energy.dampingWork();
  return e;
}

void CreatureSim::settle() {
  body.settle();
  servos.forget();
  momentum.forget();
  transmitted.forget();
  last_piece = 0.0;
  fluid.forgetFlow();
  record.clear();
}

namespace {

// The external stage: the user's wrenches on their links (frames of the step's start), and
// in the momentum balance (and the transmitted work's, `metered`) over the (sub)step of `h`.
void applyWrenches(const std::vector<ActiveWrench>& wrenches, CreatureSim& s, bool metered,
                   double h) {
  btMultiBody& mb = s.body.multiBody();
  for (const ActiveWrench& w : wrenches) {
    if (!w.started) continue;  // waiting for its start time
    const BodyKinematics kin = s.body.frames().kinematics(w.link);
    const Vec3 arm = kin.orientation * w.offset;
    const Wrench about_com{w.force, w.torque + arm.cross(w.force)};
    s.momentum.addExternal(kin.com, about_com);
    s.record.external(w.link, kin.com, about_com);
    if (metered) {
      Vec6 impulse;
      impulse << h * about_com.torque, h * about_com.force;
      s.transmitted.addImpulse(w.link, kin.com, impulse);
    }
    if (w.link == 0) {
      mb.addBaseForce(toBt(about_com.force));
      mb.addBaseTorque(toBt(about_com.torque));
    } else {
      mb.addLinkForce(w.link - 1, toBt(about_com.force));
      mb.addLinkTorque(w.link - 1, toBt(about_com.torque));
    }
  }
}

// One (sub)step of `h`, stage by stage (see creature_step.h).
void subStep(CreatureRecord& r, CreatureSim& s, const StepContext& c, double h) {
  const WorldParams& p = c.params;
  btMultiBody& mb = s.body.multiBody();
  ServoWorld& world = s.body.world();
  const double density = p.air.enabled ? p.air.density : 0.0;
  const bool metered = p.motor_work == MotorWorkMeter::kTransmitted &&
                       (density <= 0.0 || p.air.addedMassVelocityProducts() || !s.fluid.carries());
  s.last_piece = h;
  // position: the frames of the start are those the last (sub)step ended with; the momentum
  // carries the creature's Munk term with Kirchhoff's products, not where the plates shed them
  s.momentum.begin(s.body, s.fluid, density, p.air.wind, p.air.added_mass_products);
  if (metered) s.transmitted.beginSubStep(s.body, s.fluid, density, p.air.wind);
  s.servos.begin(mb, h);
  s.record.beginSubStep(s.body.frames(), h);
  if (c.energy_audit) s.energy.beginSubStep(*r.model, s.body);
  applyDrives(*r.model, r.drives, s.servos, mb, h);          // actuation
  c.air.apply(*r.model, s.body, s.fluid, s.momentum, p, h);  // fluid
  s.record.fluid(s.fluid, p.air.enabled);
  applyWrenches(r.wrenches, s, metered, h);  // external
  // velocities, then servos (none in a step too short for Bullet to take: nothing moves)
  if (world.beginStep(h)) {
    s.momentum.setDragImpulse(s.servos.solve(mb, s.body.frames(), world.leanTree(), s.fluid));
    s.record.servos(s.servos, s.fluid);
  }
  world.constrain();  // constraints
  s.record.contact(s.body.hasContacts());
  world.integrate();                                         // positions
  s.servos.integrateSaturated(mb, s.body.hasContacts(), h);  // saturated
  s.momentum.end(s.body, s.fluid, p.gravity, h);             // momentum
  if (metered) {                                             // power
    s.transmitted.endSubStep(s.body, s.fluid, s.servos, p.air.enabled, p.gravity,
                             s.body.hasContacts() || world.constraintsSolved(), h);
  }
  s.power.endSubStep(*r.model, r.drives, mb, s.servos, metered ? &s.transmitted : nullptr, h);
  if (c.energy_audit) {  // energy
    s.energy.endSubStep(*r.model, r.drives, s.body, s.fluid, s.servos, p.air.enabled, p.air.wind,
                        h);
  }
}

// The wrenches whose start time this step (starting at `time`) reaches start acting.
void startDue(std::vector<ActiveWrench>& wrenches, double time) {
  for (ActiveWrench& w : wrenches) w.started = w.started || startsWrench(time, w.start_time);
}

// One step of every wrench acting taken; those whose time is up removed.
void countDown(std::vector<ActiveWrench>& wrenches) {
  for (ActiveWrench& w : wrenches) {
    if (w.started && w.steps_left > 0) --w.steps_left;
  }
  wrenches.erase(std::remove_if(wrenches.begin(), wrenches.end(),
                                [](const ActiveWrench& w) { return w.steps_left == 0; }),
                 wrenches.end());
}

}  // namespace

ActiveWrench activeWrench(const ExternalWrench& w, int link, const BodyKinematics& kin,
                          double step_size) {
  const double steps = w.duration < 0.0 ? -1.0 : std::max(1.0, std::round(w.duration / step_size));
  ActiveWrench a;
  a.link = link;
  a.force = w.force;
  a.torque = w.torque;
  a.offset = kin.orientation.conjugate() * (w.point - kin.com);
  a.steps_left = static_cast<std::int64_t>(steps);
  a.start_time = w.start_time;
  return a;
}

std::uint64_t firstWrenchStep(double start_time, double step_size, std::uint64_t next) {
  const double k = std::ceil((start_time - kWrenchStartTolerance) / step_size);
  std::uint64_t n = k > static_cast<double>(next) ? static_cast<std::uint64_t>(k) : next;
  while (n > next && startsWrench(static_cast<double>(n - 1) * step_size, start_time)) --n;
  while (!startsWrench(static_cast<double>(n) * step_size, start_time)) ++n;
  return n;
}

Vec3 creatureAirVelocity(const CreatureSim& s, const AirParams& air, double time) {
  Vec3 velocity = air.wind + gustVelocity(air.gust, time);
  if (s.turbulence.active()) {
    velocity += s.turbulence.velocity(s.body.frames().kinematics(0).com, time, air.wind);
  }
  return velocity;
}

namespace {

// The step in an air of steady wind c.params.air.wind.
void stepInSteadyAir(CreatureRecord& r, CreatureSim& s, const StepContext& c,
                     std::uint64_t number) {
  s.before.take(s.body.multiBody());
  s.power.beginStep();
  s.record.beginStep(s.body.frames(), c.params.step_size);
  startDue(r.wrenches, c.time);  // wrenches
  const double dt = c.params.step_size, most = c.params.turn_substep;
  const StrokeTurn turn =
      most > 0.0 ? strokeTurn(*r.model, r.drives, s.servos, s.body.multiBody(), dt) : StrokeTurn();
  if (!turn.reversing) {
    subStep(r, s, c, dt);
  } else {
    // Pieces shorter than this are merged into the next: a turn at the very start or end.
    const double shortest = 1e-6 * dt;
    const double first =
        turn.first_turn < shortest || turn.first_turn > dt - shortest ? 0.0 : turn.first_turn;
    for (double length : {first, dt - first}) {
      if (length <= 0.0) continue;
      const int pieces = static_cast<int>(std::ceil(length / most * (1.0 - 1e-12)));
      for (int k = 0; k < pieces; ++k) subStep(r, s, c, length / pieces);
    }
  }
  countDown(r.wrenches);
  // watchdog
  std::string fault = s.body.motionFault(c.params.max_speed);
  if (fault.empty()) {
    r.root_acceleration = fromBt(s.body.multiBody().getBaseVel() - s.before.velocity) / dt;
    s.power.endStep(dt);
    s.record.endStep(s.power);
    return;
  }
  s.power.undoStep();
  s.record.clear();
  s.before.restore(s.body.multiBody());
  s.body.updateKinematics();
  s.servos.forget();  // a frozen creature is driven by nothing: no efforts of the refused step
  s.momentum.forget();
  s.transmitted.forget();
  s.last_piece = 0.0;
  r.root_acceleration.setZero();
  r.divergence = Divergence{r.name, number, std::move(fault)};
}

}  // namespace

void stepCreature(CreatureRecord& r, CreatureSim& s, const StepContext& c, std::uint64_t number) {
  if (r.divergence) return;  // check
  // air: a wind that is not steady is this step's uniform wind
  const Vec3 air = creatureAirVelocity(s, c.params.air, c.time);
  if (air == c.params.air.wind) {
    stepInSteadyAir(r, s, c, number);
    return;
  }
  WorldParams local = c.params;
  local.air.wind = air;
  stepInSteadyAir(r, s, StepContext{local, c.air, c.energy_audit, c.time}, number);
}

}  // namespace flapsim
