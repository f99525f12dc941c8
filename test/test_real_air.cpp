// Real air's draws for one flight (flapsim/real_air.h): those of flight_check --real-air's first
// start, deterministic, with realAirParams' magnitudes; bad parameters refused by name; the
// text `disturbance --print` writes; the evolution's upright floor, real air's bar in the
// fitness.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "flapsim/evolve.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"
#include "flapsim/real_air.h"
#include "flapsim/turbulence.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

// The message of the InputError `f` throws ("" if none).
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RealAirDraws, TheSameSeedDrawsTheSameAndAnotherSeedOthers) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  RealAirDrawParams p;
  p.seed = 7;
  const RealAirDraws a = realAirDraws(*afc, p), b = realAirDraws(*afc, p);
  EXPECT_EQ(a.wind, b.wind);
  EXPECT_EQ(a.gyro_bias, b.gyro_bias);
  EXPECT_EQ(a.torque, b.torque);
  EXPECT_EQ(a.torque_time, b.torque_time);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.force_time, b.force_time);
  EXPECT_EQ(a.force_link, b.force_link);
  p.seed = 8;
  const RealAirDraws c = realAirDraws(*afc, p);
  EXPECT_NE(a.torque_time, c.torque_time);
  EXPECT_NE(a.force_time, c.force_time);
  EXPECT_NE(a.wind, c.wind);
  EXPECT_NE(a.gyro_bias, c.gyro_bias);
}

// afc_1: 0.043 N m and 0.90 N (flight_check.h), for 0.5 s and 0.2 s, at times in 10-60 % of the
// flight; the wind 1 m/s, horizontal; the gyro bias at most 0.02 rad/s; a wing pushed.
TEST(RealAirDraws, MagnitudesAreRealAirParamsOfAfc1AndTimesInTheWindow) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  const FlightCheckParams real = realAirParams(FlightCheckParams(), *afc);
  std::vector<std::string> links;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    RealAirDrawParams p;
    p.seed = seed;
    const RealAirDraws d = realAirDraws(*afc, p);
    EXPECT_EQ(std::abs(d.torque), real.gust_torque);
    EXPECT_NEAR(std::abs(d.torque), 0.043, 0.0005);
    EXPECT_EQ(std::abs(d.force), real.gust_force);
    EXPECT_NEAR(std::abs(d.force), 0.90, 0.005);
    EXPECT_EQ(d.torque_duration, 0.5);
    EXPECT_EQ(d.force_duration, 0.2);
    EXPECT_GE(d.torque_time, 6.0);
    EXPECT_LE(d.torque_time, 36.0);
    EXPECT_GE(d.force_time, 6.0);
    EXPECT_LE(d.force_time, 36.0);
    EXPECT_NEAR(d.wind.norm(), 1.0, 1e-12);
    EXPECT_EQ(d.wind.z(), 0.0);
    EXPECT_LE(d.gyro_bias.norm(), 0.02);
    EXPECT_TRUE(d.force_link == "unit0_wing_left" || d.force_link == "unit0_wing_right")
        << d.force_link;
    links.push_back(d.force_link + (d.torque > 0 ? "+" : "-"));
  }
  std::sort(links.begin(), links.end());
  EXPECT_GE(std::unique(links.begin(), links.end()) - links.begin(), 3)
      << "both wings and both signs are drawn";
}

// The draws are those flight_check --real-air flies on its first start, whatever --starts.
TEST(RealAirDraws, AreTheFirstStartOfFlightCheckRealAir) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  FlightCheckParams check;
  check.seed = 31;
  check.starts = 5;
  check.duration = 30.0;
  check.real_air = true;
  const FlightCheckParams real = realAirParams(check, *afc);
  const EpisodeStart first = episodeStarts(flightCheckEpisodes(real), afc.get()).front();
  RealAirDrawParams p;
  p.seed = 31;
  p.duration = 30.0;
  const RealAirDraws d = realAirDraws(*afc, p);
  EXPECT_EQ(d.wind, first.wind);
  EXPECT_EQ(d.gyro_bias, first.gyro_bias);
  EXPECT_EQ(d.torque, first.torque_sign * real.gust_torque);
  EXPECT_EQ(d.torque_time, first.torque_time);
  EXPECT_EQ(d.force, first.force_sign * real.gust_force);
  EXPECT_EQ(d.force_time, first.force_time);
  EXPECT_EQ(d.force_link, first.force_link);
  EXPECT_GE(d.torque_time, 3.0);
  EXPECT_LE(d.torque_time, 18.0);
}

