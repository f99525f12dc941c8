// The feed-forward net and the paper's per-wing-pair controller.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "flapsim/ann.h"
#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"
#include "flapsim/ga.h"
#include "flapsim/make_creature.h"

namespace flapsim {
namespace {

// Hidden: h0 = tanh(x0), h1 = tanh(2 x1 + 0.5); outputs: sigmoid(h0 - h1),
// sigmoid(0.5 h0 + 0.5 h1 - 1). Layout: per neuron, input weights then bias.
const std::vector<double> kWeights = {1, 0, 0, 0, 2, 0.5, 1, -1, 0, 0.5, 0.5, -1};

TEST(FeedForwardNet, KnownWeightsGiveKnownOutputs) {
  FeedForwardNet net({2, 2, 2}, Activation::kTanh, Activation::kSigmoid);
  EXPECT_EQ(net.parameterCount(), 12);
  net.setParameters(kWeights);
  const std::vector<double> y = net.evaluate({0.3, -0.2});
  ASSERT_EQ(y.size(), 2u);
  // Computed by hand (Python math): h0 = tanh(0.3), h1 = tanh(0.1).
  EXPECT_NEAR(y[0], 0.5477650523180715, 1e-15);
  EXPECT_NEAR(y[1], 0.30906167845270577, 1e-15);

  FeedForwardNet linear({1, 1}, Activation::kLinear, Activation::kLinear);
  linear.setParameters({-2.5, 0.75});
  EXPECT_DOUBLE_EQ(linear.evaluate({2.0})[0], -4.25);
}

TEST(FeedForwardNet, DeeperNetsCountAndChainTheirLayers) {
  EXPECT_EQ(FeedForwardNet::parameterCount({3, 4, 5, 1}), 4 * 4 + 5 * 5 + 1 * 6);
  FeedForwardNet net({1, 1, 1, 1}, Activation::kLinear, Activation::kLinear);
  net.setParameters({2, 1, 3, 0, -1, 4});  // ((2x + 1) * 3) * -1 + 4
  EXPECT_DOUBLE_EQ(net.evaluate({1.0})[0], -5.0);
}

TEST(FeedForwardNet, BadShapesAndValuesAreRefused) {
  EXPECT_THROW(FeedForwardNet({2}, Activation::kTanh, Activation::kTanh), std::invalid_argument);
  EXPECT_THROW(FeedForwardNet({2, 0, 1}, Activation::kTanh, Activation::kTanh),
               std::invalid_argument);
  FeedForwardNet net({2, 2, 2}, Activation::kTanh, Activation::kSigmoid);
  EXPECT_THROW(net.setParameters(std::vector<double>(11, 0.0)), std::invalid_argument);
  std::vector<double> nan(12, 0.0);
  nan[3] = std::nan("");
  EXPECT_THROW(net.setParameters(nan), std::invalid_argument);
  EXPECT_THROW(net.evaluate({1.0}), std::invalid_argument);
  EXPECT_THROW(activationFromString("relu"), std::invalid_argument);
  EXPECT_EQ(activationFromString(toString(Activation::kSigmoid)), Activation::kSigmoid);
}

TEST(FlapInputs, AreTheVerticalComponentsOfForwardAndWingAxes) {
  const std::vector<double> level = flapInputs(Quat::Identity());
  EXPECT_DOUBLE_EQ(level[0], 0.0);
  EXPECT_DOUBLE_EQ(level[1], 0.0);
  // Rolled right by 0.2 rad (about +x): the left wing axis (+y) rises.
  const std::vector<double> right = flapInputs(Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())));
  EXPECT_NEAR(right[0], 0.0, 1e-15);
  EXPECT_NEAR(right[1], std::sin(0.2), 1e-15);
  // Nose up by 0.3 rad (about -y): the forward axis rises.
  const std::vector<double> up = flapInputs(Quat(Eigen::AngleAxisd(-0.3, Vec3::UnitY())));
  EXPECT_NEAR(up[0], std::sin(0.3), 1e-15);
  EXPECT_NEAR(up[1], 0.0, 1e-15);
  // Yaw changes nothing.
  const std::vector<double> yawed = flapInputs(Quat(Eigen::AngleAxisd(1.0, Vec3::UnitZ())) *
                                               Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())));
  EXPECT_NEAR(yawed[1], std::sin(0.2), 1e-15);
}

TEST(FlapUnitController, MapsOutputsIntoTheRateRangeRightFirst) {
  FlapControllerParams p;
  p.min_downstroke_rate = 20.0;
  p.max_downstroke_rate = 70.0;
  p.upstroke_rate = 12.0;
  p.amplitude = 0.7;
  const FlapUnitController c(p, kWeights);
  const std::vector<double> r = c.rates({0.3, -0.2});
  EXPECT_NEAR(r[0], 47.388252615903575, 1e-12);  // 20 + 50 * 0.54776...
  EXPECT_NEAR(r[1], 35.45308392263529, 1e-12);

  // All-zero weights: both sigmoids at 0.5, the middle of the range, any attitude.
  const FlapUnitController zero(p, std::vector<double>(12, 0.0));
  const WingPairCommand cmd = zero.command(Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX())));
  EXPECT_DOUBLE_EQ(cmd.left.downstroke_rate, 45.0);
  EXPECT_DOUBLE_EQ(cmd.right.downstroke_rate, 45.0);
  EXPECT_DOUBLE_EQ(cmd.left.upstroke_rate, 12.0);
  EXPECT_DOUBLE_EQ(cmd.right.amplitude, 0.7);
  EXPECT_EQ(cmd.left.offset, 0.0);
  p.stroke_offset = 0.25;  // both wings' strokes about the raised mean angle
  const WingPairCommand raised =
      FlapUnitController(p, std::vector<double>(12, 0.0)).command(Quat());
  EXPECT_EQ(raised.left.offset, 0.25);
  EXPECT_EQ(raised.right.offset, 0.25);
  EXPECT_EQ(FlapUnitController::weightCount(p), 12);
  p.hidden = 3;
  EXPECT_EQ(FlapUnitController::weightCount(p), 3 * 3 + 2 * 4);
}

