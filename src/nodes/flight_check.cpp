// flight_check: flies a creature with its controller from held-out starts, in still air or
// in a disturbance, and prints per start whether it flipped, its lowest up-component, its
// final and lowest height, the fraction of time upright, the altitude error's rms after 10 s,
// its lateral drift and mean bank. Exit status 0 if every start passes (no flip,
// up-component never below 0.5, final height above the start), 1 if one does not, 2 on bad
// arguments.
#include "flapsim/flight_check.h"

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
    "  --seed S         their seed (2024); it also draws headings, gust times, wings\n"
    "  --roll R         start roll uniform in +-R rad (0.26)\n"
    "  --pitch P        start pitch uniform in +-P rad (0.26)\n"
    "  --duration T     s (60)\n"
    "  --step-size DT   s (0.001)\n"
    "  --threads N      parallel flights (1); results do not depend on it\n"
    "  --wind SPEED     steady wind from t = 0, m/s, from a heading drawn per start (0)\n"
    "  --gust-torque NM a roll torque at a time drawn per start (10-60 %), sign drawn (0)\n"
    "  --gust-force N   a vertical push (> 0: up) on --gust-link at a drawn time (0)\n"
    "  --gust-link LINK the link pushed (default: a wing drawn per start, up or down)\n"
    "  --gust-time S    how long each gust acts, s (0.5)\n"
    "  --noise RAD      IMU noise: orientation RAD rad, angular velocity RAD rad/s (0)\n"
    "  --altitude-noise M  altimeter noise, m (0)\n"
    "  --altitude M     hold M m (the root's height); default: climb\n";

double number(const std::string& flag, const std::string& v) {
  size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size()) throw std::invalid_argument(flag + ": '" + v + "'");
  return x;
}

// Parses the flags into `p` and the others; returns false for --help.
bool parse(int argc, char** argv, flapsim::FlightCheckParams& p, std::string& weights,
           std::string& urdf, int& pairs) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") return false;
    if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
    const std::string v = argv[++i];
    double* real = a == "--roll"             ? &p.max_roll
                   : a == "--pitch"          ? &p.max_pitch
                   : a == "--duration"       ? &p.duration
                   : a == "--step-size"      ? &p.step_size
                   : a == "--wind"           ? &p.wind
                   : a == "--gust-torque"    ? &p.gust_torque
                   : a == "--gust-force"     ? &p.gust_force
                   : a == "--gust-time"      ? &p.gust_time
                   : a == "--noise"          ? &p.noise
                   : a == "--altitude-noise" ? &p.altitude_noise
                                             : nullptr;
    if (real != nullptr) {
      *real = number(a, v);
    } else if (a == "--altitude") {
      p.altitude = number(a, v);
    } else if (a == "--weights") {
      weights = v;
    } else if (a == "--urdf") {
      urdf = v;
    } else if (a == "--gust-link") {
      p.gust_link = v;
    } else if (a == "--pairs") {
      pairs = std::stoi(v);
    } else if (a == "--starts") {
      p.starts = std::stoi(v);
    } else if (a == "--seed") {
      p.seed = std::stoull(v);
    } else if (a == "--threads") {
      p.threads = std::stoi(v);
    } else {
      throw std::invalid_argument("unknown option " + a);
    }
  }
  if (weights.empty()) throw std::invalid_argument("--weights FILE is required");
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  flapsim::FlightCheckParams p;
  std::string weights, urdf;
  int pairs = 1;
  try {
    if (!parse(argc, argv, p, weights, urdf, pairs)) {
      std::cout << kUsage;
      return 0;
    }
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
    int failed = 0;
    std::cout << flapsim::flightCheckReport(p, runs, weights, failed);
    return failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "flight_check: " << e.what() << "\n";
    return 2;
  }
}