TEST(RealAirDraws, GivenSizesReplaceRealAirsAndKeepTheDrawnSignsAndTimes) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  RealAirDrawParams p;
  const RealAirDraws real = realAirDraws(*afc, p);
  p.torque = 0.1;
  p.force = 0.0;
  const RealAirDraws given = realAirDraws(*afc, p);
  EXPECT_EQ(given.torque, std::copysign(0.1, real.torque));
  EXPECT_EQ(given.torque_time, real.torque_time);
  EXPECT_EQ(given.force, 0.0);
  EXPECT_EQ(given.force_time, real.force_time);
  EXPECT_EQ(given.wind, real.wind);
  EXPECT_EQ(given.gyro_bias, real.gyro_bias);
}

// flight_check --real-air --wind 2 --turbulence moderate (the report beside the bar):
// the wind and turbulence given replace real air's 1 m/s and light, the wind's drawn heading,
// the impulses and the sensors' noises stay real air's, and the report names the air flown.
TEST(RealAirDraws, FlightChecksWindAndTurbulenceReplaceRealAirsAndKeepTheRest) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  FlightCheckOptions given, plain;
  CliParser given_cli = flightCheckCli(given), plain_cli = flightCheckCli(plain);
  const std::vector<CliSeen> seen =
      given_cli.parse({"--real-air", "--wind", "2", "--turbulence", "moderate"});
  EXPECT_EQ(flightCheckUnusedFlag(given, seen), "");
  takeRealAirSizes(given, seen);
  takeRealAirSizes(plain, plain_cli.parse({"--real-air"}));
  const FlightCheckParams real = realAirParams(plain.params, *afc);
  const FlightCheckParams moderate = realAirParams(given.params, *afc);
  EXPECT_EQ(real.wind, 1.0);
  EXPECT_EQ(real.turbulence, turbulenceLevelWind("light"));
  EXPECT_EQ(moderate.wind, 2.0);
  EXPECT_EQ(moderate.turbulence, turbulenceLevelWind("moderate"));
  EXPECT_EQ(moderate.gust_torque, real.gust_torque);
  EXPECT_EQ(moderate.gust_force, real.gust_force);
  EXPECT_EQ(moderate.noise, real.noise);
  EXPECT_EQ(moderate.gyro_bias, real.gyro_bias);
  EXPECT_EQ(moderate.altitude_noise, real.altitude_noise);
  const EpisodeStart a = episodeStarts(flightCheckEpisodes(real), afc.get()).front();
  const EpisodeStart b = episodeStarts(flightCheckEpisodes(moderate), afc.get()).front();
  EXPECT_NEAR((b.wind - 2.0 * a.wind).norm(), 0.0, 1e-12);
  EXPECT_EQ(b.torque_time, a.torque_time);
  EXPECT_EQ(realAirName(real), "real air");
  EXPECT_EQ(realAirName(moderate), "real air, wind 2 m/s, turbulence W20 15.43 m/s");
  FlightCheckOptions still;
  CliParser still_cli = flightCheckCli(still);
  takeRealAirSizes(still, still_cli.parse({"--real-air", "--wind", "0", "--turbulence", "none"}));
  const FlightCheckParams calm = realAirParams(still.params, *afc);
  EXPECT_EQ(calm.wind, 0.0);
  EXPECT_EQ(calm.turbulence, 0.0);
  EXPECT_EQ(realAirName(still.params), "real air, wind 0 m/s, no turbulence");
}

TEST(RealAirDraws, BadParametersAreRefusedByName) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  RealAirDrawParams p;
  p.torque = -0.1;
  EXPECT_NE(refusal([&] { realAirDraws(*afc, p); }).find("torque must be in [0, "),
            std::string::npos);
  p.torque = std::nan("");
  EXPECT_NE(refusal([&] { realAirDraws(*afc, p); }).find("torque"), std::string::npos);
  p.torque.reset();
  p.force = -1.0;
  EXPECT_NE(refusal([&] { realAirDraws(*afc, p); }).find("force must be in [0, "),
            std::string::npos);
  p.force.reset();
  p.duration = 0.0;
  EXPECT_NE(refusal([&] { realAirDraws(*afc, p); }).find("duration must be in (0, "),
            std::string::npos);
}

