// flight_check: flies a creature with its controller from held-out starts and prints, per
// start, whether it flipped, its lowest up-component, its final and lowest height and the
// fraction of time upright. Exit status 0 if every start passes (no flip, up-component
// never below 0.5, final height above the start), 1 if one does not, 2 on bad arguments.
#include "flapsim/flight_check.h"

#include <cstdio>
#include <iostream>
#include <string>

#include "flapsim/hover_flight.h"
#include "flapsim/make_creature.h"

namespace {

const char* kUsage =
    "usage: flight_check --weights FILE [options]\n"
    "       flight_check --hover [--urdf FILE] [--altitude Z] [--wind V] [--duration T]\n"
    "                    [--step-size DT] [--roll R] [--pitch P]\n"
    "  --hover          fly the hover creature (make_creature --layout hover, or --urdf) with\n"
    "                   its hand-designed controller from Z m (3) in a side wind of V m/s (0),\n"
    "                   started R, P rad tilted (0): height band, attitude, vertical\n"
    "                   oscillation per stroke, power and figure of merit after 10 s;\n"
    "                   exit 1 unless it holds Z within 0.3 m, upright (up >= 0.9), under 5 cm\n"
    "                   per stroke, at most 100 W/kg\n"
    "  --weights FILE   controller weights YAML (evolve's output)\n"
    "  --pairs N        the creature: make_creature --pairs N (1), or\n"
    "  --urdf FILE      a creature of flap units from a URDF file\n"
    "  --starts N       held-out starts (20)\n"
    "  --seed S         their seed (2024)\n"
    "  --roll R         start roll uniform in +-R rad (0.26)\n"
    "  --pitch P        start pitch uniform in +-P rad (0.26)\n"
    "  --duration T     s (60)\n"
    "  --step-size DT   s (0.001)\n"
    "  --threads N      parallel flights (1); results do not depend on it\n";

}  // namespace

// flight_check --hover: one hover flight and its figures.
int hoverCheck(const std::string& urdf, const flapsim::HoverControllerParams& controller,
               const flapsim::HoverFlightParams& p) {
  const flapsim::CreatureModelPtr model =
      urdf.empty() ? flapsim::parseCreatureModel(flapsim::makeHoverUrdf("hover"),
                                                 "make_creature --layout hover")
                   : flapsim::loadCreatureModel(urdf);
  const flapsim::HoverFlightResult r = flapsim::flyHover(model, controller, p);
  const double weight = r.mass * 9.81;
  const double ideal = flapsim::idealHoverPower(
      weight, p.world.air.density, flapsim::strokeDiskArea(*model, controller.amplitude));
  std::printf("hover at %g m, wind %g m/s, %g s at %g ms (figures after %g s):\n",
              controller.altitude, p.world.air.wind.norm(), p.duration, 1000.0 * p.world.step_size,
              p.settle);
  std::printf(
      "  height %.3f to %.3f m, lowest up-component %.4f, largest height range in a "
      "stroke %.1f mm, drift %.2f m, %.2f Hz\n",
      r.min_height, r.max_height, r.min_upright, 1000.0 * r.max_stroke_oscillation, r.drift.norm(),
      r.mean_frequency);
  std::printf(
      "  mechanical power of the motors: %.3f W positive (%.1f W/kg of its %.1f g), "
      "%.3f W net\n",
      r.positive_power, r.specificPower(), 1000.0 * r.mass, r.net_power);
  std::printf("  figure of merit: ideal %.3f W (actuator disk of %.4f m^2) / %.3f W = %.2f\n",
              ideal, flapsim::strokeDiskArea(*model, controller.amplitude), r.positive_power,
              ideal / r.positive_power);
  const bool ok = r.min_height >= controller.altitude - 0.3 &&
                  r.max_height <= controller.altitude + 0.3 && r.min_upright >= 0.9 &&
                  r.max_stroke_oscillation < 0.05 && r.specificPower() <= 100.0;
  std::printf("%s\n", ok ? "pass" : "FAIL");
  return ok ? 0 : 1;
}

