#include "flapsim/sweep.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "fluid/surface.h"

namespace flapsim {

std::vector<SweepRow> pressureSweep(const SweepParams& p) {
  if (!(p.speed >= 0.0) || !(p.chord > 0.0) || !(p.span > 0.0) || !(p.thickness > 0.0) ||
      !(p.step_deg > 0.0) || !(p.density >= 0.0)) {
    throw InputError("sweep: speed, density and sizes must be positive");
  }
  std::vector<SweepRow> rows;
  const double area = p.chord * p.span;
  for (const std::string& name : p.models) {
    AirModelPtr model = makeAirModel(name);
    if (!model) throw InputError("sweep: unknown air model '" + name + "'");
    const bool uses_cd = name == "pressure";
    const std::vector<double> cds = uses_cd ? p.drag_coefficients : std::vector<double>{0.0};
    for (double cd : cds) {
      for (int grid : p.grids) {
        if (grid < 1) throw InputError("sweep: grid must be >= 1");
        AeroSurface surface;
        appendBox(surface, Vec3(p.chord, p.span, p.thickness), Pose(), grid, grid);
        surface.drag_coefficient = cd;
        AirParams air;
        air.density = p.density;
        air.wind = Vec3(p.speed, 0.0, 0.0);
        const int steps = static_cast<int>(std::round(180.0 / p.step_deg));
        for (int k = 0; k <= steps; ++k) {
          const double deg = std::min(180.0, k * p.step_deg);
          BodyKinematics body;  // at rest in the wind
          body.orientation = Quat(Eigen::AngleAxisd(deg * M_PI / 180.0, Vec3::UnitY()));
          const Wrench w = model->bodyWrench(body, surface, air, nullptr);
          const Vec3 normal = body.orientation * Vec3::UnitZ();
          SweepRow row;
          row.model = name;
          row.drag_coefficient = cd;
          row.grid = grid;
          row.inclination_deg = deg;
          row.normal_force = std::abs(w.force.dot(normal));
          row.pressure = row.normal_force / area;
          row.lift = w.force.z();
          row.drag = w.force.x();
          rows.push_back(row);
        }
      }
    }
  }
  return rows;
}

std::string sweepCsv(const std::vector<SweepRow>& rows) {
  std::ostringstream out;
  out << "model,drag_coefficient,grid,inclination_deg,normal_force_N,pressure_Pa,lift_N,drag_N\n";
  out << std::setprecision(8);
  for (const SweepRow& r : rows) {
    out << r.model << ',' << r.drag_coefficient << ',' << r.grid << ',' << r.inclination_deg << ','
        << r.normal_force << ',' << r.pressure << ',' << r.lift << ',' << r.drag << '\n';
  }
  return out.str();
}

}  // namespace flapsim
