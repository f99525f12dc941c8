// make_creature: writes the URDF of a creature of N flapping units.
#include "flapsim/make_creature.h"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  int pairs = 1;
  flapsim::FlapUnitParams params;
  flapsim::HoverParams hover_params;
  bool hover = false;
  std::string name, output;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "make_creature: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--pairs" || a == "-n") {
      std::string v = value();
      char* end = nullptr;
      long n = std::strtol(v.c_str(), &end, 10);
      if (*end != '\0' || n < 1 || n > 1000) {
        std::cerr << "make_creature: --pairs must be an integer in 1..1000, got '" << v << "'\n";
        return 2;
      }
      pairs = static_cast<int>(n);
    } else if (a == "--body-mass" || a == "--wing-mass" || a == "--wing-effort") {
      const std::string v = value();
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (*end != '\0' || !(x > 0.0) || x > 1e6) {
        std::cerr << "make_creature: " << a << " must be a positive number, got '" << v << "'\n";
        return 2;
      }
      if (a == "--body-mass") {
        params.body_mass = x;
      } else if (a == "--wing-mass") {
        params.wing_mass = x;
      } else {
        params.wing_effort = x;
      }
    } else if (a == "--link-stiffness") {
      const std::string v = value();
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (*end != '\0' || !(x >= 0.0) || x > 1e6) {
        std::cerr << "make_creature: --link-stiffness must be a number in [0, 1e6] N m/rad, got '"
                  << v << "'\n";
        return 2;
      }
      params.link_stiffness = x;
    } else if (a == "--link-axis") {
      try {
        params.link_axis = flapsim::linkAxisFromString(value());
      } catch (const std::invalid_argument& e) {
        std::cerr << "make_creature: --" << e.what() << "\n";
        return 2;
      }
    } else if (a == "--com-drop") {
      const std::string v = value();
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (*end != '\0' || !(x >= 0.0) || x > 1.0) {
        std::cerr << "make_creature: --com-drop must be a number in [0, 1] m, got '" << v << "'\n";
        return 2;
      }
      params.body_com_drop = x;
    } else if (a == "--layout") {
      const std::string v = value();
      if (v != "chain" && v != "hover") {
        std::cerr << "make_creature: --layout must be chain or hover, got '" << v << "'\n";
        return 2;
      }
      hover = v == "hover";
    } else if (a == "--stall-torque" || a == "--no-load-speed" || a == "--max-power" ||
               a == "--hinge-stiffness") {
      const std::string v = value();
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      const bool positive = a == "--stall-torque";
      if (*end != '\0' || !(positive ? x > 0.0 : x >= 0.0) || x > 1e6) {
        std::cerr << "make_creature: " << a << " must be a "
                  << (positive ? "positive" : "non-negative") << " number, got '" << v << "'\n";
        return 2;
      }
      if (a == "--stall-torque") {
        hover_params.stall_torque = x;
      } else if (a == "--no-load-speed") {
        hover_params.no_load_speed = x;
      } else if (a == "--max-power") {
        hover_params.max_power = x;
      } else {
        hover_params.hinge_stiffness = x;
      }
    } else if (a == "--feathering") {
      params.feathering = true;
    } else if (a == "--name") {
      name = value();
    } else if (a == "--output" || a == "-o") {
      output = value();
    } else if (a == "--help" || a == "-h") {
      std::cout
          << "usage: make_creature [--pairs N] [--name NAME] [--feathering] [--body-mass KG]\n"
             "                     [--wing-mass KG] [--wing-effort NM] [--com-drop M]\n"
             "                     [--link-axis roll|pitch] [--link-stiffness NM_PER_RAD]\n"
             "                     [--output FILE]\n"
             "       make_creature --layout hover [--name NAME] [--stall-torque NM]\n"
             "                     [--no-load-speed RAD_PER_S] [--max-power W]\n"
             "                     [--hinge-stiffness NM_PER_RAD] [--output FILE]\n"
             "Writes the URDF of N flapping units (body + two wings) chained nose to tail by\n"
             "passive joints about --link-axis (default roll), with a <spring> of\n"
             "--link-stiffness (default 2; 0: none); to stdout unless --output is given.\n"
             "--feathering hangs each wing from a pitch joint (its feather_joint). --com-drop\n"
             "puts each body's centre of mass that far below the wing hinges (default 0.02 m;\n"
             "0: at the hinges). --wing-effort is the hinge motors' torque limit (default 8 N m\n"
             "for one pair, 2 N m per unit in a chain).\n"
             "--layout hover (default: chain, the above) writes the hover creature instead\n"
             "(default name hover): a body under two wings that sweep a horizontal stroke plane\n"
             "and pitch about their spans, flown with the quasi-steady air model; each stroke\n"
             "hinge has a DC motor (--stall-torque, default 0.06 N m; --no-load-speed, default\n"
             "300 rad/s; --max-power, default 3 W; 0: none) and a parallel spring\n"
             "(--hinge-stiffness, default 0.035 N m/rad; 0: none).\n";
      return 0;
    } else {
      std::cerr << "make_creature: unknown argument '" << a << "' (see --help)\n";
      return 2;
    }
  }
  const std::string urdf =
      hover ? flapsim::makeHoverUrdf(name.empty() ? "hover" : name, hover_params)
            : flapsim::makeCreatureUrdf(pairs, name.empty() ? "afc" : name, params);
  if (output.empty()) {
    std::cout << urdf;
    return 0;
  }
  std::ofstream out(output);
  if (!(out << urdf)) {
    std::cerr << "make_creature: cannot write '" << output << "'\n";
    return 1;
  }
  return 0;
}