TEST(FlapUnitController, ARollCorrectingNetStrokesTheLowWingHarder) {
  // Hidden h0 = tanh(5 wing_up); right = sigmoid(4 h0), left = sigmoid(-4 h0).
  const std::vector<double> w = {0, 5, 0, 0, 0, 0, 4, 0, 0, -4, 0, 0};
  const FlapUnitController c(FlapControllerParams(), w);
  const WingPairCommand rolled_right = c.command(Quat(Eigen::AngleAxisd(0.1, Vec3::UnitX())));
  EXPECT_GT(rolled_right.right.downstroke_rate, rolled_right.left.downstroke_rate + 20.0);
  const WingPairCommand rolled_left = c.command(Quat(Eigen::AngleAxisd(-0.1, Vec3::UnitX())));
  EXPECT_GT(rolled_left.left.downstroke_rate, rolled_left.right.downstroke_rate + 20.0);
  const WingPairCommand level = c.command(Quat::Identity());
  EXPECT_DOUBLE_EQ(level.left.downstroke_rate, level.right.downstroke_rate);
}

// Phase lock: whatever the downstroke rate, the stroke period 2 a (1/w1 + 1/w2) stays that
// of the middle rate (40 rad/s) with the upstroke rate (10 rad/s): 0.3 s at a = 1.2; the
// paper's controller keeps the upstroke rate.
TEST(FlapUnitController, PhaseLockKeepsTheStrokePeriod) {
  FlapControllerParams p;
  p.phase_lock = true;
  for (double w1 : {20.0, 33.0, 40.0, 60.0}) {
    const double w2 = upstrokeRate(p, w1);
    EXPECT_NEAR(2.0 * p.amplitude * (1.0 / w1 + 1.0 / w2), 0.3, 1e-12) << w1;
  }
  EXPECT_DOUBLE_EQ(upstrokeRate(p, 40.0), 10.0);
  p.phase_lock = false;
  EXPECT_EQ(upstrokeRate(p, 60.0), 10.0);
  p.phase_lock = true;
  p.min_downstroke_rate = 5.0;  // its downstroke (0.48 s) would not fit in the period
  EXPECT_NE(validateFlapControllerParams(p).find("phase_lock"), std::string::npos);
}

// Upstroke output: the mirror net's second output is each wing's upstroke rate, mapped onto
// [upstroke_rate, max_upstroke_rate]; the left wing's is the net on the mirrored inputs, so a
// level unit strokes both wings alike and a rolled one mirrors; the file keeps it.
TEST(FlapUnitController, AnUpstrokeOutputSetsEachWingsUpstrokeAndMirrors) {
  FlapControllerParams p;
  p.network = FlapNetwork::kMirror;
  p.upstroke_rate = 10.0;
  p.max_upstroke_rate = 60.0;
  EXPECT_EQ(flapOutputNames(p),
            (std::vector<std::string>{"right_downstroke_rate", "right_upstroke_rate"}));
  EXPECT_EQ(FlapUnitController::weightCount(p), 2 * 3 + 2 * 3);  // 2 hidden, 2 outputs
  // Hidden h0 = tanh(5 up.left); downstroke = sigmoid(0), upstroke = sigmoid(-4 h0): rolled
  // right (up.left > 0), the low right wing beats its upstroke slowly and the high left one
  // fast (the left's net sees up.left mirrored).
  const std::vector<double> w = {0, 5, 0, 0, 0, 0, 0, 0, 0, -4, 0, 0};
  const FlapUnitController c(p, w);
  const WingPairCommand level = c.command(Quat::Identity());
  EXPECT_DOUBLE_EQ(level.right.upstroke_rate, 35.0);  // sigmoid(0): the middle of 10..60
  EXPECT_DOUBLE_EQ(level.left.upstroke_rate, level.right.upstroke_rate);
  EXPECT_DOUBLE_EQ(level.right.downstroke_rate, 40.0);
  const WingPairCommand right_low = c.command(Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())));
  const WingPairCommand left_low = c.command(Quat(Eigen::AngleAxisd(-0.2, Vec3::UnitX())));
  EXPECT_GT(right_low.left.upstroke_rate, right_low.right.upstroke_rate + 20.0);
  EXPECT_DOUBLE_EQ(right_low.left.upstroke_rate, left_low.right.upstroke_rate);
  EXPECT_DOUBLE_EQ(right_low.right.upstroke_rate, left_low.left.upstroke_rate);
  for (const WingPairCommand& x : {right_low, left_low}) {
    for (const StrokeCommand& s : {x.left, x.right}) {
      EXPECT_GE(s.upstroke_rate, 10.0);
      EXPECT_LE(s.upstroke_rate, 60.0);
    }
  }
  const ControllerSpec back =
      controllerFromYaml(controllerToYaml(ControllerSpec{p, w}, "", {}), "round trip");
  EXPECT_EQ(back.params.max_upstroke_rate, 60.0);
  EXPECT_EQ(back.weights, w);
  p.phase_lock = true;
  EXPECT_NE(validateFlapControllerParams(p).find("phase_lock off"), std::string::npos);
  p.phase_lock = false;
  p.max_upstroke_rate = 5.0;
  EXPECT_NE(validateFlapControllerParams(p).find("max_upstroke_rate"), std::string::npos);
  p.max_upstroke_rate = 60.0;
  p.network = FlapNetwork::kPaper;
  EXPECT_NE(validateFlapControllerParams(p).find("network mirror"), std::string::npos);
}

