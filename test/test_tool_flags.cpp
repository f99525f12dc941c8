// Every flag of make_creature (a single unit, a chain, the hover creature) and of sweep, given on
// its own: each changes what the tool makes (the URDF text, the sweep's rows) or is refused by
// name. The output flags (--output, --out) change only where it goes and are left out; the
// tables' rules (makeCreatureUnusedFlag, sweepUnusedFlag) are what refuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "flapsim/make_creature.h"
#include "flapsim/sweep.h"

namespace flapsim {
namespace {

// What make_creature writes for `args`, or its refusal.
std::pair<std::string, std::string> makeCreature(const std::vector<std::string>& args) {
  MakeCreatureOptions o;
  CliParser cli = makeCreatureCli(o);
  try {
    const std::vector<CliSeen> seen = cli.parse(args);
    const std::string unused = makeCreatureUnusedFlag(o, seen);
    if (!unused.empty()) return {"", unused};
    return {makeCreatureOutput(o), ""};
  } catch (const InputError& e) {
    return {"", e.what()};
  }
}

// The flags a table lists, but `left_out`.
std::vector<std::string> listed(const CliParser& cli, const std::vector<std::string>& left_out) {
  std::vector<std::string> names;
  for (const CliFlag& flag : cli.flags()) {
    if (std::find(left_out.begin(), left_out.end(), flag.names[0]) == left_out.end()) {
      names.push_back(flag.names[0]);
    }
  }
  return names;
}

TEST(ToolFlags, EveryFlagOfMakeCreatureChangesTheUrdfOrIsRefusedByName) {
  // (flag, values, then per mode (one unit, a chain of 2, --layout hover) "" if the flag must
  // change the URDF, else the flag's name, which its refusal must begin with).
  const std::vector<
      std::tuple<std::string, std::vector<std::string>, std::string, std::string, std::string>>
      tried = {
          {"--pairs", {"3"}, "", "", "--pairs"},
          {"--layout", {"hover"}, "", "--pairs", ""},  // on a chain: --pairs then does nothing
          {"--name", {"other"}, "", "", ""},
          {"--feathering", {}, "", "", "--feathering"},
          {"--body-mass", {"0.02"}, "", "", "--body-mass"},
          {"--wing-mass", {"0.005"}, "", "", "--wing-mass"},
          {"--wing-effort", {"5"}, "", "", "--wing-effort"},
          {"--com-drop", {"0.03"}, "", "", "--com-drop"},
          {"--link-axis", {"pitch"}, "--link-axis", "", "--link-axis"},
          {"--link-stiffness", {"3"}, "--link-stiffness", "", "--link-stiffness"},
          {"--stall-torque", {"0.05"}, "--stall-torque", "--stall-torque", ""},
          {"--no-load-speed", {"250"}, "--no-load-speed", "--no-load-speed", ""},
          {"--max-power", {"2"}, "--max-power", "--max-power", ""},
          {"--hinge-stiffness", {"0.03"}, "--hinge-stiffness", "--hinge-stiffness", ""},
      };
  MakeCreatureOptions table_options;
  std::vector<std::string> walked;
  for (const auto& t : tried) walked.push_back(std::get<0>(t));
  EXPECT_EQ(walked, listed(makeCreatureCli(table_options), {"--output"}));
  const std::vector<std::vector<std::string>> modes = {{}, {"--pairs", "2"}, {"--layout", "hover"}};
  for (int m = 0; m < 3; ++m) {
    const auto [plain, plain_refused] = makeCreature(modes[m]);
    ASSERT_EQ(plain_refused, "");
    for (const auto& t : tried) {
      const std::string& flag = std::get<0>(t);
      const std::string& refusal = m == 0   ? std::get<2>(t)
                                   : m == 1 ? std::get<3>(t)
                                            : std::get<4>(t);
      SCOPED_TRACE(flag + " in mode " + std::to_string(m));
      std::vector<std::string> args = modes[m];
      if (flag == "--pairs" && m == 1) args = {};  // the chain of 2 given its own --pairs
      if (flag == "--layout" && m == 2) continue;  // the mode itself
      args.push_back(flag);
      for (const std::string& v : std::get<1>(t)) args.push_back(v);
      const auto [urdf, refused] = makeCreature(args);
      if (refusal.empty()) {
        EXPECT_EQ(refused, "");
        EXPECT_NE(urdf, plain);
      } else {
        EXPECT_EQ(refused.rfind(refusal, 0), 0u) << refused;
      }
    }
  }
}

// What sweep computes for `args`, or its refusal.
std::pair<std::vector<SweepRow>, std::string> sweep(const std::vector<std::string>& args) {
  SweepParams p;
  std::string out;
  CliParser cli = sweepCli(p, out);
  try {
    const std::vector<CliSeen> seen = cli.parse(args);
    const std::string unused = sweepUnusedFlag(p, seen);
    if (!unused.empty()) return {{}, unused};
    return {pressureSweep(p), ""};
  } catch (const InputError& e) {
    return {{}, e.what()};
  }
}

std::vector<double> figures(const std::vector<SweepRow>& rows) {
  std::vector<double> f;
  for (const SweepRow& r : rows) {
    f.insert(f.end(), {r.drag_coefficient, double(r.grid), r.inclination_deg, r.normal_force,
                       r.lift, r.drag});
  }
  return f;
}

TEST(ToolFlags, EveryFlagOfSweepChangesTheRowsOrIsRefusedByName) {
  const auto [plain, plain_refused] = sweep({});
  ASSERT_EQ(plain_refused, "");
  const std::vector<std::pair<std::string, std::string>> tried = {{"--speed", "3"},
                                                                  {"--cd", "1.5"},
                                                                  {"--grid", "2"},
                                                                  {"--models", "quasi_steady"},
                                                                  {"--step", "10"}};
  SweepParams table_params;
  std::string table_out;
  std::vector<std::string> walked;
  for (const auto& t : tried) walked.push_back(t.first);
  EXPECT_EQ(walked, listed(sweepCli(table_params, table_out), {"--out"}));
  for (const auto& [flag, value] : tried) {
    SCOPED_TRACE(flag);
    const auto [rows, refused] = sweep({flag, value});
    EXPECT_EQ(refused, "");
    EXPECT_NE(figures(rows), figures(plain));
  }
  // --cd acts on the pressure model only.
  EXPECT_EQ(sweep({"--models", "quasi_steady", "--cd", "1.5"}).second.rfind("--cd", 0), 0u);
}

}  // namespace
}  // namespace flapsim
