#include "flapsim/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
    const bool uses_cd = model->readsDragCoefficient();
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

std::string sweepTable(const SweepParams& p, const std::vector<SweepRow>& rows) {
  char line[256];
  std::snprintf(line, sizeof line,
                "plate %.2f x %.2f m in a %.1f m/s flow (rho %.3f): average pressure on the "
                "plate\n%-13s %5s %4s %7s %12s %10s %10s\n",
                p.chord, p.span, p.speed, p.density, "model", "Cd", "grid", "incl", "pressure/Pa",
                "lift/N", "drag/N");
  std::string out = line;
  for (const auto& r : rows) {
    std::snprintf(line, sizeof line, "%-13s %5.2f %4d %7.1f %12.3f %10.4f %10.4f\n",
                  r.model.c_str(), r.drag_coefficient, r.grid, r.inclination_deg, r.pressure,
                  r.lift, r.drag);
    out += line;
  }
  return out;
}

std::string sweepGnuplotScript(const SweepParams& p, const std::vector<SweepRow>& rows,
                               const std::string& csv, const std::string& png) {
  std::ostringstream gp;
  gp << "set datafile separator ','\nset terminal pngcairo size 900,600 noenhanced\n"
     << "set output '" << png << "'\nset title 'Average pressure on a " << p.chord << " x "
     << p.span << " m plate in a " << p.speed << " m/s flow (paper Fig. 15)'\n"
     << "set xlabel 'inclination (deg; 0 = edge-on, 90 = face-on)'\n"
     << "set ylabel 'average pressure (Pa)'\nset xrange [0:180]\nset xtics 15\nset grid\n"
     << "set key top left\nplot ";
  // One curve per (model, Cd, grid): their rows are contiguous in the CSV.
  for (size_t first = 0; first < rows.size();) {
    size_t last = first;
    while (last + 1 < rows.size() && rows[last + 1].inclination_deg > rows[last].inclination_deg) {
      ++last;
    }
    std::ostringstream title;
    title << rows[first].model;
    const AirModelPtr model = makeAirModel(rows[first].model);
    if (model && model->readsDragCoefficient()) {
      title << " Cd " << std::to_string(rows[first].drag_coefficient).substr(0, 4);
    }
    title << ", grid " << rows[first].grid;
    gp << (first ? ", " : "") << "'" << csv << "' skip 1 every ::" << first << "::" << last
       << " using 4:6 with linespoints title '" << title.str() << "'";
    first = last + 1;
  }
  gp << "\n";
  return gp.str();
}

std::string sweepUnusedFlag(const SweepParams& p, const std::vector<CliSeen>& seen) {
  const bool reads_cd = std::any_of(p.models.begin(), p.models.end(), [](const std::string& m) {
    const AirModelPtr model = makeAirModel(m);
    return model && model->readsDragCoefficient();
  });
  for (const CliSeen& given : seen) {
    if (given.flag->names[0] == "--cd" && !reads_cd) {
      return "--cd has no effect without the pressure model in --models (it sets that "
             "model's drag coefficients)";
    }
  }
  return "";
}

CliParser sweepCli(SweepParams& p, std::string& out_dir) {
  CliParser t("usage: sweep [options]");
  t.real("--speed", "M_S", &p.speed, {0, 1e3}, "flow speed, m/s")
      .reals("--cd", "LIST", &p.drag_coefficients, {0, 1e3, true}, 16,
             "drag coefficients of the pressure model")
      .integers("--grid", "LIST", &p.grids, {1, 64}, 16, "cells per face edge")
      .texts("--models", "LIST", &p.models, airModelNames(), 4, "air models")
      .real("--step", "DEG", &p.step_deg, {0.1, 180}, "inclination step, degrees")
      .text("--out", "DIR", &out_dir, "output directory (sweep.csv, sweep.png)");
  return t;
}

}  // namespace flapsim