// The chain pitch term: nose up (world_up . forward = sin 0.05 > 0) slows the nose unit and
// speeds the tail unit by gain * sin(0.05) each, leaves the middle unit and each unit's
// left/right ratio alone, is capped at pitch_limit, and does nothing to a single unit.
TEST(WingControllers, ChainPitchTermSlowsTheNoseAndSpeedsTheTailWhileTheNoseIsUp) {
  FlapControllerParams p;
  p.pitch_gain = 2.0;
  const double nose_up = std::sin(0.05);
  EXPECT_DOUBLE_EQ(chainPitchScale(p, 0, 3, nose_up), 1.0 - 2.0 * nose_up);
  EXPECT_DOUBLE_EQ(chainPitchScale(p, 1, 3, nose_up), 1.0);
  EXPECT_DOUBLE_EQ(chainPitchScale(p, 2, 3, nose_up), 1.0 + 2.0 * nose_up);
  EXPECT_DOUBLE_EQ(chainPitchScale(p, 0, 3, -0.5), 1.0 + p.pitch_limit);
  EXPECT_DOUBLE_EQ(chainPitchScale(p, 0, 1, nose_up), 1.0);
  // Hidden h0 = tanh(5 wing_up); right = sigmoid(4 h0), left = sigmoid(-4 h0): a rolled unit
  // strokes its wings at two rates, so the ratio is visible.
  const std::vector<double> w = {0, 5, 0, 0, 0, 0, 4, 0, 0, -4, 0, 0};
  // Pitched nose up 0.05 rad about y (negative: body y rotation > 0 is nose down), rolled 0.05.
  const Quat q =
      Quat(Eigen::AngleAxisd(-0.05, Vec3::UnitY())) * Quat(Eigen::AngleAxisd(0.05, Vec3::UnitX()));
  ASSERT_NEAR(flapInputs(q)[0], nose_up, 1e-12);
  const FlapUnitController plain(FlapControllerParams(), w);
  const std::vector<StrokeCommand> one = AnnWingController(plain).commands(FlapSensing({q}));
  const std::vector<StrokeCommand> chain =
      AnnWingController(FlapUnitController(p, w)).commands(FlapSensing({q, q, q}));
  ASSERT_EQ(chain.size(), 6u);
  for (int side = 0; side < 2; ++side) {
    EXPECT_DOUBLE_EQ(
        chain[side].downstroke_rate,
        std::max(p.min_downstroke_rate, (1.0 - 2.0 * nose_up) * one[side].downstroke_rate));
    EXPECT_DOUBLE_EQ(chain[2 + side].downstroke_rate, one[side].downstroke_rate);
    EXPECT_DOUBLE_EQ(chain[4 + side].downstroke_rate,
                     (1.0 + 2.0 * nose_up) * one[side].downstroke_rate);
    EXPECT_DOUBLE_EQ(chain[4 + side].upstroke_rate,
                     upstrokeRate(p, chain[4 + side].downstroke_rate));
  }
  EXPECT_NE(one[0].downstroke_rate, one[1].downstroke_rate);
  EXPECT_NEAR(chain[4].downstroke_rate / chain[5].downstroke_rate,
              one[0].downstroke_rate / one[1].downstroke_rate, 1e-12);
  // Beyond max_downstroke_rate, up to pitch_max_downstroke_rate.
  const Quat nose_down(Eigen::AngleAxisd(0.5, Vec3::UnitY()));
  p.pitch_limit = 0.5;
  const std::vector<double> fast = {0, 0, 0, 0, 0, 0, 0, 0, 50, 0, 0, 50};  // both at 60
  const std::vector<StrokeCommand> capped =
      AnnWingController(FlapUnitController(p, fast)).commands(FlapSensing({nose_down, nose_down}));
  EXPECT_DOUBLE_EQ(capped[0].downstroke_rate, p.pitch_max_downstroke_rate);
  EXPECT_DOUBLE_EQ(capped[2].downstroke_rate, 30.0);
}

// The chain input: unit k of n sees s_k p (s_k = 1 - 2k/(n-1), p the units' mean pitch input),
// so one network on every unit can beat the nose and the tail differently; a lone unit sees 0.
TEST(WingControllers, TheChainInputIsThePlaceAlongTheChainTimesItsMeanPitch) {
  EXPECT_DOUBLE_EQ(chainInput(0, 3, 0.2), 0.2);
  EXPECT_DOUBLE_EQ(chainInput(1, 3, 0.2), 0.0);
  EXPECT_DOUBLE_EQ(chainInput(2, 3, 0.2), -0.2);
  EXPECT_DOUBLE_EQ(chainInput(1, 4, 0.3), 0.3 / 3.0);
  EXPECT_DOUBLE_EQ(chainInput(0, 1, 0.2), 0.0);
  FlapControllerParams p;
  p.chain_input = true;
  p.network = FlapNetwork::kMirror;
  ASSERT_EQ(flapInputCount(p), 3);
  EXPECT_EQ(flapInputNames(p).back(), "chain_position.chain_pitch");
  // One hidden neuron h = tanh(10 chain input); the output sigmoid(-4 h): a nose up makes the
  // nose (input > 0) beat slower than half-way and the tail faster, both of a unit's wings
  // alike (the mirror leaves the chain input as it is).
  p.hidden = 1;
  ASSERT_EQ(FlapUnitController::weightCount(p), 4 + 2);
  const std::vector<double> w = {0, 0, 10, 0, -4, 0};
  // Units pitched 0.1, 0.05 and 0 rad nose up (negative rotation about y): the mean pitch.
  std::vector<Quat> bodies;
  double mean = 0.0;
  for (double pitch : {0.1, 0.05, 0.0}) {
    bodies.push_back(Quat(Eigen::AngleAxisd(-pitch, Vec3::UnitY())));
    mean += std::sin(pitch) / 3.0;
  }
  const std::vector<StrokeCommand> c =
      AnnWingController(FlapUnitController(p, w)).commands(FlapSensing(bodies));
  ASSERT_EQ(c.size(), 6u);
  const double middle = 0.5 * (p.min_downstroke_rate + p.max_downstroke_rate);
  const auto rate = [&](double input) {
    const double y = 1.0 / (1.0 + std::exp(4.0 * std::tanh(10.0 * input)));
    return p.min_downstroke_rate + (p.max_downstroke_rate - p.min_downstroke_rate) * y;
  };
  for (int side = 0; side < 2; ++side) {
    EXPECT_NEAR(c[side].downstroke_rate, rate(mean), 1e-12);
    EXPECT_DOUBLE_EQ(c[2 + side].downstroke_rate, middle);
    EXPECT_NEAR(c[4 + side].downstroke_rate, rate(-mean), 1e-12);
  }
  EXPECT_LT(c[0].downstroke_rate, middle - 5.0);
  EXPECT_GT(c[4].downstroke_rate, middle + 5.0);
  // Without the input the same pitches give every unit the same command.
  p.chain_input = false;
  const std::vector<StrokeCommand> plain =
      AnnWingController(FlapUnitController(p, {0, 0, 0, -4, 0})).commands(FlapSensing(bodies));
  EXPECT_DOUBLE_EQ(plain[0].downstroke_rate, plain[4].downstroke_rate);
}