// The plate (0.2 x 0.2 x 0.002 m, 10 g, no wing): real air's torque is 0.5 x m g x 0.1 m, its
// roll inertia m (b^2 + c^2) / 12, so the torque spins it at 1.5 g b / (b^2 + c^2) = 73.568
// rad/s whatever its mass; and so it does in vacuum, the torque applied for its 0.5 s. No wing:
// no push.
TEST(RealAirSpinUp, ThePlateSpinsAtTheTorquesImpulseOverItsBoxInertia) {
  const CreatureModelPtr plate = test::loadUrdf("plate.urdf");
  const RealAirSpinUp s = realAirSpinUp(*plate);
  const double b = 0.2, c = 0.002;
  EXPECT_NEAR(s.roll_inertia, 0.01 * (b * b + c * c) / 12.0, 1e-12);
  EXPECT_NEAR(s.torque_rate, 1.5 * 9.81 * b / (b * b + c * c), 1e-6);  // the URDF: 9 digits
  EXPECT_EQ(s.push_arm, 0.0);
  EXPECT_EQ(s.push_rate, 0.0);
  WorldParams params;
  params.ground = false;
  params.air.enabled = false;
  params.gravity = Vec3::Zero();
  World world(params);
  world.spawn("plate", plate, Pose());
  ExternalWrench torque;
  torque.torque = Vec3(s.impulses.torque, 0.0, 0.0);
  torque.duration = s.impulses.torque_duration;
  world.applyWrench("plate", torque);
  world.step(600);
  EXPECT_NEAR(world.state("plate").link_twists[0].angular.x(), s.torque_rate, 1e-9);
}

TEST(RealAirPrint, TheWindAndGyroBiasAreYamlListsOfEveryBit) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  RealAirPrintOptions o;
  const RealAirDraws d = realAirDraws(*afc, o.draw);
  for (const std::string what : {"wind", "gyro_bias"}) {
    o.print = what;
    const std::string text = realAirPrint(o, d);
    const Vec3 want = what == "wind" ? d.wind : d.gyro_bias;
    ASSERT_EQ(text.front(), '[') << text;
    char* end = nullptr;
    const double x = std::strtod(text.c_str() + 1, &end);
    const double y = std::strtod(end + 1, &end);
    const double z = std::strtod(end + 1, &end);
    EXPECT_EQ(std::string(end), "]\n");
    EXPECT_EQ(Vec3(x, y, z), want) << text;
  }
  o.print = "all";
  EXPECT_NE(realAirPrint(o, d).find("push"), std::string::npos);
}

TEST(RealAirPrint, FlagsAreCheckedByName) {
  RealAirPrintOptions o;
  CliParser cli = realAirPrintCli(o);
  EXPECT_NE(refusal([&] { cli.parse({"--print", "storm"}); }).find("--print"), std::string::npos);
  EXPECT_NE(refusal([&] {
              cli.parse({"--duration", "-1"});
            }).find("--duration"),
            std::string::npos);
  cli.parse({"--print", "wind", "--seed", "12", "--urdf", "x.urdf", "--duration", "30"});
  EXPECT_EQ(o.print, "wind");
  EXPECT_EQ(o.draw.seed, 12u);
  EXPECT_EQ(o.urdf, "x.urdf");
  EXPECT_EQ(o.draw.duration, 30.0);
}

