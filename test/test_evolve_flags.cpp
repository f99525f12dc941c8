// Every flag of evolve's flap presets, run: given on its own to a tiny evolution, each either
// changes what evolves (the generations' fitness or the best weights differ from the same run
// without it) or is refused by name; and the settings an --init file must share with the
// evolution it seeds. The tool's own flags (threads, files, the farm) do not
// change what evolves and are left out; test_cli_args checks their meaning. The rules that
// refuse a flag another leaves without effect are in evolve_args.cpp (checkDependentFlags).
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"
#include "flapsim/evolve_args.h"
#include "flapsim/evolve_tool.h"
#include "flapsim/text_file.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::withFlag;

struct Evolved {
  std::string refused;
  std::vector<double> figures;  // each generation's best and mean, then the best weights
};

Evolved evolveWith(const std::vector<std::string>& args) {
  Evolved e;
  EvolveOptions o;
  try {
    o = parseEvolveArgs(args, /*threads=*/1);
  } catch (const InputError& error) {
    e.refused = error.what();
    return e;
  }
  EvolveResult r;
  try {
    r = evolveFlapController(o.params);
  } catch (const std::exception& error) {  // refused, but not as the flags were read
    e.refused = std::string("evolveFlapController: ") + error.what();
    return e;
  }
  for (const GenerationStats& g : r.history) e.figures.insert(e.figures.end(), {g.best, g.mean});
  e.figures.insert(e.figures.end(), r.best_weights.begin(), r.best_weights.end());
  return e;
}

// A tiny robust-preset evolution: 4 individuals, one generation after the first, 2 episodes of
// 1 s at 1 ms.
const std::vector<std::string> kBase = {"--population", "4",    "--generations", "1",
                                        "--episodes",   "2",    "--duration",    "1",
                                        "--step-sizes", "0.001"};

// (flag, values, what the run must do: "" changes what evolves, "near" the same with altitude
// setpoints near the 1 m start (the altitude input, the error over 1 m, is clamped at +1 with
// the preset's 2-8 m, and the altimeter's noise does not show), else the refusal's text).
std::vector<std::tuple<std::string, std::vector<std::string>, std::string>> triedFlags() {
  return {
      {"--preset", {"paper"}, ""},
      {"--pairs", {"2"}, ""},
      {"--generations", {"2"}, ""},
      {"--population", {"6"}, ""},
      {"--seed", {"2"}, ""},
      {"--duration", {"0.8"}, ""},
      {"--episodes", {"3"}, ""},
      {"--episode-sets", {"2"}, ""},
      {"--min-rate", {"25"}, ""},
      {"--max-rate", {"55"}, ""},
      {"--upstroke-rate", {"12"}, ""},
      {"--max-upstroke-rate",
       {"40"},
       "--max-upstroke-rate: has no effect without --network mirror"},
      {"--mixer-headroom", {"0.2"}, ""},
      {"--amplitude", {"1.0"}, ""},
      {"--stroke-offset", {"0.1"}, ""},
      {"--control-period", {"0.01"}, ""},
      {"--roll", {"0.1", "0.3"}, ""},
      {"--pitch", {"0.2"}, ""},
      {"--link-axis", {"pitch"}, "--link-axis: has no effect on a single unit"},
      {"--link-stiffness", {"3"}, "--link-stiffness: has no effect on a single unit"},
      {"--start-rate", {"2"}, ""},
      {"--gust", {"1"}, ""},
      {"--wind", {"0.5", "1"}, ""},
      {"--noise", {"0.05"}, ""},
      {"--altitude-noise", {"0.1"}, "near"},
      {"--velocity-noise", {"0.1"}, "--velocity-noise: has no effect without a climb input"},
      {"--gyro-bias", {"0.02"}, ""},
      {"--turbulence", {"light"}, ""},
      {"--real-air", {}, "--real-air: for --preset hover or morph"},
      {"--gust-torque", {"0.1"}, ""},
      {"--gust-torque-time", {"0.2"}, ""},
      {"--gust-force", {"0.5"}, ""},
      {"--gust-force-time", {"0.1"}, ""},
      {"--gust-link", {"unit0_wing_left"}, ""},
      {"--altitude", {"1", "3"}, ""},
      {"--altitude-hold", {"off"}, ""},
      {"--step-sizes", {"0.0005"}, ""},
      {"--turn-substep", {"0.001"}, ""},
      {"--flip-penalty", {"5"}, ""},
      {"--crash-height", {"1.5"}, ""},
      {"--settle", {"3"}, "--settle: has no effect"},
      {"--upright-floor", {"0.99", "5"}, "--upright-floor: has no effect with --settle at or"},
      {"--rms-ceiling", {"0.01", "5"}, "--rms-ceiling: has no effect with --settle at or"},
      {"--payload", {"0.005"}, "--payload: has no effect but with --preset morph"},
      {"--motor-specific-power",
       {"300"},
       "--motor-specific-power: has no effect but with --preset morph"},
      {"--power-weight", {"2"}, "--power-weight: has no effect but with --preset morph"},
      {"--selection", {"nsga2"}, "--selection: has no effect but with --preset morph"},
      {"--motor-work", {"servo"}, "--motor-work: has no effect but with --preset hover or morph"},
      {"--network", {"paper"}, ""},
      {"--hidden", {"3"}, ""},
      {"--rate-inputs", {"off"}, ""},
      {"--rate-scale", {"5"}, ""},
      {"--altitude-input", {"off"}, ""},
      {"--altitude-scale", {"2"}, "near"},
      {"--climb-input", {"on"}, ""},
      {"--climb-scale", {"2"}, "--climb-scale: has no effect without a climb input"},
      {"--chain-input", {"on"}, "--chain-input: has no effect on a single unit"},
      {"--com-drop", {"0.03"}, ""},
      {"--phase-lock", {"off"}, ""},
      {"--pitch-gain", {"1"}, "--pitch-gain: has no effect on a single unit"},
      {"--gene-range", {"5"}, ""},
      {"--air-model", {"quasi_steady"}, ""},
      {"--added-mass-products", {"kirchhoff"}, ""},
  };
}

