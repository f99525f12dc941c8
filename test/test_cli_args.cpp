// The tools' argument parser (flapsim/cli_args.h) and the tables of evolve, flight_check,
// sweep and make_creature: a bad number, an unknown flag, a missing value and a value out of
// range are refused naming the flag; --help shows the defaults of what runs.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/cli_args.h"
#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"
#include "flapsim/sweep.h"

namespace flapsim {
namespace {

// The message of the InputError that parsing `args` with `table` throws ("" if none).
std::string refusal(CliParser table, const std::vector<std::string>& args) {
  try {
    table.parse(args);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

struct Fields {
  int n = 3;
  double x = 0.5;
  std::uint64_t seed = 7;
  std::string name = "afc";
  bool on = false;
  std::vector<double> list{1.0, 2.0};
};

CliParser table(Fields& f) {
  CliParser t("usage: tool [options]", "notes\n");
  t.integer("--n,-n", "N", &f.n, {1, 10}, "a count")
      .real("--x", "X", &f.x, {0, 1, true}, "a fraction")
      .seed("--seed", "S", &f.seed, "a seed")
      .text("--name", "NAME", &f.name, "a name", {"afc", "plate"})
      .flag("--on", &f.on, true, "a switch")
      .reals("--list", "LIST", &f.list, {0, 5}, 3, "numbers");
  return t;
}

TEST(CliParser, ValuesGoToTheirFieldsInOrderAndAliasesWork) {
  Fields f;
  CliParser t = table(f);
  const auto seen = t.parse({"-n", "4", "--x", "1", "--seed", "18446744073709551615", "--name",
                             "plate", "--on", "--list", "0,2.5,5"});
  EXPECT_EQ(f.n, 4);
  EXPECT_EQ(f.x, 1.0);
  EXPECT_EQ(f.seed, 18446744073709551615ull);
  EXPECT_EQ(f.name, "plate");
  EXPECT_TRUE(f.on);
  EXPECT_EQ(f.list, (std::vector<double>{0.0, 2.5, 5.0}));
  ASSERT_EQ(seen.size(), 6u);
  EXPECT_EQ(seen[0].flag->names.front(), "--n");
  EXPECT_EQ(seen[0].values, std::vector<std::string>{"4"});
  EXPECT_FALSE(t.help());
  t.parse({"--help"});
  EXPECT_TRUE(t.help());
}

TEST(CliParser, BadValuesAreRefusedNamingTheFlag) {
  Fields f;
  EXPECT_EQ(refusal(table(f), {"--n", "3x"}), "--n: '3x' is not an integer");
  EXPECT_EQ(refusal(table(f), {"--n", ""}), "--n: '' is not an integer");
  EXPECT_EQ(refusal(table(f), {"--n", "99999999999999999999"}),
            "--n: '99999999999999999999' is not an integer");
  EXPECT_EQ(refusal(table(f), {"--n", "0"}), "--n: 0 is not in [1, 10]");
  EXPECT_EQ(refusal(table(f), {"--x", "0"}), "--x: 0 is not in (0, 1]");
  EXPECT_EQ(refusal(table(f), {"--x", "0.5m"}), "--x: '0.5m' is not a number");
  EXPECT_EQ(refusal(table(f), {"--x", "nan"}), "--x: 'nan' is not finite");
  EXPECT_EQ(refusal(table(f), {"--x", " 0.5"}), "--x: ' 0.5' is not a number");
  EXPECT_EQ(refusal(table(f), {"--seed", "-1"}), "--seed: '-1' is not an integer in [0, 2^64)");
  EXPECT_EQ(refusal(table(f), {"--seed", "18446744073709551616"}),
            "--seed: '18446744073709551616' is not an integer in [0, 2^64)");
  EXPECT_EQ(refusal(table(f), {"--name", "bird"}), "--name: 'bird' is not one of afc, plate");
  EXPECT_EQ(refusal(table(f), {"--list", "1,,2"}), "--list: '' is not a number");
  EXPECT_EQ(refusal(table(f), {"--list", "1,2,3,4"}), "--list: more than 3 items");
  EXPECT_EQ(refusal(table(f), {"--list", "6"}), "--list: 6 is not in [0, 5]");
  EXPECT_EQ(refusal(table(f), {"--bogus", "1"}), "unknown option '--bogus' (see --help)");
  EXPECT_EQ(refusal(table(f), {"--n"}), "--n needs a value (N)");
  EXPECT_EQ(refusal(table(f), {"--n", "--on"}), "--n needs a value (N)");
  EXPECT_EQ(f.n, 3);  // nothing stored from a refused value
}

// The campaign's edges: a trailing comma ("0.001,0.0005," was taken as two items while
// "0.001,,0.0005" was refused), an empty text ("evolve --out ''" failed in the filesystem
// without naming the flag), a flag given twice (the last silently won).
TEST(CliParser, TrailingCommasEmptyTextsAndRepeatedFlagsAreRefusedByName) {
  Fields f;
  EXPECT_EQ(refusal(table(f), {"--list", "1,2,"}), "--list: '' is not a number");
  EXPECT_EQ(refusal(table(f), {"--list", ",1"}), "--list: '' is not a number");
  EXPECT_EQ(refusal(table(f), {"--list", ""}), "--list: an empty list");
  EXPECT_EQ(refusal(table(f), {"--name", ""}), "--name: an empty value");
  EXPECT_EQ(refusal(table(f), {"--x", "0.2", "--x", "0.3"}),
            "--x is given twice (or under another of its names)");
  EXPECT_EQ(refusal(table(f), {"--n", "2", "-n", "3"}),
            "-n is given twice (or under another of its names)");
  EXPECT_EQ(refusal(table(f), {"--on", "--on"}),
            "--on is given twice (or under another of its names)");
  Fields later;
  table(later).parse({"--x", "0.2", "--x", "0.3"}, false, /*later_wins=*/true);
  EXPECT_EQ(later.x, 0.3);
  // Through evolve's table: the flags the issue named.
  auto evolveRefusal = [](const std::vector<std::string>& args) {
    try {
      parseEvolveArgs(args);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(evolveRefusal({"--out", ""}), "--out: an empty value");
  EXPECT_EQ(evolveRefusal({"--step-sizes", "0.001,0.0005,"}), "--step-sizes: '' is not a number");
  // The list parser of every reals flag (--step-sizes takes "auto" too).
  EXPECT_EQ(evolveRefusal({"--step-sizes", ""}), "--step-sizes: an empty list");
  EXPECT_EQ(evolveRefusal({"--step-sizes",
                           "0.001,0.001,0.001,0.001,0.001,0.001,0.001,0.001,0.001,"
                           "0.001,0.001,0.001,0.001,0.001,0.001,0.001,0.001"}),
            "--step-sizes: more than 16 items");
  EXPECT_EQ(evolveRefusal({"--seed", "1", "--seed", "2"}),
            "--seed is given twice (or under another of its names)");
}

TEST(CliParser, AHugeValueIsQuotedShort) {
  Fields f;
  const std::string huge(16 << 20, '7');
  const std::string msg = refusal(table(f), {"--x", huge + "x"});
  EXPECT_LT(msg.size(), 100u) << msg.substr(0, 200);
  EXPECT_EQ(msg, "--x: '" + huge.substr(0, kMaxQuotedValue) +
                     "...' (16777217 characters) is not "
                     "a number");
  EXPECT_EQ(refusal(table(f), {"--name", std::string(kMaxTextValue + 1, 'a')}),
            "--name: 4097 characters, over the limit of 4096");
}

TEST(CliParser, UsageShowsTheFieldsAsTheyAre) {
  Fields f;
  CliParser t = table(f);
  EXPECT_EQ(t.usage(),
            "usage: tool [options]\n"
            "  --n, -n N             a count (3)\n"
            "  --x X                 a fraction (0.5)\n"
            "  --seed S              a seed (7)\n"
            "  --name NAME           a name (afc)\n"
            "  --on                  a switch\n"
            "  --list LIST           numbers (1,2)\n"
            "notes\n");
  t.parse({"--n", "9"});
  EXPECT_NE(t.usage().find("a count (9)"), std::string::npos);
}

// flight_check used std::stoi, which took "3x" for 3.
TEST(ToolTables, FlightCheckRefusesANumberWithTrailingText) {
  FlightCheckOptions o;
  EXPECT_EQ(refusal(flightCheckCli(o), {"--pairs", "3x"}), "--pairs: '3x' is not an integer");
  EXPECT_EQ(refusal(flightCheckCli(o), {"--starts", "0"}), "--starts: 0 is not in [1, 1000]");
  EXPECT_EQ(refusal(flightCheckCli(o), {"--duration", "1e9"}),
            "--duration: 1e9 is not in (0, 10000]");
  EXPECT_EQ(refusal(flightCheckCli(o), {"--weights"}), "--weights needs a value (FILE)");
  EXPECT_EQ(refusal(flightCheckCli(o), {"--velocity-noise", "-0.1"}),
            "--velocity-noise: -0.1 is not in [0, 1000]");
  flightCheckCli(o).parse({"--weights", "w.yaml", "--pairs", "4", "--step-size", "0.0005"});
  EXPECT_EQ(o.weights, "w.yaml");
  EXPECT_EQ(o.pairs, 4);
  EXPECT_EQ(o.params.step_size, 0.0005);
  flightCheckCli(o).parse({"--velocity-noise", "0.05"});
  EXPECT_EQ(o.params.velocity_noise, 0.05);
  EXPECT_EQ(refusal(flightCheckCli(o), {"--turbulence", "stormy"}),
            "--turbulence: turbulence 'stormy' is not one of none, light, moderate, severe nor a "
            "wind at 6 m in m/s");
  EXPECT_EQ(refusal(flightCheckCli(o), {"--turbulence", "-1"}),
            "--turbulence: turbulence wind at 6 m '-1' is not in [0, 100] m/s");
  flightCheckCli(o).parse({"--turbulence", "3.5"});
  EXPECT_EQ(o.params.turbulence, 3.5);
  flightCheckCli(o).parse({"--turbulence", "moderate"});
  EXPECT_DOUBLE_EQ(o.params.turbulence, 30.0 * 1852.0 / 3600.0);
}

// With --real-air, --gust-torque and --gust-force are its impulses' sizes (>= 0: their signs
// are drawn), on the hover creature too.
TEST(ToolTables, FlightCheckTakesRealAirsImpulseSizes) {
  FlightCheckOptions sized;
  CliParser sizes = flightCheckCli(sized);
  const std::vector<CliSeen> sizes_seen =
      sizes.parse({"--hover", "--real-air", "--gust-torque", "0", "--gust-force", "0.5"});
  EXPECT_EQ(flightCheckUnusedFlag(sized, sizes_seen), "");
  takeRealAirSizes(sized, sizes_seen);
  ASSERT_TRUE(sized.params.real_air_torque.has_value());
  EXPECT_EQ(*sized.params.real_air_torque, 0.0);
  EXPECT_EQ(sized.params.real_air_force.value_or(-1.0), 0.5);
  FlightCheckOptions negative;
  CliParser negative_cli = flightCheckCli(negative);
  EXPECT_EQ(
      flightCheckUnusedFlag(negative, negative_cli.parse({"--real-air", "--gust-torque", "-0.1"})),
      "--gust-torque with --real-air is a size (its sign is drawn): give it >= 0");
}

// flight_check --hover used to fly the same flight to the bit with and without --noise,
// --seed, --starts or the gusts. Every flag of the table, given with a value it accepts, is
// either flown by the mode or refused by name.
// A valid value of flight_check's flag `name` for its metavariable `metavar`.
std::string walkValue(const std::string& name, const std::string& metavar) {
  if (name == "--gust-link") return "wing";
  if (name == "--motor-work") return "servo";
  if (name == "--added-mass-products") return "kirchhoff";
  if (metavar == "FILE") return "f.yaml";
  if (metavar == "LEVEL") return "light";
  return name == "--step-size" || name == "--turn-substep" ? "0.001" : "1";
}

// The motors' meter acts unless the added mass's products are omitted, in either mode.
TEST(ToolTables, FlightCheckRefusesTheMotorMeterWithTheAddedMassProductsOmitted) {
  for (bool hover : {false, true}) {
    FlightCheckOptions m;
    CliParser meter = flightCheckCli(m);
    std::vector<std::string> args = {"--added-mass-products", "omitted", "--motor-work", "servo"};
    if (hover) args.insert(args.begin(), "--hover");
    EXPECT_EQ(flightCheckUnusedFlag(m, meter.parse(args)),
              std::string("--motor-work") + kMotorWorkWithoutProducts);
  }
}

TEST(ToolTables, FlightCheckRefusesEveryFlagItsModeWouldIgnore) {
  auto refused = [](bool hover) {
    std::vector<std::string> names;
    FlightCheckOptions table_fields;
    const CliParser table = flightCheckCli(table_fields);
    for (const CliFlag& flag : table.flags()) {
      const std::string& name = flag.names[0];
      if (name == "--hover") continue;
      std::vector<std::string> args;
      if (hover) args.push_back("--hover");
      args.push_back(name);
      for (const std::string& metavar : flag.metavars) args.push_back(walkValue(name, metavar));
      FlightCheckOptions o;
      CliParser cli = flightCheckCli(o);  // the flags `seen` points to
      const std::vector<CliSeen> seen = cli.parse(args);
      const std::string why = flightCheckUnusedFlag(o, seen);
      if (why.empty()) continue;
      EXPECT_EQ(why.rfind(name + " ", 0), 0u) << why;  // it names the flag
      names.push_back(name);
    }
    return names;
  };
  EXPECT_EQ(refused(true),
            std::vector<std::string>({"--weights", "--pairs", "--starts", "--seed", "--threads",
                                      "--trace", "--gyro-bias", "--gust-torque", "--gust-force",
                                      "--gust-link", "--gust-time", "--noise", "--altitude-noise",
                                      "--velocity-noise"}));
  // Without a gust (the walk gives one flag at a time), its link and duration do nothing.
  EXPECT_EQ(refused(false),
            std::vector<std::string>({"--gains", "--write-gains", "--gust-link", "--gust-time"}));
  FlightCheckOptions o;
  CliParser cli = flightCheckCli(o);
  EXPECT_EQ(flightCheckUnusedFlag(o, cli.parse({"--hover", "--noise", "0.1"})),
            "--noise has no effect with --hover (one flight of the hover controller: no "
            "network, no held-out starts, gusts or sensor noise but those of --real-air)");
  // The hover creature's held-out starts come with real air.
  FlightCheckOptions h;
  CliParser hover = flightCheckCli(h);
  EXPECT_EQ(flightCheckUnusedFlag(
                h, hover.parse({"--hover", "--real-air", "--starts", "3", "--seed", "5"})),
            "");
  FlightCheckOptions hw;
  CliParser hover_wind = flightCheckCli(hw);
  EXPECT_EQ(flightCheckUnusedFlag(hw, hover_wind.parse({"--hover", "--real-air", "--wind", "1"})),
            "");
  // --real-air sets the gusts' times and sensors itself (its wind, turbulence and impulses'
  // sizes can be given: test_real_air.cpp, below).
  for (const char* set : {"--gust-time", "--noise", "--altitude-noise", "--gyro-bias"}) {
    FlightCheckOptions r;
    CliParser real = flightCheckCli(r);
    EXPECT_EQ(flightCheckUnusedFlag(r, real.parse({"--real-air", set, "1"})),
              std::string(set) + " is set by --real-air (give one or the other)");
  }
  FlightCheckOptions g;
  CliParser gust = flightCheckCli(g);
  EXPECT_EQ(flightCheckUnusedFlag(
                g, gust.parse({"--gust-force", "1", "--gust-link", "wing", "--gust-time", "0.2"})),
            "");
  // The sensors' noises hang on the controller flown.
  FlapControllerParams plain, altimeter, damped;
  altimeter.altitude_input = true;
  damped.velocity_gain = 0.2;
  FlightCheckOptions n;
  CliParser noisy = flightCheckCli(n);
  const std::vector<CliSeen> seen =
      noisy.parse({"--altitude-noise", "0.1", "--velocity-noise", "0.1"});
  EXPECT_EQ(flightCheckUnusedSensorFlag(plain, seen),
            "--altitude-noise has no effect: the controller's network reads no altimeter");
  EXPECT_EQ(
      flightCheckUnusedSensorFlag(altimeter, seen),
      "--velocity-noise has no effect: the controller has no ground-speed damping or climb input");
  FlapControllerParams climbing = altimeter;
  climbing.climb_input = true;
  EXPECT_EQ(flightCheckUnusedSensorFlag(climbing, seen), "");
  altimeter.velocity_gain = 0.2;
  EXPECT_EQ(flightCheckUnusedSensorFlag(altimeter, seen), "");
}

// make_creature --layout hover wrote the same file with and without --pairs 3 (and every other
// chain flag), the chain ignored the hover's motor flags, and a single unit its link flags;
// sweep ignored --cd without the pressure model. Each flag of the two tables, given with a value
// it accepts, is used by the creature or sweep it asks for, or refused by name.
TEST(ToolTables, MakeCreatureAndSweepRefuseEveryFlagTheirModeWouldIgnore) {
  auto refused = [](const std::vector<std::string>& mode) {
    std::vector<std::string> names;
    MakeCreatureOptions table_fields;
    const CliParser table = makeCreatureCli(table_fields);
    for (const CliFlag& flag : table.flags()) {
      const std::string& name = flag.names[0];
      if (name == "--layout" || name == "--pairs") continue;
      std::vector<std::string> args = mode;
      args.push_back(name);
      for (const std::string& metavar : flag.metavars) {
        args.push_back(metavar == "roll|pitch" ? "pitch" : metavar == "FILE" ? "f.urdf" : "0.5");
      }
      MakeCreatureOptions o;
      CliParser cli = makeCreatureCli(o);  // the flags `seen` points to
      const std::vector<CliSeen> seen = cli.parse(args);
      const std::string why = makeCreatureUnusedFlag(o, seen);
      if (why.empty()) continue;
      EXPECT_EQ(why.rfind(name + " ", 0), 0u) << why;
      names.push_back(name);
    }
    return names;
  };
  EXPECT_EQ(refused({"--layout", "hover"}),
            std::vector<std::string>({"--feathering", "--body-mass", "--wing-mass", "--wing-effort",
                                      "--com-drop", "--link-axis", "--link-stiffness"}));
  EXPECT_EQ(refused({"--pairs", "3"}),
            std::vector<std::string>(
                {"--stall-torque", "--no-load-speed", "--max-power", "--hinge-stiffness"}));
  EXPECT_EQ(refused({"--pairs", "1"}),
            std::vector<std::string>({"--link-axis", "--link-stiffness", "--stall-torque",
                                      "--no-load-speed", "--max-power", "--hinge-stiffness"}));
  MakeCreatureOptions o;
  CliParser cli = makeCreatureCli(o);
  EXPECT_EQ(makeCreatureUnusedFlag(o, cli.parse({"--layout", "hover", "--pairs", "3"})),
            "--pairs has no effect with --layout hover (it builds the chain of flap units)");

  SweepParams p;
  std::string out;
  CliParser sweep = sweepCli(p, out);
  EXPECT_EQ(sweepUnusedFlag(p, sweep.parse({"--models", "quasi_steady", "--cd", "1"})),
            "--cd has no effect without the pressure model in --models (it sets that model's "
            "drag coefficients)");
  SweepParams q;
  CliParser both = sweepCli(q, out);
  EXPECT_EQ(sweepUnusedFlag(q, both.parse({"--models", "pressure,quasi_steady", "--cd", "1"})), "");
}

TEST(ToolTables, SweepAndMakeCreatureRefuseBadValuesByFlag) {
  SweepParams p;
  std::string out;
  EXPECT_EQ(refusal(sweepCli(p, out), {"--grid", "4,x"}), "--grid: 'x' is not an integer");
  EXPECT_EQ(refusal(sweepCli(p, out), {"--models", "pressure,magic"}),
            "--models: 'magic' is not one of pressure, quasi_steady");
  EXPECT_EQ(refusal(sweepCli(p, out), {"--step", "0"}), "--step: 0 is not in [0.1, 180]");
  MakeCreatureOptions o;
  EXPECT_EQ(refusal(makeCreatureCli(o), {"-n", "0"}), "--pairs: 0 is not in [1, 1000]");
  EXPECT_EQ(refusal(makeCreatureCli(o), {"--body-mass", "-1"}),
            "--body-mass: -1 is not in (0, 1e+06]");
  EXPECT_EQ(refusal(makeCreatureCli(o), {"--link-axis", "yaw"}),
            "--link-axis: 'yaw' is not one of roll, pitch");
  makeCreatureCli(o).parse({"-n", "4", "--wing-effort", "3", "-o", "x.urdf", "--feathering"});
  EXPECT_EQ(o.pairs, 4);
  EXPECT_EQ(o.params.wing_effort, 3.0);
  EXPECT_EQ(o.output, "x.urdf");
  EXPECT_TRUE(o.params.feathering);
}

// The turn substep of flight_check and evolve: 0 (off) or at least 1e-7 s, else refused by
// name; a value given is flown.
TEST(ToolTables, TurnSubstepIsFlownOrRefusedByName) {
  FlightCheckOptions o;
  EXPECT_EQ(refusal(flightCheckCli(o), {"--turn-substep", "-1"}),
            "--turn-substep: -1 is not in [0, 0.1]");
  EXPECT_EQ(refusal(flightCheckCli(o), {"--turn-substep", "1e-9"}),
            "--turn-substep: turn_substep must be 0 (off) or finite and >= 1e-7 s");
  flightCheckCli(o).parse({"--turn-substep", "0.002"});
  EXPECT_EQ(o.params.turn_substep, 0.002);
  EXPECT_EQ(flightCheckEpisodes(o.params).world.turn_substep, 0.002);
  try {
    parseEvolveArgs({"--turn-substep", "1e-9"});
    ADD_FAILURE() << "evolve took a turn substep of 1e-9 s";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--turn-substep: turn_substep must be 0 (off) or finite and >= 1e-7 s");
  }
  EXPECT_EQ(parseEvolveArgs({"--turn-substep", "0"}).params.episode.world.turn_substep, 0.0);
}

// A rate range above the chain pitch term's 75 rad/s ceiling was refused for a parameter no
// flag sets ("pitch_max_downstroke_rate must be ... >= max_downstroke_rate"): the ceiling now
// rises with --max-rate, and a range within it leaves it at 75.
TEST(ToolTables, EvolveTakesAMaxRateAboveThePitchTermsCeiling) {
  const FlapControllerParams fast =
      parseEvolveArgs({"--min-rate", "10", "--max-rate", "100"}).params.controller;
  EXPECT_EQ(fast.max_downstroke_rate, 100.0);
  EXPECT_EQ(fast.pitch_max_downstroke_rate, 100.0);
  EXPECT_EQ(validateFlapControllerParams(fast), "");
  EXPECT_EQ(parseEvolveArgs({"--max-rate", "70"}).params.controller.pitch_max_downstroke_rate,
            75.0);
}

// Issue 26 item 6: evolve --help showed the paper preset's 10, 200 and 30 s while running
// the robust one.
TEST(ToolTables, EvolveHelpShowsTheDefaultsOfThePresetThatRuns) {
  const std::string robust = evolveUsage();
  EXPECT_NE(robust.find("individuals (32)"), std::string::npos) << robust;
  EXPECT_NE(robust.find("generations after the initial one (100)"), std::string::npos);
  EXPECT_NE(robust.find("episode length, s (20)"), std::string::npos);
  // auto: afc_1's accurate step sizes (flapsim/step_accuracy.h), found as the flags are read.
  EXPECT_NE(robust.find("(0.004,0.002)"), std::string::npos);
  const std::string paper = evolveUsage({"--preset", "paper", "--population", "12"});
  EXPECT_NE(paper.find("individuals (12)"), std::string::npos) << paper;
  EXPECT_NE(paper.find("generations after the initial one (200)"), std::string::npos);
  EXPECT_NE(paper.find("episode length, s (30)"), std::string::npos);
  EXPECT_NE(paper.find("step sizes drawn per episode, s, e.g. 0.001,0.0005; auto: the "
                       "creature's largest accurate step and its half (flapsim/step_accuracy.h) "
                       "(0.001)"),
            std::string::npos);
  EXPECT_NE(evolveUsage({}, 6).find("results do not depend on it (6)"), std::string::npos);
}

TEST(ToolTables, EvolveFlagsKeepTheirMeaningAndRefuseByFlag) {
  const EvolveOptions o =
      parseEvolveArgs({"--roll", "0.1", "0.2", "--step-sizes", "0.001", "--gene-range", "4",
                       "--phase-lock", "off", "__name:=evolve", "--no-plot", "--farm-batch", "3"});
  EXPECT_EQ(o.params.episode.min_roll, 0.1);
  EXPECT_EQ(o.params.episode.max_roll, 0.2);
  EXPECT_EQ(o.params.episode.step_sizes, std::vector<double>{0.001});
  EXPECT_EQ(o.params.ga.gene_min, -4.0);
  EXPECT_FALSE(o.params.controller.phase_lock);
  EXPECT_FALSE(o.plot);
  EXPECT_EQ(o.farm_batch, 3);
  EXPECT_EQ(o.spec_args,
            (std::vector<std::string>{"--preset", "robust", "--roll", "0.1", "0.2", "--step-sizes",
                                      "0.001", "--gene-range", "4", "--phase-lock", "off"}));
  auto refused = [](const std::vector<std::string>& args) {
    try {
      parseEvolveArgs(args);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refused({"--roll", "0.2", "0.1"}), "--roll: 0.1 is not in [0.2, 3.14159]");
  EXPECT_EQ(refused({"--roll", "0.2"}), "--roll needs a value (HI)");
  EXPECT_EQ(refused({"--phase-lock", "maybe"}), "--phase-lock takes on or off");
  EXPECT_EQ(refused({"--preset", "fast"}),
            "--preset: 'fast' is not one of robust, paper, hover, morph");
  EXPECT_EQ(refused({"--farm-timeout", "0"}), "--farm-timeout: 0 is not in (0, 1e+06]");
  EXPECT_EQ(refused({"--air-model", "vacuum"}),
            "--air-model: 'vacuum' is not one of pressure, quasi_steady");
  // Flags that did nothing where another left them without effect (the robust preset has
  // gusts, altitude hold and the altitude input; the paper's has none of them).
  EXPECT_EQ(refused({"--settle", "3"}),
            "--settle: has no effect but with --preset hover or morph, --upright-floor or "
            "--rms-ceiling (the flap network's fitness has none without them)");
  // The fitness terms that count after --settle.
  for (const std::string term : {"--upright-floor", "--rms-ceiling"}) {
    SCOPED_TRACE(term);
    EXPECT_EQ(refused({term, "0.3", "5", "--settle", "3"}), "");
    EXPECT_EQ(refused({term, "0.3", "5", "--settle", "20"}),
              term + ": has no effect with --settle at or after --duration (no sample settles)");
    EXPECT_EQ(refused({term, "0.3", "5", "--altitude-hold", "off"}),
              term + ": has no effect without --altitude-hold on");
  }
  EXPECT_EQ(refused({"--upright-floor", "1.5", "5"}), "--upright-floor: 1.5 is not in [0, 1]");
  EXPECT_EQ(refused({"--rms-ceiling", "-1", "2"}), "--rms-ceiling: -1 is not in [0, 1000]");
  EXPECT_EQ(refused({"--preset", "hover", "--rms-ceiling", "0.3", "2"}),
            "--rms-ceiling: not a flag of --preset hover (the hover controller's gains)");
  // The flap network's outputs: until 8 December 2026 --max-upstroke-rate with hover was
  // refused naming the network's key, not the flag.
  EXPECT_EQ(refused({"--preset", "hover", "--max-upstroke-rate", "40"}),
            "--max-upstroke-rate: not a flag of --preset hover (the hover controller's gains)");
  EXPECT_EQ(refused({"--preset", "hover", "--mixer-headroom", "0.1"}),
            "--mixer-headroom: not a flag of --preset hover (the hover controller's gains)");
  EXPECT_EQ(refused({"--preset", "paper", "--gust-link", "wing"}),
            "--gust-link: has no effect without --gust-force");
  EXPECT_EQ(refused({"--preset", "paper", "--gust-torque-time", "0.3"}),
            "--gust-torque-time: has no effect without --gust-torque");
  EXPECT_EQ(refused({"--altitude", "2", "3", "--altitude-hold", "off"}),
            "--altitude: has no effect without --altitude-hold on");
  EXPECT_EQ(refused({"--altitude-input", "off", "--altitude-noise", "0.1"}),
            "--altitude-noise: has no effect without an altitude input (--altitude-input on)");
  EXPECT_EQ(refused({"--gust-link", "wing", "--gust-force-time", "0.3", "--altitude", "2", "3",
                     "--altitude-input", "on", "--altitude-noise", "0.1"}),
            "");
  // The chain's terms on a single unit (the robust preset's --pairs 1).
  EXPECT_EQ(refused({"--chain-input", "on"}),
            "--chain-input: has no effect on a single unit (--pairs 1: no chain)");
  EXPECT_EQ(refused({"--pitch-gain", "2"}),
            "--pitch-gain: has no effect on a single unit (--pairs 1: no chain)");
  const EvolveOptions chain = parseEvolveArgs(
      {"--pairs", "4", "--chain-input", "on", "--step-sizes", "0.001", "--pitch-gain", "0"});
  EXPECT_TRUE(chain.params.controller.chain_input);
  EXPECT_EQ(chain.spec_args,
            (std::vector<std::string>{"--preset", "robust", "--pairs", "4", "--chain-input", "on",
                                      "--step-sizes", "0.001", "--pitch-gain", "0"}));
  EXPECT_EQ(evaluationSpecFromArgs(chain.spec_args).controller.chain_input, true);
}

}  // namespace
}  // namespace flapsim