// The climb input: the root's vertical speed in the world, from its velocity in its own axes
// turned by its attitude, over climb_scale and clamped to +-1; the same on both sides of the
// mirror (a climb is not handed), after the altitude error in the inputs.
TEST(WingControllers, TheClimbInputIsTheRootsVerticalSpeedInTheWorldOverItsScale) {
  FlapControllerParams p;
  p.network = FlapNetwork::kMirror;
  p.altitude_input = true;
  p.climb_input = true;
  p.climb_scale = 2.0;
  ASSERT_EQ(flapInputCount(p), 4);
  EXPECT_EQ(flapInputNames(p)[2], "altitude_error");
  EXPECT_EQ(flapInputNames(p)[3], "climb_rate");
  // Rolled 90 deg about x, the body's +y axis points up: 1.2 m/s along it is a climb of 1.2.
  const Quat rolled(Eigen::AngleAxisd(M_PI / 2.0, Vec3::UnitX()));
  EXPECT_NEAR(climbInput(p, rolled, Vec3(0.0, 1.2, 0.0)), 0.6, 1e-15);
  EXPECT_NEAR(climbInput(p, rolled, Vec3(0.0, 0.0, 1.2)), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(climbInput(p, Quat::Identity(), Vec3(0.0, 0.0, -3.0)), -1.0);
  EXPECT_DOUBLE_EQ(climbInput(p, Quat::Identity(), Vec3(0.0, 0.0, 5.0)), 1.0);
  const std::vector<double> x =
      flapNetworkInputs(p, Quat::Identity(), Vec3::Zero(), 0.25, 0.0, -0.4);
  ASSERT_EQ(x.size(), 4u);
  EXPECT_DOUBLE_EQ(x[2], 0.25);
  EXPECT_DOUBLE_EQ(x[3], -0.4);
  EXPECT_DOUBLE_EQ(mirroredInputs(p, x)[3], -0.4);
  // One hidden neuron h = tanh(3 climb input), the output sigmoid(-2 h): sinking (input < 0)
  // beats both wings faster than half-way, climbing slower.
  p.hidden = 1;
  ASSERT_EQ(FlapUnitController::weightCount(p), 5 + 2);
  const FlapUnitController unit(p, {0, 0, 0, 3, 0, -2, 0});
  const auto command = [&](double vz) {
    FlapSensing s({Quat::Identity()});
    s.velocity = Vec3(0.0, 0.0, vz);
    return AnnWingController(unit).commands(s);
  };
  const double middle = 0.5 * (p.min_downstroke_rate + p.max_downstroke_rate);
  const auto rate = [&](double input) {
    const double y = 1.0 / (1.0 + std::exp(2.0 * std::tanh(3.0 * input)));
    return p.min_downstroke_rate + (p.max_downstroke_rate - p.min_downstroke_rate) * y;
  };
  for (int side = 0; side < 2; ++side) {
    EXPECT_NEAR(command(-1.0)[side].downstroke_rate, rate(-0.5), 1e-12);
    EXPECT_NEAR(command(1.0)[side].downstroke_rate, rate(0.5), 1e-12);
    EXPECT_DOUBLE_EQ(command(0.0)[side].downstroke_rate, middle);
  }
  EXPECT_GT(command(-1.0)[0].downstroke_rate, middle + 5.0);
  // Without a velocity reading it does not guess.
  try {
    AnnWingController(unit).commands(FlapSensing({Quat::Identity()}));
    ADD_FAILURE() << "no velocity, no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("climb input needs the root's velocity"),
              std::string::npos)
        << e.what();
  }
  p.climb_scale = 0.0;
  EXPECT_NE(validateFlapControllerParams(p).find("climb_scale"), std::string::npos);
}

// Ground-speed damping: the up the units level to leans against the horizontal velocity
// (odometry's, in the root's axes) by velocity_gain |v| up to velocity_tilt_limit.
TEST(GroundSpeedDamping, LeansTheLevelledUpAgainstTheHorizontalVelocityUpToItsLimit) {
  FlapControllerParams p;
  p.velocity_gain = 0.1;
  p.velocity_tilt_limit = 0.05;
  const Quat level = Quat::Identity();
  auto expectUp = [](const Vec3& up, const Vec3& want) {
    EXPECT_NEAR((up - want).norm(), 0.0, 1e-15) << up.transpose() << " vs " << want.transpose();
  };
  // 0.3 m/s forward: leaned back by 0.03 rad
  expectUp(levelledUp(p, level, Vec3(0.3, 0, 0)), Vec3(-std::sin(0.03), 0, std::cos(0.03)));
  // the body's forward is the world's +y when it heads left (yaw 90 deg)
  const Quat heading_left(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  expectUp(levelledUp(p, heading_left, Vec3(0.3, 0, 0)), Vec3(0, -std::sin(0.03), std::cos(0.03)));
  // beyond 0.5 m/s the limit; climbing or sinking leans nothing; off: the world's up
  expectUp(levelledUp(p, level, Vec3(0, -2.0, 0)), Vec3(0, std::sin(0.05), std::cos(0.05)));
  EXPECT_EQ(levelledUp(p, level, Vec3(0, 0, 2.0)), Vec3::UnitZ());
  p.velocity_gain = 0.0;
  EXPECT_EQ(levelledUp(p, level, Vec3(0.3, 0, 0)), Vec3::UnitZ());
}

// What the damping does to the commands: a level chain moving forward at v commands what the
// chain at rest pitched nose down by velocity_gain v commands (so it pitches up to brake), and
// moving right what it commands rolled right wing low; the chain pitch term included.
TEST(GroundSpeedDamping, ALevelChainMovingCommandsWhatItCommandsAtRestTiltedTheOtherWay) {
  FlapControllerParams p;
  p.pitch_gain = 2.0;
  p.velocity_gain = 0.1;
  const AnnWingController damped(FlapUnitController(p, kWeights));
  auto chain = [](const Quat& q) { return FlapSensing({q, q, q}); };
  auto expectSame = [](const std::vector<StrokeCommand>& a, const std::vector<StrokeCommand>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_NEAR(a[i].downstroke_rate, b[i].downstroke_rate, 1e-9) << i;
      EXPECT_NEAR(a[i].upstroke_rate, b[i].upstroke_rate, 1e-9) << i;
    }
  };
  FlapSensing forward = chain(Quat::Identity());
  forward.velocity = Vec3(0.3, 0, 0);
  const Quat nose_down(Eigen::AngleAxisd(0.03, Vec3::UnitY()));
  const std::vector<StrokeCommand> moving = damped.commands(forward);
  expectSame(moving, damped.commands(chain(nose_down)));
  // and that is not what it commands level at rest: the nose and tail differ
  const std::vector<StrokeCommand> still = damped.commands(chain(Quat::Identity()));
  EXPECT_GT(std::abs(moving[0].downstroke_rate - still[0].downstroke_rate), 0.1);
  FlapSensing right = chain(Quat::Identity());
  right.velocity = Vec3(0, -0.3, 0);
  const Quat right_low(Eigen::AngleAxisd(0.03, Vec3::UnitX()));
  expectSame(damped.commands(right), damped.commands(chain(right_low)));
  // without a velocity reading, or with the gain 0, the level chain's commands at rest
  EXPECT_EQ(damped.commands(chain(Quat::Identity()))[0].downstroke_rate, still[0].downstroke_rate);
  p.velocity_gain = 0.0;
  EXPECT_EQ(AnnWingController(FlapUnitController(p, kWeights)).commands(forward)[0].downstroke_rate,
            still[0].downstroke_rate);
}