// The flags evolve's usage lists, but the tool's own (threads, files, the farm).
std::vector<std::string> listedFlags() {
  const std::vector<std::string> tool = {
      "--threads",   "--out",  "--weights",      "--no-plot",   "--resume",        "--init",
      "--init-body", "--farm", "--farm-timeout", "--farm-wait", "--farm-inflight", "--farm-batch"};
  std::vector<std::string> listed;
  std::istringstream usage(evolveUsage());
  for (std::string line; std::getline(usage, line);) {
    if (line.rfind("  --", 0) != 0) continue;
    const std::string name = line.substr(2, line.find(' ', 2) - 2);
    if (std::find(tool.begin(), tool.end(), name) == tool.end()) listed.push_back(name);
  }
  return listed;
}

TEST(EvolveFlags, EveryFlagOfTheFlapPresetsChangesWhatEvolvesOrIsRefusedByName) {
  const Evolved plain = evolveWith(kBase);
  ASSERT_EQ(plain.refused, "");
  const auto tried = triedFlags();
  std::vector<std::string> walked;
  for (const auto& t : tried) walked.push_back(std::get<0>(t));
  EXPECT_EQ(walked, listedFlags());
  for (const auto& [flag, values, refusal] : tried) {
    SCOPED_TRACE(flag);
    if (refusal == "near") {  // the altitude input acts inside its clamp: setpoints near 1 m
      const std::vector<std::string> near = withFlag(kBase, "--altitude", {"0.9", "1.1"});
      EXPECT_NE(evolveWith(withFlag(near, flag, values)).figures, evolveWith(near).figures);
      continue;
    }
    const Evolved e = evolveWith(withFlag(kBase, flag, values));
    if (refusal.empty()) {
      EXPECT_EQ(e.refused, "");
      EXPECT_NE(e.figures, plain.figures);
    } else {
      EXPECT_EQ(e.refused.rfind(refusal, 0), 0u) << e.refused;
    }
  }
  // The flip penalty and the crash height act only on a flip or a crash: from starts rolled
  // 1.5 rad (nearly on their backs) some episode flips within its second.
  const std::vector<std::string> rolled = withFlag(kBase, "--roll", {"1.5", "1.5"});
  EXPECT_NE(evolveWith(withFlag(rolled, "--flip-penalty", {"5"})).figures,
            evolveWith(rolled).figures);
  // The upright floor acts on the samples after --settle (the preset's 10 s: none in 1 s).
  const std::vector<std::string> settled = withFlag(kBase, "--settle", {"0.5"});
  const Evolved floored = evolveWith(withFlag(settled, "--upright-floor", {"0.99", "5"}));
  EXPECT_EQ(floored.refused, "");
  EXPECT_NE(floored.figures, evolveWith(settled).figures);
  const Evolved capped = evolveWith(withFlag(settled, "--rms-ceiling", {"0.01", "5"}));
  EXPECT_EQ(capped.refused, "");
  EXPECT_NE(capped.figures, evolveWith(settled).figures);
}