int main(int argc, char** argv) {
  flapsim::FlightCheckParams p;
  std::string weights, urdf;
  int pairs = 1;
  bool hover = false;
  flapsim::HoverControllerParams hover_controller;
  flapsim::HoverFlightParams hover_flight;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        std::cout << kUsage;
        return 0;
      }
      if (a == "--hover") {
        hover = true;
        continue;
      }
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
      const std::string v = argv[++i];
      if (a == "--weights")
        weights = v;
      else if (a == "--pairs")
        pairs = std::stoi(v);
      else if (a == "--urdf")
        urdf = v;
      else if (a == "--starts")
        p.starts = std::stoi(v);
      else if (a == "--seed")
        p.seed = std::stoull(v);
      else if (a == "--roll")
        p.max_roll = hover_flight.start_roll = std::stod(v);
      else if (a == "--pitch")
        p.max_pitch = hover_flight.start_pitch = std::stod(v);
      else if (a == "--duration")
        p.duration = hover_flight.duration = std::stod(v);
      else if (a == "--step-size")
        p.step_size = hover_flight.world.step_size = std::stod(v);
      else if (a == "--altitude")
        hover_controller.altitude = std::stod(v);
      else if (a == "--wind")
        hover_flight.world.air.wind = flapsim::Vec3(0.0, std::stod(v), 0.0);
      else if (a == "--threads")
        p.threads = std::stoi(v);
      else
        throw std::invalid_argument("unknown option " + a);
    }
    if (weights.empty() && !hover) throw std::invalid_argument("--weights FILE is required");
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    if (hover) return hoverCheck(urdf, hover_controller, hover_flight);
    const flapsim::ControllerSpec spec = flapsim::loadControllerYaml(weights);
    const flapsim::CreatureModelPtr model =
        urdf.empty() ? flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(pairs, "afc"),
                                                   "make_creature --pairs " + std::to_string(pairs))
                     : flapsim::loadCreatureModel(urdf);
    const std::vector<flapsim::FlightCheckRun> runs = flapsim::flightCheck(model, spec, p);
    std::printf("%-5s %8s %8s %8s %7s %9s %9s %9s %8s %8s %8s %8s\n", "start", "roll", "pitch",
                "flipped", "min_up", "final_z", "min_z", "upright", "P+", "P+/m", "P_net",
                "result");
    int failed = 0;
    double positive = 0.0, net = 0.0, mass = 0.0;
    for (size_t i = 0; i < runs.size(); ++i) {
      const flapsim::FlightCheckRun& r = runs[i];
      const bool ok = r.passed(p.start_height);
      failed += ok ? 0 : 1;
      positive += r.positive_power / static_cast<double>(runs.size());
      net += r.net_power / static_cast<double>(runs.size());
      mass = r.mass;
      std::printf(
          "%-5zu %7.1f° %7.1f° %8s %7.3f %8.2fm %8.2fm %8.1f%% %7.2fW %5.0fW/kg %7.2fW %8s\n", i,
          r.start.roll * 180.0 / M_PI, r.start.pitch * 180.0 / M_PI, r.flipped ? "yes" : "no",
          r.min_upright, r.final_height, r.min_height, 100.0 * r.upright_fraction, r.positive_power,
          r.positive_power / r.mass, r.net_power, ok ? "pass" : "FAIL");
    }
    const double disk = flapsim::strokeDiskArea(*model, spec.params.amplitude);
    const double ideal = flapsim::idealHoverPower(9.81 * mass, 1.204, disk);
    std::printf(
        "mechanical power of the motors, mean over the starts: %.2f W positive (%.0f W/kg of its "
        "%.1f g), %.2f W net; figure of merit %.3f (ideal %.3f W on a disk of %.3f m^2)\n",
        positive, positive / mass, 1000.0 * mass, net, ideal / positive, ideal, disk);
    std::printf(
        "%d of %zu starts passed (%s, %g s at %g ms, %d wing pair(s))\n",
        static_cast<int>(runs.size()) - failed, runs.size(), weights.c_str(), p.duration,
        1000.0 * p.step_size,
        model->wing_joints.size() > 0 ? static_cast<int>(model->wing_joints.size() / 2) : 0);
    return failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n";
    return 2;
  }
}
