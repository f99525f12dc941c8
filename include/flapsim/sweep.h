// The paper's Fig. 14-15 experiment: a plate held in a steady uniform flow at a range of
// inclinations; the air's force on it, per air model, drag coefficient and grid size.
#pragma once

#include <string>
#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/cli_args.h"

namespace flapsim {

struct SweepParams {
  double speed = 10.0;  // m/s, flow along +x
  double density = 1.204;
  double chord = 0.2;  // plate size along the flow at 90 deg (x before tilting)
  double span = 0.4;   // plate size across the flow (y)
  double thickness = 0.002;
  double step_deg = 15.0;  // inclinations 0, step, ..., 180
  std::vector<std::string> models{"pressure", "quasi_steady"};
  std::vector<double> drag_coefficients{2.0, 1.15};  // for the pressure model
  std::vector<int> grids{4};                         // cells per face edge
};

struct SweepRow {
  std::string model;
  double drag_coefficient = 0.0;  // 0 for models that do not use it
  int grid = 0;
  double inclination_deg = 0.0;  // 0: edge-on, 90: face-on
  double normal_force = 0.0;     // |F . plate normal|, N
  double pressure = 0.0;         // normal_force / plate area, Pa
  double lift = 0.0;             // F across the flow (+z), N
  double drag = 0.0;             // F along the flow (+x), N
};

/// Runs the sweep with the models' pure functions (no world). Throws InputError for an
/// unknown model or non-positive sizes.
std::vector<SweepRow> pressureSweep(const SweepParams& params);

/// The rows as CSV, with a header line.
std::string sweepCsv(const std::vector<SweepRow>& rows);

/// The rows as the table the sweep tool prints.
std::string sweepTable(const SweepParams& params, const std::vector<SweepRow>& rows);

/// gnuplot commands drawing `png` from the CSV `csv` of `rows`: one curve per (model, Cd,
/// grid).
std::string sweepGnuplotScript(const SweepParams& params, const std::vector<SweepRow>& rows,
                               const std::string& csv, const std::string& png);

/// The sweep tool's flags (flapsim/cli_args.h) over `params` and `out_dir`.
CliParser sweepCli(SweepParams& params, std::string& out_dir);

/// Empty if every flag `seen` (sweepCli's parse) changes the sweep; else a message naming the
/// first that would be ignored (--cd without the pressure model).
std::string sweepUnusedFlag(const SweepParams& params, const std::vector<CliSeen>& seen);

}  // namespace flapsim
