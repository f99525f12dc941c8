// flight_check: flies a creature with its controller from held-out starts and prints, per
// start, whether it flipped, its lowest up-component, its final and lowest height, the
// fraction of time upright and its motors' power; --trace N FILE writes start N's flight as
// CSV (flapsim::flightTraceCsv). Exit status 0 if every start passes (no
// flip, up-component never below 0.5, final height above the start), 1 if one does not, 2 on
// bad arguments. --hover flies the hover creature instead (flapsim::hoverCheckReport;
// with --real-air from held-out starts, flapsim::hoverRealAirCheck).
#include "flapsim/flight_check.h"

#include <algorithm>
#include <iostream>
#include <string>

#include "flapsim/make_creature.h"
#include "flapsim/real_air.h"
#include "flapsim/text_file.h"

int main(int argc, char** argv) {
  flapsim::FlightCheckOptions o;
  flapsim::CliParser cli = flapsim::flightCheckCli(o);
  std::vector<flapsim::CliSeen> seen;
  try {
    seen = cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cli.help()) {
      std::cout << cli.usage();
      return 0;
    }
    if (o.weights.empty() && !o.hover) throw flapsim::InputError("--weights FILE is required");
    const std::string unused = flapsim::flightCheckUnusedFlag(o, seen);
    if (!unused.empty()) throw flapsim::InputError(unused);
    flapsim::takeRealAirSizes(o, seen);
    auto given = [&seen](const std::string& flag) {
      return std::any_of(seen.begin(), seen.end(),
                         [&](const flapsim::CliSeen& s) { return s.flag->names[0] == flag; });
    };
    if (o.hover && !given("--roll")) o.params.max_roll = 0.0;
    if (o.hover && !given("--pitch")) o.params.max_pitch = 0.0;
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n" << cli.usage();
    return 2;
  }
  try {
    if (o.hover) {
      if (!o.write_gains.empty()) {
        flapsim::writeTextFile(o.write_gains, flapsim::hoverCheckGainsFile(o));
        std::cout << "wrote " << o.write_gains << "\n";
      }
      const flapsim::CreatureModelPtr hover =
          o.urdf.empty() ? flapsim::parseCreatureModel(flapsim::makeHoverUrdf("hover"),
                                                       "make_creature --layout hover")
                         : flapsim::loadCreatureModel(o.urdf);
      if (o.params.real_air) {  // from held-out starts
        int failed = 0;
        std::cout << flapsim::hoverRealAirReport(o, flapsim::hoverRealAirCheck(hover, o), failed)
                  << flapsim::realAirSpinUpLine(flapsim::realAirSpinUp(*hover));
        return failed == 0 ? 0 : 1;
      }
      bool ok = false;
      std::cout << flapsim::hoverCheckReport(hover, o, ok);
      return ok ? 0 : 1;
    }
    const flapsim::ControllerSpec spec = flapsim::loadControllerYaml(o.weights);
    const std::string unused = flapsim::flightCheckUnusedSensorFlag(spec.params, seen);
    if (!unused.empty()) {
      std::cerr << "flight_check: " << unused << "\n";
      return 2;
    }
    const flapsim::CreatureModelPtr model =
        o.urdf.empty()
            ? flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(o.pairs, "afc"),
                                          "make_creature --pairs " + std::to_string(o.pairs))
            : flapsim::loadCreatureModel(o.urdf);
    const auto runs = flapsim::flightCheck(model, spec, o.params);
    int failed = 0;
    std::cout << flapsim::flightCheckReport(o, runs,
                                            static_cast<int>(model->wing_joints.size() / 2), failed)
              << flapsim::flightPowerSummary(
                     runs, flapsim::strokeDiskArea(*model, spec.params.amplitude));
    if (o.params.real_air) std::cout << flapsim::realAirSpinUpLine(flapsim::realAirSpinUp(*model));
    if (!o.trace_path.empty()) {
      flapsim::writeTextFile(o.trace_path,
                             flapsim::flightTraceCsv(runs.at(o.params.trace_start),
                                                     flapsim::flapUnitLayout(*model).wing_joints));
      std::cout << "wrote " << o.trace_path << " (start " << o.params.trace_start << ")\n";
    }
    return failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n";
    return 2;
  }
}
