// Every flag of flight_check's network mode (and of its hover mode, below), flown: given on its
// own to a short flight, each either changes what is flown (a figure of some start differs from
// the same flight without it) or is refused by name, and --threads changes nothing (its results
// do not depend on it). The flag tables' rules (test_cli_args:
// FlightCheckRefusesEveryFlagItsModeWouldIgnore) say which flags each mode refuses; this walk
// proves that the others act.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "flapsim/controller_file.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"
#include "flapsim/text_file.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::withFlag;

// What flight_check's main() flies for `args` (its parse, its two refusals, its creature), as
// the figures of every start; `refused` the refusal instead.
struct Flown {
  std::string refused;
  std::vector<double> figures;
};

// Each start's figures, one after another.
std::vector<double> figures(const std::vector<FlightCheckRun>& runs) {
  std::vector<double> out;
  for (const FlightCheckRun& r : runs) {
    out.insert(out.end(), {r.start.roll, r.start.pitch, r.final_height, r.min_height, r.min_upright,
                           r.mean_bank, r.lateral_drift, r.positive_power, r.mass});
  }
  return out;
}

Flown fly(const std::vector<std::string>& args) {
  FlightCheckOptions o;
  CliParser cli = flightCheckCli(o);
  const std::vector<CliSeen> seen = cli.parse(args);
  Flown f;
  f.refused = flightCheckUnusedFlag(o, seen);
  if (!f.refused.empty()) return f;
  takeRealAirSizes(o, seen);
  const ControllerSpec spec = loadControllerYaml(o.weights);
  f.refused = flightCheckUnusedSensorFlag(spec.params, seen);
  if (!f.refused.empty()) return f;
  const CreatureModelPtr model = o.urdf.empty()
                                     ? parseCreatureModel(makeCreatureUrdf(o.pairs, "afc"))
                                     : loadCreatureModel(o.urdf);
  f.figures = figures(flightCheck(model, spec, o.params));
  return f;
}

// The short flight every flag is tried on: afc_12's altitude network (it reads the altimeter
// and has ground-speed damping, so the sensors' noises act) on one unit, two starts of 0.4 s
// holding 1.1 m, near the start's 1 m (its altitude input, the error over 0.25 m, stays inside
// its +-1 clamp: holding 5 m or 4 m it is +1 all the flight, and neither the setpoint nor the
// altimeter's noise would show), with a push on a wing at a drawn time (so that the gust's link
// and duration act).
std::vector<std::string> base() {
  return {"--weights",    test::sourcePath("config/afc_12_altitude_weights.yaml"),
          "--starts",     "2",
          "--duration",   "0.4",
          "--altitude",   "1.1",
          "--gust-force", "1"};
}

TEST(FlightCheckFlags, EveryFlagOfTheNetworkModeChangesTheFlightOrIsRefusedByName) {
  const Flown plain = fly(base());
  ASSERT_EQ(plain.refused, "");
  ASSERT_EQ(plain.figures.size(), 2u * 9u);
  // A value other than the base flight's for each flag (the table's metavariables).
  const std::vector<std::pair<std::string, std::vector<std::string>>> tried = {
      {"--weights", {test::sourcePath("config/afc_1_real_air_weights.yaml")}},
      {"--pairs", {"2"}},
      {"--urdf", {test::sourcePath("urdf/afc_4.urdf")}},
      {"--starts", {"3"}},
      {"--seed", {"7"}},
      {"--roll", {"0.1"}},
      {"--pitch", {"0.1"}},
      {"--duration", {"0.3"}},
      {"--step-size", {"0.0005"}},
      {"--turn-substep", {"0"}},
      {"--wind", {"1"}},
      {"--turbulence", {"light"}},
      {"--gyro-bias", {"0.02"}},
      {"--real-air", {}},
      {"--gust-torque", {"0.05"}},
      {"--gust-force", {"2"}},
      {"--gust-link", {"unit0_wing_left"}},
      {"--gust-time", {"0.1"}},
      {"--noise", {"0.05"}},
      {"--altitude-noise", {"0.05"}},
      {"--velocity-noise", {"0.05"}},
      {"--added-mass-products", {"kirchhoff"}},
      {"--motor-work", {"servo"}},
      {"--altitude", {"1.2"}},
  };
  // Every flag of the table is tried, but --threads (below), --trace (its own test), --hover and
  // its gains.
  FlightCheckOptions table_options;
  const CliParser table = flightCheckCli(table_options);
  std::vector<std::string> walked;
  for (const CliFlag& flag : table.flags()) {
    const std::string& name = flag.names[0];
    if (name == "--threads" || name == "--hover" || name == "--gains" || name == "--write-gains" ||
        name == "--trace") {
      continue;
    }
    walked.push_back(name);
  }
  std::vector<std::string> names;
  for (const auto& t : tried) names.push_back(t.first);
  EXPECT_EQ(names, walked);

  for (const auto& [flag, values] : tried) {
    SCOPED_TRACE(flag);
    std::vector<std::string> args = withFlag(base(), flag, values);
    if (flag == "--real-air") {  // the base's push is its push's size: flown without it
      args = withFlag(
          {"--weights", base()[1], "--starts", "2", "--duration", "0.4", "--altitude", "1.1"}, flag,
          values);
      const Flown real = fly(args);
      ASSERT_EQ(real.refused, "");
      const Flown calm =
          fly({"--weights", base()[1], "--starts", "2", "--duration", "0.4", "--altitude", "1.1"});
      EXPECT_NE(real.figures, calm.figures);
      continue;
    }
    if (flag == "--motor-work") {  // it acts unless the added mass's products are omitted
      const std::vector<std::string> omitted =
          withFlag(base(), "--added-mass-products", {"omitted"});
      EXPECT_NE(fly(withFlag(omitted, flag, values)).refused, "");
      const Flown f = fly(args);
      EXPECT_EQ(f.refused, "");
      EXPECT_NE(f.figures, plain.figures);
      continue;
    }
    const Flown f = fly(args);
    EXPECT_EQ(f.refused, "");
    EXPECT_NE(f.figures, plain.figures);
  }
  // The threads share the starts out; what each start flies is the same to the bit.
  EXPECT_EQ(fly(withFlag(base(), "--threads", {"2"})).figures, plain.figures);
}