// The roll reflex: banked beyond roll_reflex_bank and still rolling over faster than
// roll_reflex_rate (body gyro), the low wing beats fast down / slow up, the high wing slow
// down / fast up; otherwise, and with the reflex off, the command stays the network's.
TEST(RollReflex, ActsOnlyWhileBankedAndRollingFurtherOverAndMirrors) {
  FlapControllerParams p;
  p.roll_reflex_bank = 0.4;
  p.roll_reflex_rate = 5.0;
  p.roll_reflex_fast_rate = 65.0;
  p.roll_reflex_slow_rate = 40.0;
  const WingPairCommand net{StrokeCommand{30, 10, 1.2}, StrokeCommand{31, 11, 1.2}};
  auto reflex = [&](double bank, double roll_rate, const FlapControllerParams& params,
                    WingPairCommand& c) {
    c = net;
    return applyRollReflex(params, Quat(Eigen::AngleAxisd(bank, Vec3::UnitX())),
                           Vec3(roll_rate, 0.3, -0.2), c);
  };
  WingPairCommand c;
  // right wing low (bank > 0), rolling further right: the right wing is the low one
  ASSERT_TRUE(reflex(0.45, 6.0, p, c));
  EXPECT_EQ(c.right.downstroke_rate, 65.0);
  EXPECT_EQ(c.right.upstroke_rate, 40.0);
  EXPECT_EQ(c.left.downstroke_rate, 40.0);
  EXPECT_EQ(c.left.upstroke_rate, 65.0);
  EXPECT_EQ(c.left.amplitude, 1.2);  // only the rates change
  // the mirror image: left wing low, rolling further left
  ASSERT_TRUE(reflex(-0.45, -6.0, p, c));
  EXPECT_EQ(c.left.downstroke_rate, 65.0);
  EXPECT_EQ(c.left.upstroke_rate, 40.0);
  EXPECT_EQ(c.right.downstroke_rate, 40.0);
  EXPECT_EQ(c.right.upstroke_rate, 65.0);
  // banked but rolling back, or over more slowly than the gate, or banked less: the network's
  for (const auto& [bank, rate] : {std::pair<double, double>{0.45, -6.0},
                                   {0.45, 4.9},
                                   {0.35, 6.0},
                                   {-0.45, 6.0},
                                   {-0.35, -6.0}}) {
    EXPECT_FALSE(reflex(bank, rate, p, c)) << bank << " rad, " << rate << " rad/s";
    EXPECT_EQ(c.right.downstroke_rate, 31.0);
    EXPECT_EQ(c.left.upstroke_rate, 10.0);
  }
  FlapControllerParams off = p;
  off.roll_reflex_bank = 0.0;
  EXPECT_FALSE(reflex(1.2, 50.0, off, c));
  // through the wing controller, per unit
  const AnnWingController ann(FlapUnitController(p, std::vector<double>(12, 0.0)));
  FlapSensing sensed({Quat::Identity(), Quat(Eigen::AngleAxisd(0.5, Vec3::UnitX()))});
  sensed.rates[1] = Vec3(8.0, 0.0, 0.0);
  const std::vector<StrokeCommand> cmds = ann.commands(sensed);
  EXPECT_EQ(cmds[0].downstroke_rate, cmds[1].downstroke_rate);  // unit 0 level: the network's
  EXPECT_EQ(cmds[3].downstroke_rate, 65.0);                     // unit 1: right wing low
  EXPECT_EQ(cmds[2].upstroke_rate, 65.0);
}

// The chain pitch reflex: while the chain's mean pitch is beyond pitch_reflex_angle, the units
// of its low end (|s_k| > pitch_reflex_ends) beat fast down / slow up, those of its high end
// slow down / fast up, the middle ones keep their command; within the angle, with the reflex
// off, or for a single unit, every command stays the network's.
TEST(PitchReflex, ActsOnTheChainsEndsOnlyBeyondItsAngleAndMirrors) {
  FlapControllerParams p;
  p.pitch_reflex_angle = 0.2;
  p.pitch_reflex_ends = 0.3;
  p.pitch_reflex_fast_rate = 65.0;
  p.pitch_reflex_slow_rate = 40.0;
  const WingPairCommand net{StrokeCommand{30, 10, 1.2}, StrokeCommand{31, 11, 1.2}};
  auto reflex = [&](int unit, double pitch_angle, const FlapControllerParams& params,
                    WingPairCommand& c, int units = 5) {
    c = net;
    return applyPitchReflex(params, unit, units, std::sin(pitch_angle), c);
  };
  WingPairCommand c;
  // The pair's mean downstroke rate becomes the reflex's; the network's right/left ratio (its
  // roll control, 31 / 30) is kept.
  auto downstrokes = [](const WingPairCommand& c, double mean) {
    EXPECT_DOUBLE_EQ(c.left.downstroke_rate, mean * 30.0 / 30.5);
    EXPECT_DOUBLE_EQ(c.right.downstroke_rate, mean * 31.0 / 30.5);
  };
  // nose up 0.25 rad, 5 units (s = 1, 0.5, 0, -0.5, -1): the nose is the high end
  for (int unit : {0, 1}) {
    ASSERT_TRUE(reflex(unit, 0.25, p, c)) << unit;
    downstrokes(c, 40.0);
    for (const StrokeCommand& w : {c.left, c.right}) {
      EXPECT_EQ(w.upstroke_rate, 65.0);
      EXPECT_EQ(w.amplitude, 1.2);  // only the rates change
    }
  }
  for (int unit : {3, 4}) {  // the tail: the low end
    ASSERT_TRUE(reflex(unit, 0.25, p, c)) << unit;
    downstrokes(c, 65.0);
    EXPECT_EQ(c.left.upstroke_rate, 40.0);
  }
  EXPECT_FALSE(reflex(2, 0.25, p, c));  // the middle (s = 0) keeps the network's
  EXPECT_EQ(c.right.downstroke_rate, 31.0);
  // the mirror image: nose down, the nose is the low end
  ASSERT_TRUE(reflex(0, -0.25, p, c));
  downstrokes(c, 65.0);
  EXPECT_EQ(c.right.upstroke_rate, 40.0);
  ASSERT_TRUE(reflex(4, -0.25, p, c));
  downstrokes(c, 40.0);
  // within the angle, either way; the ends threshold; off; a single unit
  for (double angle : {0.19, -0.19, 0.0}) {
    EXPECT_FALSE(reflex(0, angle, p, c)) << angle;
    EXPECT_EQ(c.right.downstroke_rate, 31.0);
    EXPECT_EQ(c.left.upstroke_rate, 10.0);
  }
  FlapControllerParams ends = p;
  ends.pitch_reflex_ends = 0.5;  // units 1 and 3 (|s| = 0.5) no longer take part
  EXPECT_FALSE(reflex(1, 0.25, ends, c));
  EXPECT_TRUE(reflex(0, 0.25, ends, c));
  FlapControllerParams off = p;
  off.pitch_reflex_angle = 0.0;
  EXPECT_FALSE(reflex(0, 1.0, off, c));
  EXPECT_FALSE(reflex(0, 1.0, p, c, 1));
  // through the wing controller: the mean pitch of the units decides, without a pitch term
  FlapControllerParams q = p;
  q.pitch_reflex_fast_rate = 64.0;
  q.pitch_reflex_slow_rate = 36.0;
  const AnnWingController ann(FlapUnitController(q, std::vector<double>(12, 0.0)));
  const Quat up(Eigen::AngleAxisd(-0.3, Vec3::UnitY()));  // nose up 0.3 rad (y left)
  const std::vector<StrokeCommand> cmds = ann.commands(FlapSensing({up, up, up}));
  ASSERT_EQ(cmds.size(), 6u);
  EXPECT_EQ(cmds[0].downstroke_rate, 36.0);  // nose unit: the high end
  EXPECT_EQ(cmds[0].upstroke_rate, 64.0);
  EXPECT_EQ(cmds[5].downstroke_rate, 64.0);  // tail unit: the low end
  EXPECT_EQ(cmds[5].upstroke_rate, 36.0);
  // the middle unit: the network's (sigmoid(0) of 20-60 rad/s)
  EXPECT_DOUBLE_EQ(cmds[2].downstroke_rate, 0.5 * (q.min_downstroke_rate + q.max_downstroke_rate));
  EXPECT_EQ(cmds[2].downstroke_rate, cmds[3].downstroke_rate);
}

