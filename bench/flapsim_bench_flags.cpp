// flapsim_bench's usage and the flags each of its forms reads (see bench/flapsim_bench.cpp).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "flapsim_bench.h"

namespace flapsim_bench {

int usage(bool help) {
  std::fprintf(help ? stdout : stderr,
               "usage: flapsim_bench [--runs N] [--seconds S] [--only NAME] [--json] [--cpu-time]\n"
               "                     [--step S] [--turn-substep S] [--no-ground]\n"
               "       flapsim_bench --check T [--reference-step S] [--only NAME | --urdf FILE "
               "[--height Z]]\n"
               "                     [--step S] [--turn-substep S] [--no-ground]\n"
               "       flapsim_bench --urdf FILE [--height Z] [--no-ground] [--skip S] "
               "[--runs N] [--seconds S]\n"
               "                     [--step S] [--turn-substep S] [--cpu-time]\n"
               "       flapsim_bench --energy [--urdf FILE] [--seconds S]\n"
               "                              [--added-mass-products shed|kirchhoff|omitted]\n"
               "                              [--motor-work transmitted|servo]\n");
  return help ? 0 : 2;
}

std::vector<std::string> formFlags(bool energy, bool check, bool urdf) {
  if (energy) {
    return {"--energy", "--urdf", "--seconds", "--added-mass-products", "--motor-work"};
  }
  std::vector<std::string> flags = {"--step", "--turn-substep", "--no-ground"};
  if (check) {
    flags.insert(flags.end(), {"--check", "--reference-step"});
    if (urdf) {
      flags.insert(flags.end(), {"--urdf", "--height"});
    } else {
      flags.push_back("--only");
    }
  } else if (urdf) {
    flags.insert(flags.end(),
                 {"--urdf", "--height", "--skip", "--runs", "--seconds", "--cpu-time"});
  } else {
    flags.insert(flags.end(), {"--runs", "--seconds", "--only", "--json", "--cpu-time"});
  }
  return flags;
}

std::string unreadFlag(const std::vector<std::string>& given, bool energy, bool check, bool urdf) {
  const std::vector<std::string> flags = formFlags(energy, check, urdf);
  for (const std::string& flag : given) {
    if (std::find(flags.begin(), flags.end(), flag) != flags.end()) continue;
    const std::string form = energy  ? "with --energy"
                             : check ? (urdf ? "with --check and --urdf" : "with --check")
                             : urdf  ? "with --urdf"
                                     : "in the timing table (without --energy, --check, --urdf)";
    std::string list;
    for (const std::string& f : flags) list += (list.empty() ? "" : ", ") + f;
    return flag + " does nothing " + form + ", which reads " + list;
  }
  return "";
}

}  // namespace flapsim_bench
