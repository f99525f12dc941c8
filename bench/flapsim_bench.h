// What flapsim_bench's files share: where the package's creatures are, and the energy table
// (bench/flapsim_bench_energy.cpp). For bench/flapsim_bench*.cpp only.
#pragma once

#include <string>
#include <vector>

#include "flapsim/world.h"

namespace flapsim_bench {

/// The usage, on stdout for --help (exit 0), else on stderr (exit 2): the exit code
/// (bench/flapsim_bench_flags.cpp).
int usage(bool help);

/// The flags a form of the command reads: --energy's, --check's (with --urdf or not), --urdf's,
/// or the timing table's.
std::vector<std::string> formFlags(bool energy, bool check, bool urdf);

/// The first of the `given` flags that the form does not read, with what it reads ("--json does
/// nothing with --energy, which reads ..."); empty if none.
std::string unreadFlag(const std::vector<std::string>& given, bool energy, bool check, bool urdf);

/// `text` as a MotorWorkMeter's name into `out`; false (and said on stderr) if it is none.
bool parseMotorWork(const char* text, flapsim::MotorWorkMeter* out);

/// The package's creatures: in the source tree it was built from, else where it is installed.
std::string urdfPath(const std::string& file);

/// --energy: the energy audit (flapsim/energy_audit.h) of the flap unit, afc_4 and the hover
/// creature (or the `urdf` creature) in vacuum, air and water at 1, 0.5 and 0.25 ms; in air and
/// water with the added mass's `products` (AirParams::added_mass_products). Returns the exit
/// code.
/// The motors' work is taken by `meter` (WorldParams::motor_work). An error is said on stderr
/// (exit code 1).
int energyTable(const std::string& urdf, double seconds, flapsim::AddedMassProducts products,
                flapsim::MotorWorkMeter meter);

/// `text` as AddedMassProducts into `out`, or false with the choices said on stderr.
bool parseAddedMassProducts(const char* text, flapsim::AddedMassProducts* out);

}  // namespace flapsim_bench