TEST(FlapUnitController, BadParamsAreRefused) {
  FlapControllerParams p;
  p.max_downstroke_rate = p.min_downstroke_rate - 1.0;
  EXPECT_THROW(FlapUnitController(p, kWeights), std::invalid_argument);
  p = FlapControllerParams();
  p.pitch_gain = -1.0;
  EXPECT_NE(validateFlapControllerParams(p).find("pitch_gain"), std::string::npos);
  p = FlapControllerParams();
  p.pitch_limit = 1.0;
  EXPECT_NE(validateFlapControllerParams(p).find("pitch_limit"), std::string::npos);
  p = FlapControllerParams();
  p.pitch_max_downstroke_rate = p.max_downstroke_rate - 1.0;
  EXPECT_NE(validateFlapControllerParams(p).find("pitch_max_downstroke_rate"), std::string::npos);
  p = FlapControllerParams();
  p.amplitude = 0.0;
  EXPECT_FALSE(validateFlapControllerParams(p).empty());
  p = FlapControllerParams();
  p.stroke_offset = std::nan("");
  EXPECT_NE(validateFlapControllerParams(p).find("stroke_offset"), std::string::npos);
  p = FlapControllerParams();
  p.roll_reflex_bank = M_PI / 2;
  EXPECT_NE(validateFlapControllerParams(p).find("roll_reflex_bank"), std::string::npos);
  p = FlapControllerParams();
  p.roll_reflex_rate = std::nan("");
  EXPECT_NE(validateFlapControllerParams(p).find("roll_reflex_rate"), std::string::npos);
  p = FlapControllerParams();
  p.roll_reflex_slow_rate = 0.0;
  EXPECT_NE(validateFlapControllerParams(p).find("roll_reflex_slow_rate"), std::string::npos);
  p = FlapControllerParams();
  p.pitch_reflex_angle = -0.1;
  EXPECT_NE(validateFlapControllerParams(p).find("pitch_reflex_angle"), std::string::npos);
  p = FlapControllerParams();
  p.pitch_reflex_ends = 1.0;
  EXPECT_NE(validateFlapControllerParams(p).find("pitch_reflex_ends"), std::string::npos);
  p = FlapControllerParams();
  p.pitch_reflex_fast_rate = std::nan("");
  EXPECT_NE(validateFlapControllerParams(p).find("pitch_reflex_fast_rate"), std::string::npos);
  p = FlapControllerParams();
  p.attitude_filter_time = -0.02;
  EXPECT_NE(validateFlapControllerParams(p).find("attitude_filter_time"), std::string::npos);
  p = FlapControllerParams();
  p.velocity_gain = std::nan("");
  EXPECT_NE(validateFlapControllerParams(p).find("velocity_gain"), std::string::npos);
  p = FlapControllerParams();
  p.velocity_tilt_limit = 0.6;
  EXPECT_NE(validateFlapControllerParams(p).find("velocity_tilt_limit"), std::string::npos);
  EXPECT_THROW(FlapUnitController(FlapControllerParams(), {1.0, 2.0}), std::invalid_argument);
}

TEST(WingControllers, OneNetPerUnitInLayoutOrder) {
  const FlapUnitController c(FlapControllerParams(), {0, 5, 0, 0, 0, 0, 4, 0, 0, -4, 0, 0});
  const AnnWingController ann(c);
  const std::vector<Quat> bodies = {Quat::Identity(), Quat(Eigen::AngleAxisd(0.1, Vec3::UnitX()))};
  const std::vector<StrokeCommand> cmds = ann.commands(FlapSensing(bodies));
  ASSERT_EQ(cmds.size(), 4u);
  EXPECT_DOUBLE_EQ(cmds[0].downstroke_rate, cmds[1].downstroke_rate);  // unit 0 level
  EXPECT_GT(cmds[3].downstroke_rate, cmds[2].downstroke_rate);         // unit 1: right > left
  const OpenLoopWingController open(StrokeCommand{30, 10, 0.8});
  const std::vector<StrokeCommand> o = open.commands(FlapSensing(bodies));
  ASSERT_EQ(o.size(), 4u);
  EXPECT_EQ(o[3].downstroke_rate, 30.0);
}

