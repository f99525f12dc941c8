// make_creature: writes the URDF of a creature of N flapping units, or of the hover creature.
#include "flapsim/make_creature.h"

#include <iostream>
#include <string>

#include "flapsim/text_file.h"
#include "flapsim/types.h"

int main(int argc, char** argv) {
  flapsim::MakeCreatureOptions o;
  flapsim::CliParser cli = flapsim::makeCreatureCli(o);
  try {
    const std::vector<flapsim::CliSeen> seen =
        cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    const std::string unused = flapsim::makeCreatureUnusedFlag(o, seen);
    if (!unused.empty()) throw flapsim::InputError(unused);
  } catch (const std::exception& e) {
    std::cerr << "make_creature: " << e.what() << "\n";
    return 2;
  }
  if (cli.help()) {
    std::cout << cli.usage();
    return 0;
  }
  try {
    const std::string urdf = flapsim::makeCreatureOutput(o);
    if (o.output.empty()) {
      std::cout << urdf;
    } else {
      flapsim::writeTextFile(o.output, urdf);
    }
  } catch (const std::exception& e) {
    std::cerr << "make_creature: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