// The inputs' scales, the mixer's headroom, the phase lock and the chain pitch term change what
// a network's weights command as the stroke settings do: a file flown with others is refused by
// key, naming the flag that would match it (until 7 December 2026 evolve seeded from it and
// wrote its own, silently).
TEST(EvolveInit, RefusesAFileWhoseInputScalesMixerPhaseLockOrPitchTermAreNotTheEvolutions) {
  const std::string source =
      std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_1_shed_floor_weights.yaml";
  const ControllerSpec spec = loadControllerYaml(source);
  std::optional<EvolveCheckpoint> resume;
  const std::vector<std::string> evolution = {"--max-upstroke-rate", "65", "--phase-lock", "off",
                                              "--climb-input",       "on"};
  // refused(args, file): the message resolving `args` with --init `file` throws ("" if none).
  auto refused = [&](std::vector<std::string> args, const std::string& file) {
    args.insert(args.begin(), {"--init", file});
    try {
      resolveEvolveOptions(args, 1, resume);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ASSERT_EQ(refused(evolution, source), "");
  auto withScale = [&](const std::string& key, double FlapControllerParams::*scale,
                       const std::string& flag) {
    ControllerSpec scaled = spec;
    scaled.params.*scale = 2.5;
    const std::string path = ::testing::TempDir() + "afc_1_" + key + ".yaml";
    writeTextFile(path, controllerToYaml(scaled));
    EXPECT_EQ(refused(evolution, path),
              "--init: " + path + ": its " + key + " is 2.5, the evolution's " +
                  (key == "rate_scale" ? "10" : "1") + " (give " + flag + " 2.5)");
    std::vector<std::string> matching = evolution;
    matching.insert(matching.end(), {flag, "2.5"});
    matching.insert(matching.begin(), {"--init", path});
    EXPECT_EQ(resolveEvolveOptions(matching, 1, resume).params.controller.*scale, 2.5);
  };
  withScale("rate_scale", &FlapControllerParams::rate_scale, "--rate-scale");
  withScale("altitude_scale", &FlapControllerParams::altitude_scale, "--altitude-scale");
  withScale("climb_scale", &FlapControllerParams::climb_scale, "--climb-scale");
  const std::string mixer =
      std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_1_mixer_seed_weights.yaml";
  EXPECT_EQ(refused(evolution, mixer), "--init: " + mixer +
                                           ": its mixer_headroom is 0.1, the evolution's 0 (give "
                                           "--mixer-headroom 0.1)");
  std::vector<std::string> mixed = evolution;
  mixed.insert(mixed.end(), {"--mixer-headroom", "0.1"});
  EXPECT_EQ(refused(mixed, mixer), "");
  EXPECT_EQ(refused(mixed, source), "--init: " + source +
                                        ": its mixer_headroom is 0, the evolution's 0.1 (give "
                                        "--mixer-headroom 0)");
  // An input the net does not have: its scale does not count.
  ControllerSpec no_climb =
      loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_1_real_air_weights.yaml");
  ASSERT_FALSE(no_climb.params.climb_input);
  no_climb.params.climb_scale = 2.5;
  const std::string unused = ::testing::TempDir() + "afc_1_unused_climb_scale.yaml";
  writeTextFile(unused, controllerToYaml(no_climb));
  EXPECT_EQ(refused({"--max-upstroke-rate", "65", "--phase-lock", "off"}, unused), "");
  // config/afc_4_weights.yaml: the paper's network with the phase lock and the chain pitch term
  // (pitch_gain 1, its rates up to 85 rad/s), here on a chain of two units.
  const std::string chain = std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_4_weights.yaml";
  const std::vector<std::string> paper = {"--network",        "paper", "--rate-inputs", "off",
                                          "--altitude-input", "off",   "--hidden",      "2",
                                          "--max-rate",       "80"};
  auto plus = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  EXPECT_EQ(
      refused(plus(paper, {"--pairs", "2", "--phase-lock", "off"}), chain),
      "--init: " + chain + ": its phase_lock is on, the evolution's off (give --phase-lock on)");
  EXPECT_EQ(refused(plus(paper, {"--pairs", "2"}), chain),
            "--init: " + chain + ": its pitch_gain is 1, the evolution's 0 (give --pitch-gain 1)");
  EXPECT_EQ(refused(plus(paper, {"--pairs", "2", "--pitch-gain", "1"}), chain),
            "--init: " + chain +
                ": its pitch_max_downstroke_rate is 85, the evolution's 80 (set by hand, not "
                "evolved: seed from a file without it)");
  // On one unit the pitch term does nothing: the file passes every setting checked before its
  // attitude filter (set by hand), which refuses it.
  EXPECT_EQ(refused(paper, chain),
            "--init: " + chain +
                ": its attitude_filter_time is 0.05, the evolution's 0 (set by hand, not evolved: "
                "seed from a file without it)");
}

// An input's scale means nothing without its input: each is refused by name without it (and
// the climb scale, which the walk above tries without its input, acts with it).
TEST(EvolveFlags, EachInputScaleIsRefusedWithoutItsInputAndTheClimbScaleActsWithIt) {
  EXPECT_EQ(evolveWith(withFlag(withFlag(kBase, "--rate-inputs", {"off"}), "--rate-scale", {"5"}))
                .refused,
            "--rate-scale: has no effect without the rate inputs (--rate-inputs on)");
  EXPECT_EQ(
      evolveWith(withFlag(withFlag(kBase, "--altitude-input", {"off"}), "--altitude-scale", {"2"}))
          .refused,
      "--altitude-scale: has no effect without an altitude input (--altitude-input on)");
  // With its input on, the climb input's scale changes what evolves.
  const std::vector<std::string> climbing = withFlag(kBase, "--climb-input", {"on"});
  const Evolved scaled = evolveWith(withFlag(climbing, "--climb-scale", {"0.2"}));
  EXPECT_EQ(scaled.refused, "");
  EXPECT_NE(scaled.figures, evolveWith(climbing).figures);
}

}  // namespace
}  // namespace flapsim
