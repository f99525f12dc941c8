#include "flapsim/energy_audit.h"

#include <cmath>
#include <cstdio>

namespace flapsim {

EnergyAuditResult auditEnergy(const CreatureModelPtr& model, const EnergyAuditParams& p) {
  WorldParams params = p.world;
  params.ground = false;
  World w(params);
  w.setEnergyAudit(true);
  w.spawn("creature", model,
          Pose{Vec3(0.0, 0.0, p.height), Quat(Eigen::AngleAxisd(p.roll, Vec3::UnitX()))});
  w.setWingCommands("creature", {},
                    std::vector<StrokeCommand>(model->wing_joints.size(), p.stroke));
  EnergyAuditResult r;
  r.start = w.energy("creature");
  w.step(static_cast<int>(std::lround(p.seconds / params.step_size)));
  r.end = w.energy("creature");
  r.positive_motor_work = w.power("creature").totalPositiveWork();
  return r;
}

std::string energyAuditLine(const EnergyAuditResult& r) {
  char line[512];
  std::snprintf(line, sizeof line,
                "motor %+.4f J (positive %.4f) | air %+.4f | damping %+.4f | kinetic %+.4f | "
                "potential %+.4f | spring %+.4f | fluid kinetic %+.4f | residual %+.2e J = "
                "%+.3f %% of positive work",
                r.end.motor_work - r.start.motor_work, r.positive_motor_work,
                r.end.air_work - r.start.air_work, r.end.damping_work - r.start.damping_work,
                r.end.kinetic - r.start.kinetic, r.end.potential - r.start.potential,
                r.end.spring - r.start.spring, r.end.fluid_kinetic - r.start.fluid_kinetic,
                r.residual(), 100.0 * r.relativeResidual());
  return line;
}

}  // namespace flapsim