// A gust acts from its drawn time on: the flight is the still one, bit for bit, up to the
// sample it starts at, and another after it (the roll torque of 0.05 N m for 0.5 s, and the
// 1 N push on a drawn wing for 0.2 s).
TEST(Episodes, GustsActFromTheirDrawnTimeOn) {
  EpisodeParams p;
  p.duration = 2.0;
  p.gust_window_start = 0.25;
  p.gust_window_end = 0.5;
  const CreatureModelPtr unit = parseCreatureModel(makeCreatureUrdf(1, "afc"), "afc1");
  const OpenLoopWingController open(StrokeCommand{40, 10, 1.2});
  const EpisodeResult still = runEpisode(unit, open, 0.02, p, attitudeStart(0.05, 0.0), true);
  for (const bool torque : {true, false}) {
    EpisodeParams g = p;
    (torque ? g.gust_torque : g.gust_force) = torque ? 0.05 : 1.0;
    const EpisodeStart start = episodeStarts(g, unit.get()).front();
    EpisodeStart at = attitudeStart(0.05, 0.0);
    at.torque_time = start.torque_time;
    at.torque_sign = start.torque_sign;
    at.force_time = start.force_time;
    at.force_sign = start.force_sign;
    at.force_link = start.force_link;
    const double t = torque ? at.torque_time : at.force_time;
    ASSERT_GE(t, 0.5);
    ASSERT_LE(t, 1.0);
    const EpisodeResult r = runEpisode(unit, open, 0.02, g, at, true);
    const size_t first = static_cast<size_t>(std::floor(t / 0.02));
    for (size_t i = 0; i < first; ++i) {
      ASSERT_EQ(r.trace[i].height, still.trace[i].height) << i;
      ASSERT_EQ(r.trace[i].upright, still.trace[i].upright) << i;
    }
    EXPECT_NE(r.trace[first].upright, still.trace[first].upright) << (torque ? "torque" : "push");
  }
}

// evolve --upright-floor U W: an episode whose lowest up-component after settling falls below
// U scores W m less per unit below it, to the bit; a floor under that lowest changes nothing.
// A second of the open-loop flap unit holding an altitude, settled after half of it: the
// episode of the settled terms' tests.
EpisodeParams settledSecond() {
  EpisodeParams p;
  p.duration = 1.0;
  p.settle_time = 0.5;
  p.altitude_hold = true;
  return p;
}

TEST(UprightFloor, TakesWPerUnitOfTheLowestUpComponentBelowTheFloorAfterSettling) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  const OpenLoopWingController open(StrokeCommand{40, 10, 1.2});
  EpisodeParams p = settledSecond();
  EpisodeStart start;
  start.roll = 0.3;
  start.altitude = 1.0;
  const EpisodeResult off = runEpisode(afc, open, 0.02, p, start);
  ASSERT_LT(off.min_upright_settled, 0.99);  // the open-loop unit tips: the term is not zero
  p.upright_floor = 1.0;
  p.upright_floor_weight = 7.0;
  const EpisodeResult on = runEpisode(afc, open, 0.02, p, start);
  EXPECT_EQ(on.fitness, off.fitness - 7.0 * (1.0 - off.min_upright_settled));
  p.upright_floor = off.min_upright_settled - 0.01;
  EXPECT_EQ(runEpisode(afc, open, 0.02, p, start).fitness, off.fitness);
  p.upright_floor = 1.5;
  EXPECT_NE(validateEpisodeParams(p).find("upright_floor must be"), std::string::npos);
}

// evolve --rms-ceiling R W: an episode whose altitude rms after settling exceeds R m scores W m
// less per m over it, to the bit; a ceiling above that rms changes nothing.
TEST(RmsCeiling, TakesWPerMetreOfTheAltitudeRmsAboveTheCeilingAfterSettling) {
  const CreatureModelPtr afc = test::loadUrdf("afc_1.urdf");
  const OpenLoopWingController open(StrokeCommand{40, 10, 1.2});
  EpisodeParams p = settledSecond();
  EpisodeStart start;
  start.altitude = 3.0;  // 2 m above the start: the open-loop unit misses it by metres
  const EpisodeResult off = runEpisode(afc, open, 0.02, p, start);
  ASSERT_GT(off.altitude_rms, 1.0);
  p.altitude_rms_ceiling = 0.3;
  p.altitude_rms_weight = 2.0;
  const EpisodeResult on = runEpisode(afc, open, 0.02, p, start);
  EXPECT_EQ(on.altitude_rms, off.altitude_rms);
  EXPECT_EQ(on.fitness, off.fitness - 2.0 * (off.altitude_rms - 0.3));
  p.altitude_rms_ceiling = off.altitude_rms + 0.01;
  EXPECT_EQ(runEpisode(afc, open, 0.02, p, start).fitness, off.fitness);
  p.altitude_rms_ceiling = -0.1;
  EXPECT_NE(validateEpisodeParams(p).find("altitude_rms_ceiling must be"), std::string::npos);
}

}  // namespace
}  // namespace flapsim