// --trace N FILE records start N's flight without changing it: the same figures to the bit, a
// row per control update whose last height is the run's final height, the air's vertical speed
// at the root (0 in still air, not in turbulence), each wing's commanded downstroke within the
// network's range and the upstroke its phase lock gives it. A start beyond the last is refused by
// name.
TEST(FlightCheckFlags, TheTraceRecordsOneStartsFlightWithoutChangingIt) {
  auto traced = [](const std::vector<std::string>& args, int start) {
    FlightCheckOptions o;
    CliParser cli = flightCheckCli(o);
    cli.parse(withFlag(args, "--trace", {std::to_string(start), "unused.csv"}));
    EXPECT_EQ(o.trace_path, "unused.csv");
    const ControllerSpec spec = loadControllerYaml(o.weights);
    return std::make_pair(
        flightCheck(parseCreatureModel(makeCreatureUrdf(1, "afc")), spec, o.params), spec);
  };
  const auto [runs, spec] = traced(base(), 1);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_TRUE(runs[0].trace.empty());
  const FlightCheckRun& run = runs[1];
  ASSERT_EQ(run.trace.size(), 20u);  // 0.4 s of 0.02 s updates
  EXPECT_EQ(run.trace.back().height, run.final_height);
  EXPECT_EQ(figures(runs), fly(base()).figures);
  const std::vector<std::string> wings = {"unit0_wing_left_joint", "unit0_wing_right_joint"};
  const std::string csv = flightTraceCsv(run, wings);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "time,height,upright,air_vz,unit0_wing_left_joint_down,unit0_wing_left_joint_up,"
            "unit0_wing_right_joint_down,unit0_wing_right_joint_up");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 21);
  const FlapControllerParams& c = spec.params;
  for (const EpisodeSample& s : run.trace) {
    EXPECT_EQ(s.air.z(), 0.0);  // still air
    for (size_t w = 0; w < 2; ++w) {
      EXPECT_GE(s.downstroke[w], c.min_downstroke_rate);
      EXPECT_LE(s.downstroke[w], c.pitch_max_downstroke_rate);
      EXPECT_EQ(s.upstroke[w], upstrokeRate(c, s.downstroke[w]));  // its phase lock's
    }
  }
  const auto turbulent = traced(withFlag(base(), "--turbulence", {"light"}), 0).first;
  double largest = 0.0;
  for (const EpisodeSample& s : turbulent[0].trace)
    largest = std::max(largest, std::abs(s.air.z()));
  EXPECT_GT(largest, 0.05);  // light turbulence: sigma_w 0.77 m/s
  EXPECT_THROW(flightTraceCsv(runs[0], wings), InputError);
  try {
    traced(base(), 2);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--trace: start 2 of 2 (the starts are numbered from 0)");
  }
}

