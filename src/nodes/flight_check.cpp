// flight_check: flies a creature with its controller from held-out starts and prints, per
// start, whether it flipped, its lowest up-component, its final and lowest height and the
// fraction of time upright. Exit status 0 if every start passes (no flip, up-component
// never below 0.5, final height above the start), 1 if one does not, 2 on bad arguments.
#include "flapsim/flight_check.h"

#include <cstdio>
#include <iostream>
#include <string>

#include "flapsim/make_creature.h"

namespace {

const char* kUsage =
    "usage: flight_check --weights FILE [options]\n"
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

int main(int argc, char** argv) {
  flapsim::FlightCheckParams p;
  std::string weights, urdf;
  int pairs = 1;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        std::cout << kUsage;
        return 0;
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
        p.max_roll = std::stod(v);
      else if (a == "--pitch")
        p.max_pitch = std::stod(v);
      else if (a == "--duration")
        p.duration = std::stod(v);
      else if (a == "--step-size")
        p.step_size = std::stod(v);
      else if (a == "--threads")
        p.threads = std::stoi(v);
      else
        throw std::invalid_argument("unknown option " + a);
    }
    if (weights.empty()) throw std::invalid_argument("--weights FILE is required");
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    const flapsim::ControllerSpec spec = flapsim::loadControllerYaml(weights);
    const flapsim::CreatureModelPtr model =
        urdf.empty() ? flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(pairs, "afc"),
                                                   "make_creature --pairs " + std::to_string(pairs))
                     : flapsim::loadCreatureModel(urdf);
    const std::vector<flapsim::FlightCheckRun> runs = flapsim::flightCheck(model, spec, p);
    std::printf("%-5s %8s %8s %8s %7s %9s %9s %9s %8s\n", "start", "roll", "pitch", "flipped",
                "min_up", "final_z", "min_z", "upright", "result");
    int failed = 0;
    for (size_t i = 0; i < runs.size(); ++i) {
      const flapsim::FlightCheckRun& r = runs[i];
      const bool ok = r.passed(p.start_height);
      failed += ok ? 0 : 1;
      std::printf("%-5zu %7.1f° %7.1f° %8s %7.3f %8.2fm %8.2fm %8.1f%% %8s\n", i,
                  r.start.roll * 180.0 / M_PI, r.start.pitch * 180.0 / M_PI,
                  r.flipped ? "yes" : "no", r.min_upright, r.final_height, r.min_height,
                  100.0 * r.upright_fraction, ok ? "pass" : "FAIL");
    }
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
