// flapsim_bench --energy: the energy audit's table (see bench/flapsim_bench.cpp).
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/energy_audit.h"
#include "flapsim_bench.h"

namespace flapsim_bench {

bool parseMotorWork(const char* text, flapsim::MotorWorkMeter* out) {
  if (flapsim::motorWorkMeterFromName(text, out)) return true;
  std::fprintf(stderr, "flapsim_bench: --motor-work wants transmitted or servo, not '%s'\n", text);
  return false;
}

namespace {

int energyRows(const std::string& urdf, double seconds, flapsim::AddedMassProducts products,
               flapsim::MotorWorkMeter meter) {
  std::vector<std::string> files = {"flap_unit.urdf", "afc_4.urdf", "hover_1.urdf"};
  if (!urdf.empty()) files = {urdf};
  std::printf(
      "| creature | medium | step | motor work (positive) | air work | damping work | "
      "kinetic | potential | spring | fluid kinetic | residual |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& file : files) {
    const flapsim::CreatureModelPtr model =
        flapsim::loadCreatureModel(urdf.empty() ? urdfPath(file) : file);
    for (const char* medium : {"vacuum", "air", "water"}) {
      for (double dt : {0.001, 0.0005, 0.00025}) {
        flapsim::EnergyAuditParams p;
        p.seconds = seconds;
        p.world.step_size = dt;
        if (std::string(medium) == "vacuum") p.world.air.enabled = false;
        if (std::string(medium) == "water") {
          p.world.air = flapsim::waterParams();
          p.stroke = flapsim::StrokeCommand{3.0, 1.0, 0.6};
        }
        p.world.air.added_mass_products = products;
        p.world.motor_work = meter;
        const flapsim::EnergyAuditResult r = flapsim::auditEnergy(model, p);
        std::printf(
            "| %s | %s | %g ms | %+.4f J (%.4f) | %+.4f | %+.4f | %+.4f | %+.4f | %+.4f | %+.4f "
            "| %+.3f %% |\n",
            model->name.c_str(), medium, dt * 1e3, r.end.motor_work - r.start.motor_work,
            r.positive_motor_work, r.end.air_work - r.start.air_work,
            r.end.damping_work - r.start.damping_work, r.end.kinetic - r.start.kinetic,
            r.end.potential - r.start.potential, r.end.spring - r.start.spring,
            r.end.fluid_kinetic - r.start.fluid_kinetic, 100.0 * r.relativeResidual());
      }
    }
  }
  std::printf(
      "(%g s from 20 m, rolled 0.05 rad, every wing 60/10 rad/s and 0.6 rad; in water "
      "3/1 rad/s; residual: the works less the change of the energies, as a share of the "
      "motors' positive work; added mass's products %s; motor work %s)\n",
      seconds, flapsim::addedMassProductsName(products), flapsim::motorWorkMeterName(meter));
  return 0;
}

}  // namespace

bool parseAddedMassProducts(const char* text, flapsim::AddedMassProducts* out) {
  try {
    *out = flapsim::parseAddedMassProducts(text);
    return true;
  } catch (const flapsim::InputError& e) {
    std::fprintf(stderr, "flapsim_bench: --added-mass-products: %s\n", e.what());
    return false;
  }
}

int energyTable(const std::string& urdf, double seconds, flapsim::AddedMassProducts products,
                flapsim::MotorWorkMeter meter) {
  try {
    return energyRows(urdf, seconds, products, meter);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flapsim_bench: %s\n", e.what());
    return 1;
  }
}

}  // namespace flapsim_bench