TEST(FlapUnitLayout, FollowsTheGeneratorsNames) {
  const auto model = parseCreatureModel(makeCreatureUrdf(3, "afc"));
  const FlapUnitLayout a = flapUnitLayout(*model);
  const FlapUnitLayout b = flapUnitLayout(3);
  EXPECT_EQ(a.body_links, b.body_links);
  EXPECT_EQ(a.wing_joints, b.wing_joints);
  ASSERT_EQ(a.units(), 3);
  EXPECT_EQ(a.body_links[2], "unit2_body");
  EXPECT_EQ(a.wing_joints[1], "unit0_wing_right_joint");
  for (const auto& j : a.wing_joints) EXPECT_TRUE(model->joints[model->findJoint(j)].wing) << j;
  EXPECT_THROW(flapUnitLayout(0), std::invalid_argument);
  const auto plate = parseCreatureModel(
      "<robot name='p'><link name='plate'><inertial><mass value='1'/><inertia ixx='1' ixy='0' "
      "ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link></robot>");
  EXPECT_THROW(flapUnitLayout(*plate), InputError);
}

TEST(ControllerYaml, RoundTripsExactlyAndNamesBadInput) {
  ControllerSpec spec;
  spec.params.min_downstroke_rate = 12.5;
  spec.params.control_period = 0.01;
  spec.params.pitch_gain = 0.1 + 0.2;
  spec.params.pitch_limit = 0.25;
  spec.params.pitch_max_downstroke_rate = 70.0;
  spec.params.stroke_offset = 0.25;
  spec.params.roll_reflex_bank = 0.3;
  spec.params.roll_reflex_rate = 0.1 + 0.2;
  spec.params.roll_reflex_fast_rate = 70.0;
  spec.params.roll_reflex_slow_rate = 35.0;
  spec.params.pitch_reflex_angle = 0.1 + 0.2;
  spec.params.pitch_reflex_ends = 0.4;
  spec.params.pitch_reflex_fast_rate = 66.0;
  spec.params.pitch_reflex_slow_rate = 33.0;
  spec.params.attitude_filter_time = 0.1 + 0.05;
  spec.params.velocity_gain = 0.1 + 0.2;
  spec.params.velocity_tilt_limit = 0.04;
  spec.weights = kWeights;
  spec.weights[0] = 0.1 + 0.2;  // not exactly representable in short decimal
  const std::string text = controllerToYaml(spec, "line one\nline two", {{"seed", "7"}});
  EXPECT_EQ(text.rfind("# line one\n# line two\n", 0), 0u) << text;
  const ControllerSpec back = controllerFromYaml(text, "mem");
  EXPECT_EQ(back.weights, spec.weights);
  EXPECT_EQ(back.params.min_downstroke_rate, 12.5);
  EXPECT_EQ(back.params.control_period, 0.01);
  EXPECT_EQ(back.params.hidden, 2);
  EXPECT_EQ(back.params.pitch_gain, 0.1 + 0.2);
  EXPECT_EQ(back.params.pitch_limit, 0.25);
  EXPECT_EQ(back.params.pitch_max_downstroke_rate, 70.0);
  EXPECT_EQ(back.params.stroke_offset, 0.25);
  EXPECT_EQ(back.params.roll_reflex_bank, 0.3);
  EXPECT_EQ(back.params.roll_reflex_rate, 0.1 + 0.2);
  EXPECT_EQ(back.params.roll_reflex_fast_rate, 70.0);
  EXPECT_EQ(back.params.roll_reflex_slow_rate, 35.0);
  EXPECT_EQ(back.params.pitch_reflex_angle, 0.1 + 0.2);
  EXPECT_EQ(back.params.pitch_reflex_ends, 0.4);
  EXPECT_EQ(back.params.pitch_reflex_fast_rate, 66.0);
  EXPECT_EQ(back.params.pitch_reflex_slow_rate, 33.0);
  EXPECT_EQ(back.params.attitude_filter_time, 0.1 + 0.05);
  EXPECT_EQ(back.params.velocity_gain, 0.1 + 0.2);
  EXPECT_EQ(back.params.velocity_tilt_limit, 0.04);
  // without the reflexes their keys are not written
  const std::string plain = controllerToYaml(ControllerSpec{FlapControllerParams(), kWeights});
  EXPECT_EQ(plain.find("roll_reflex"), std::string::npos);
  EXPECT_EQ(plain.find("pitch_reflex"), std::string::npos);
  EXPECT_EQ(plain.find("attitude_filter"), std::string::npos);
  EXPECT_EQ(plain.find("velocity_"), std::string::npos);

  try {
    controllerFromYaml("flap_unit_controller: {hidden: 2, weights: [1, 2, 3]}", "short.yaml");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("short.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("weights"), std::string::npos) << e.what();
  }
  try {  // a bad pitch term is named
    controllerFromYaml("flap_unit_controller: {pitch_limit: 1.5, weights: [" +
                           std::string("0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]}"),
                       "pitch.yaml");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("pitch_limit"), std::string::npos) << e.what();
  }
  EXPECT_THROW(controllerFromYaml("other: 1"), std::runtime_error);
  EXPECT_THROW(controllerFromYaml("flap_unit_controller: {weights: [1, 2}"), std::runtime_error);
  EXPECT_THROW(loadControllerYaml("/nonexistent/weights.yaml"), std::runtime_error);
}

// The chain input's and the climb input's keys are written only when they are on, and a file
// with one reads back the same: a third input to both hidden neurons, last in the inputs.
TEST(ControllerYaml, TheChainAndClimbInputsAreWrittenOnlyWhenOnAndReadBack) {
  const std::string plain = controllerToYaml(ControllerSpec{FlapControllerParams(), kWeights});
  EXPECT_EQ(plain.find("chain_"), std::string::npos);
  EXPECT_EQ(plain.find("climb_"), std::string::npos);
  FlapControllerParams chain, climb;
  chain.chain_input = true;
  climb.climb_input = true;
  climb.climb_scale = 0.75;
  for (const auto& [params, line, input] :
       {std::tuple{chain, "chain_input: true", "chain_position.chain_pitch"},
        std::tuple{climb, "climb_scale: 0.75", "climb_rate"}}) {
    ControllerSpec spec;
    spec.params = params;
    spec.weights.assign(static_cast<size_t>(FlapUnitController::weightCount(params)), 0.5);
    ASSERT_EQ(spec.weights.size(), kWeights.size() + 2);
    const std::string yaml = controllerToYaml(spec);
    EXPECT_NE(yaml.find(line), std::string::npos) << yaml;
    const ControllerSpec back = controllerFromYaml(yaml, "w.yaml");
    EXPECT_EQ(back.params.chain_input, params.chain_input);
    EXPECT_EQ(back.params.climb_input, params.climb_input);
    EXPECT_DOUBLE_EQ(back.params.climb_scale, params.climb_scale);
    EXPECT_EQ(back.weights, spec.weights);
    EXPECT_EQ(flapInputNames(back.params).back(), input);
  }
}

