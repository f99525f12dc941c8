// The energy audit a user runs (flapsim_bench --energy): a creature stroking its wings from a
// start in open sky, its motors' work against the change of its kinetic, potential, spring
// and fluid kinetic energy plus the air's and the damping's work (World::energy).
#pragma once

#include <string>

#include "flapsim/creature_model.h"
#include "flapsim/world.h"

namespace flapsim {

struct EnergyAuditParams {
  WorldParams world;  // its ground is taken away
  double seconds = 2.0;
  double height = 20.0;                   // m, of the root at the start
  double roll = 0.05;                     // rad, of the start
  StrokeCommand stroke{60.0, 10.0, 0.6};  // on every wing
};

struct EnergyAuditResult {
  CreatureEnergy start, end;
  double positive_motor_work = 0.0;  // J
  double residual() const { return end.residual(start); }
  /// The residual as a fraction of the motors' positive work (0 without any).
  double relativeResidual() const {
    return positive_motor_work > 0.0 ? residual() / positive_motor_work : 0.0;
  }
};

EnergyAuditResult auditEnergy(const CreatureModelPtr& model, const EnergyAuditParams& params);

/// One line of the audit's table: the changes, the works and the residual.
std::string energyAuditLine(const EnergyAuditResult& r);

}  // namespace flapsim