// With --real-air, --gust-torque and --gust-force size its two impulses: both 0 fly real air's
// wind, turbulence and sensors alone, the same bits as those flags given one by one; a push of
// another size flies otherwise than real air's own.
TEST(FlightCheckFlags, WithRealAirTheGustFlagsSizeItsImpulses) {
  const std::vector<std::string> start = {"--weights",  base()[1], "--starts",   "2",
                                          "--duration", "0.4",     "--altitude", "1.1"};
  auto with = [&start](std::vector<std::string> more) {
    std::vector<std::string> args = start;
    args.insert(args.end(), more.begin(), more.end());
    return fly(args);
  };
  const Flown real = with({"--real-air"});
  const Flown calm = with({"--real-air", "--gust-torque", "0", "--gust-force", "0"});
  const Flown by_hand = with({"--wind", "1", "--turbulence", "light", "--noise", "0.05",
                              "--gyro-bias", "0.02", "--altitude-noise", "0.05"});
  ASSERT_EQ(real.refused, "");
  ASSERT_EQ(calm.refused, "");
  ASSERT_EQ(by_hand.refused, "");
  EXPECT_EQ(calm.figures, by_hand.figures);
  EXPECT_NE(calm.figures, real.figures);
  EXPECT_NE(with({"--real-air", "--gust-force", "2"}).figures, real.figures);
}

// flight_check --hover: its report for `args` (the tool's parse, refusal and two reports), or
// the refusal.
std::string flyHoverCheck(const std::vector<std::string>& args) {
  FlightCheckOptions o;
  CliParser cli = flightCheckCli(o);
  const std::vector<CliSeen> seen = cli.parse(args);
  const std::string refused = flightCheckUnusedFlag(o, seen);
  if (!refused.empty()) return "refused: " + refused;
  takeRealAirSizes(o, seen);
  const CreatureModelPtr model =
      o.urdf.empty() ? parseCreatureModel(makeHoverUrdf("hover")) : loadCreatureModel(o.urdf);
  int failed = 0;
  if (o.params.real_air) return hoverRealAirReport(o, hoverRealAirCheck(model, o), failed);
  bool ok = false;
  return hoverCheckReport(model, o, ok);
}

// The hover mode the same way: each of its flags changes the report of a flight of 10.5 s (its
// figures count after 10 s), but --write-gains, which writes a file.
TEST(FlightCheckFlags, EveryFlagOfTheHoverModeChangesItsFlight) {
  const std::vector<std::string> base = {"--hover", "--duration", "10.5"};
  const std::string plain = flyHoverCheck(base);
  ASSERT_EQ(plain.find("refused"), std::string::npos) << plain;
  // Another hover creature (hover_1.urdf is make_creature's own: the same flight).
  HoverParams heavier;
  heavier.body_mass = 0.017;
  const std::string urdf = ::testing::TempDir() + "/hover_heavier.urdf";
  writeTextFile(urdf, makeHoverUrdf("hover", heavier));
  const std::vector<std::pair<std::string, std::vector<std::string>>> tried = {
      {"--urdf", {urdf}},
      {"--roll", {"0.1"}},
      {"--pitch", {"0.1"}},
      {"--duration", {"10.4"}},
      {"--step-size", {"0.0005"}},
      {"--turn-substep", {"0"}},
      {"--gains", {test::sourcePath("config/hover_1_gains.yaml")}},
      {"--wind", {"1"}},
      {"--turbulence", {"light"}},
      {"--added-mass-products", {"kirchhoff"}},
      {"--motor-work", {"servo"}},
      {"--altitude", {"2.5"}},
      {"--real-air", {}},
  };
  for (const auto& [flag, values] : tried) {
    SCOPED_TRACE(flag);
    if (flag == "--motor-work") {  // it acts unless the added mass's products are omitted
      const std::vector<std::string> omitted = withFlag(base, "--added-mass-products", {"omitted"});
      EXPECT_NE(flyHoverCheck(withFlag(omitted, flag, values)).find("refused"), std::string::npos);
      const std::string report = flyHoverCheck(withFlag(base, flag, values));
      EXPECT_EQ(report.find("refused"), std::string::npos) << report;
      EXPECT_NE(report, plain);
      continue;
    }
    const std::string report = flyHoverCheck(withFlag(base, flag, values));
    EXPECT_EQ(report.find("refused"), std::string::npos) << report;
    EXPECT_NE(report, plain);
  }
}

}  // namespace
}  // namespace flapsim
