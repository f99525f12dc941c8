// flight_check: flies a creature with its controller from held-out starts and prints, per
// start, whether it flipped, its lowest up-component, its final and lowest height and the
// fraction of time upright. Exit status 0 if every start passes (no flip, up-component
// never below 0.5, final height above the start), 1 if one does not, 2 on bad arguments.
#include "flapsim/flight_check.h"

#include <iostream>
#include <string>

#include "flapsim/make_creature.h"

int main(int argc, char** argv) {
  flapsim::FlightCheckOptions o;
  flapsim::CliParser cli = flapsim::flightCheckCli(o);
  try {
    cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cli.help()) {
      std::cout << cli.usage();
      return 0;
    }
    if (o.weights.empty()) throw flapsim::InputError("--weights FILE is required");
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n" << cli.usage();
    return 2;
  }
  try {
    const flapsim::ControllerSpec spec = flapsim::loadControllerYaml(o.weights);
    const flapsim::CreatureModelPtr model =
        o.urdf.empty()
            ? flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(o.pairs, "afc"),
                                          "make_creature --pairs " + std::to_string(o.pairs))
            : flapsim::loadCreatureModel(o.urdf);
    const auto runs = flapsim::flightCheck(model, spec, o.params);
    int failed = 0;
    std::cout << flapsim::flightCheckReport(
        o, runs, static_cast<int>(model->wing_joints.size() / 2), failed);
    return failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n";
    return 2;
  }
}