std::string yamlError(const std::string& keys) {
  try {
    controllerFromYaml(
        "flap_unit_controller: {" + keys + "weights: [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]}",
        "w.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// Issue 27: a control period of 1e-12 s ran ann_controller at 1e12 Hz; `inputs` and
// `outputs` were never read, nor was a misspelt key noticed.
TEST(ControllerYaml, EveryKeyIsReadAndTheControlPeriodIsBounded) {
  EXPECT_EQ(yamlError(""), "");
  EXPECT_EQ(yamlError("control_period: 1e-12, "),
            "controller YAML w.yaml: control_period must be in [0.001, 10] s");
  EXPECT_EQ(yamlError("control_period: 1e9, "),
            "controller YAML w.yaml: control_period must be in [0.001, 10] s");
  EXPECT_EQ(yamlError("hidden: 1000000000, "),
            "controller YAML w.yaml: hidden must be in [1, 256]");
  EXPECT_EQ(yamlError("inputs: [world_up.body_left, world_up.body_forward], "),
            "controller YAML w.yaml: 'inputs' must be [world_up.body_forward, world_up.body_left]");
  EXPECT_EQ(yamlError("outputs: [left_downstroke_rate, right_downstroke_rate], "),
            "controller YAML w.yaml: 'outputs' must be [right_downstroke_rate, "
            "left_downstroke_rate]");
  EXPECT_EQ(yamlError("output_activation: tanh, "),
            "controller YAML w.yaml: 'output_activation' must be sigmoid");
  EXPECT_EQ(yamlError("control_perod: 0.01, "),
            "controller YAML w.yaml: unknown key 'control_perod'");
  // A key given twice (hidden: 4, hidden: 5 was read as 4).
  EXPECT_EQ(yamlError("hidden: 4, hidden: 5, "),
            "controller YAML w.yaml: key 'hidden' given twice");
  EXPECT_EQ(
      yamlError("inputs: [world_up.body_forward, world_up.body_left], outputs: "
                "[right_downstroke_rate, left_downstroke_rate], output_activation: sigmoid, "),
      "");
  // Every shipped weights file has only keys that are read.
  for (int pairs : {1, 4, 6, 12}) {
    EXPECT_NO_THROW(loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_" +
                                       std::to_string(pairs) + "_weights.yaml"));
  }
}

// What scripts/widen_weights.py added to a seed: an input or hidden neurons.
enum class Widened { kInput, kHidden };

// Over attitudes, rates, altitude errors, climbs and chain pitches the seed `to` commands both
// wings as its source `from` does, to the bit, whatever its new input reads.
void expectCommandsOfItsSource(const std::string& from, const std::string& to, Widened what) {
  SCOPED_TRACE(to);
  const std::string config = std::string(FLAPSIM_SOURCE_DIR) + "/config/";
  const ControllerSpec source = loadControllerYaml(config + from);
  const ControllerSpec seed = loadControllerYaml(config + to);
  const bool climb = what == Widened::kInput && !source.params.climb_input;
  const bool chain = what == Widened::kInput && !climb;
  if (what == Widened::kInput) {
    ASSERT_TRUE(climb ? seed.params.climb_input : seed.params.chain_input);
    ASSERT_EQ(seed.weights.size(),
              source.weights.size() + static_cast<size_t>(source.params.hidden));
  } else {
    ASSERT_GT(seed.params.hidden, source.params.hidden);
    ASSERT_EQ(seed.params.climb_input, source.params.climb_input);
    ASSERT_EQ(seed.params.chain_input, source.params.chain_input);
  }
  const FlapUnitController a(source.params, source.weights), b(seed.params, seed.weights);
  Rng rng(7);
  for (int i = 0; i < 200; ++i) {
    const Quat body(Eigen::AngleAxisd(rng.uniform(-1.0, 1.0), Vec3::UnitX()) *
                    Eigen::AngleAxisd(rng.uniform(-1.0, 1.0), Vec3::UnitY()));
    const Vec3 rate(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20));
    const double altitude = rng.uniform(-1.0, 1.0), climb_rate = rng.uniform(-1.0, 1.0);
    const double pitch = rng.uniform(-1.0, 1.0);
    const WingPairCommand x =
        climb ? a.command(body, rate, altitude) : a.command(body, rate, altitude, 0.0, climb_rate);
    const WingPairCommand y = b.command(body, rate, altitude, chain ? pitch : 0.0, climb_rate);
    for (const auto& [p, q] : {std::pair{x.left, y.left}, std::pair{x.right, y.right}}) {
      EXPECT_EQ(p.downstroke_rate, q.downstroke_rate);
      EXPECT_EQ(p.upstroke_rate, q.upstroke_rate);
    }
  }
}

// The seeds scripts/widen_weights.py writes with a new input: config/afc_1_climb_seed_weights.yaml
// is config/afc_1_real_air_weights.yaml with a climb input whose weights are 0, and
// config/afc_1_climb_chain_seed_weights.yaml is config/afc_1_climb_weights.yaml with a chain
// input whose weights are 0.
TEST(ControllerYaml, AWidenedSeedCommandsWhatItsSourceCommands) {
  expectCommandsOfItsSource("afc_1_real_air_weights.yaml", "afc_1_climb_seed_weights.yaml",
                            Widened::kInput);
  expectCommandsOfItsSource("afc_1_climb_weights.yaml", "afc_1_climb_chain_seed_weights.yaml",
                            Widened::kInput);
}

// The seed scripts/widen_weights.py --hidden 8 writes: config/afc_1_hidden8_seed_weights.yaml is
// config/afc_1_shed_floor_weights.yaml with four more hidden neurons, copies of its four whose
// output weights are 0.
TEST(ControllerYaml, ASeedWidenedByHiddenNeuronsCommandsWhatItsSourceCommands) {
  expectCommandsOfItsSource("afc_1_shed_floor_weights.yaml", "afc_1_hidden8_seed_weights.yaml",
                            Widened::kHidden);
}

}  // namespace
}  // namespace flapsim
