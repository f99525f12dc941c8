// The attitude-first mixer between a flap unit's network and its wings (flapsim/output_mixer.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "flapsim/ann.h"
#include "flapsim/controller_file.h"
#include "flapsim/ga.h"
#include "flapsim/output_mixer.h"

namespace flapsim {
namespace {

// Out of the range the difference is kept and the mean moves: (70, 50) in [20, 60] has the
// half-difference 10 and the mean 60, which moves to 50 (so 60 and 40, not 60 and 50, which
// clipping each gives); (5, 15) keeps -5 and moves its mean 10 to 25; a difference wider than the
// range is cut to it.
TEST(OutputMixer, KeepsTheDifferenceAndMovesTheMeanIntoTheRange) {
  const WingRates high = mixAttitudeFirst({70.0, 50.0}, 20.0, 60.0);
  EXPECT_EQ(high.right, 60.0);
  EXPECT_EQ(high.left, 40.0);
  const WingRates low = mixAttitudeFirst({5.0, 15.0}, 20.0, 60.0);
  EXPECT_EQ(low.right, 20.0);
  EXPECT_EQ(low.left, 30.0);
  const WingRates wide = mixAttitudeFirst({100.0, 0.0}, 20.0, 60.0);
  EXPECT_EQ(wide.right, 60.0);
  EXPECT_EQ(wide.left, 20.0);
  const WingRates mirrored = mixAttitudeFirst({50.0, 70.0}, 20.0, 60.0);
  EXPECT_EQ(mirrored.right, high.left);
  EXPECT_EQ(mirrored.left, high.right);
}

// A pair inside the range is not moved (to rounding: (c + d) is not always the bit it came from).
TEST(OutputMixer, APairInsideTheRangeComesOutAsItWentIn) {
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const WingRates in{rng.uniform(20.0, 60.0), rng.uniform(20.0, 60.0)};
    const WingRates out = mixAttitudeFirst(in, 20.0, 60.0);
    EXPECT_NEAR(out.right, in.right, 1e-13);
    EXPECT_NEAR(out.left, in.left, 1e-13);
  }
}

// Headroom 0 is the paper's map, to the bit; headroom 0.25 maps (1, 0.75) onto [10, 70]: 70 and
// 55, mixed into [20, 60] as 60 and 45 (the paper's map: 60 and 50).
TEST(OutputMixer, HeadroomWidensTheMapThenMixesAttitudeFirst) {
  const WingRates paper = outputRates({0.3, 0.9}, 20.0, 60.0, 0.0);
  EXPECT_EQ(paper.right, 20.0 + 40.0 * 0.3);
  EXPECT_EQ(paper.left, 20.0 + 40.0 * 0.9);
  const WingRates mixed = outputRates({1.0, 0.75}, 20.0, 60.0, 0.25);
  EXPECT_DOUBLE_EQ(mixed.right, 60.0);
  EXPECT_DOUBLE_EQ(mixed.left, 45.0);
  const WingRates middle = outputRates({0.5, 0.5}, 20.0, 60.0, 0.25);
  EXPECT_DOUBLE_EQ(middle.right, 40.0);  // the trim is the range's middle at any headroom
  EXPECT_DOUBLE_EQ(middle.left, 40.0);
}

// Through the controller: a mirror net with both outputs pushed past their ranges on a rolled
// unit keeps both differences that roll it back, and its mean gives way; a level unit strokes
// both wings alike; the mirrored attitude swaps the wings; every rate stays in its range.
TEST(OutputMixer, AMirrorNetKeepsItsRollDifferenceAtTheEndOfItsRange) {
  FlapControllerParams p;
  p.network = FlapNetwork::kMirror;
  p.hidden = 1;
  p.rate_inputs = false;
  p.max_upstroke_rate = 65.0;
  // h = tanh(10 up.left); downstroke = sigmoid(4 + 3 h), upstroke = sigmoid(4 - 3 h): near the
  // top of both ranges, the low (right, up.left > 0) wing's downstroke higher, its upstroke lower.
  const std::vector<double> w = {0, 10, 0, 3, 4, -3, 4};
  const Quat rolled(Eigen::AngleAxisd(0.3, Vec3::UnitX()));
  p.mixer_headroom = 0.0;
  const WingPairCommand paper = FlapUnitController(p, w).command(rolled);
  p.mixer_headroom = 0.5;
  const FlapUnitController mixed(p, w);
  const WingPairCommand c = mixed.command(rolled);
  const WingPairCommand m = mixed.command(rolled.conjugate());
  const WingPairCommand level = mixed.command(Quat::Identity());
  // The wanted rates (wide maps [0, 80] and [-17.5, 92.5]) leave the ranges; their differences
  // are 80 (s(7) - s(1)) and 110 (s(7) - s(1)), kept up to the ranges' spans, 40 and 55.
  const double s7 = 1.0 / (1.0 + std::exp(-4.0 - 3.0 * std::tanh(10 * std::sin(0.3))));
  const double s1 = 1.0 / (1.0 + std::exp(-4.0 + 3.0 * std::tanh(10 * std::sin(0.3))));
  EXPECT_NEAR(c.right.downstroke_rate - c.left.downstroke_rate, std::min(40.0, 80.0 * (s7 - s1)),
              1e-12);
  EXPECT_NEAR(c.left.upstroke_rate - c.right.upstroke_rate, std::min(55.0, 110.0 * (s7 - s1)),
              1e-12);
  // The paper's map squeezes the same outputs' difference into the range: (1 + 2h) = 2 x less.
  EXPECT_NEAR(c.right.downstroke_rate - c.left.downstroke_rate,
              2.0 * (paper.right.downstroke_rate - paper.left.downstroke_rate), 1e-12);
  EXPECT_EQ(level.right.downstroke_rate, level.left.downstroke_rate);
  EXPECT_EQ(level.right.upstroke_rate, level.left.upstroke_rate);
  EXPECT_EQ(m.right.downstroke_rate, c.left.downstroke_rate);
  EXPECT_EQ(m.left.upstroke_rate, c.right.upstroke_rate);
  for (const StrokeCommand& s : {c.left, c.right, m.left, m.right, level.left, level.right}) {
    EXPECT_GE(s.downstroke_rate, 20.0);
    EXPECT_LE(s.downstroke_rate, 60.0);
    EXPECT_GE(s.upstroke_rate, 10.0);
    EXPECT_LE(s.upstroke_rate, 65.0);
  }
}

// The headroom is refused outside [0, 1], by the params' check and by name in a file, which
// keeps it when it is on and leaves it out when it is off.
TEST(OutputMixer, TheHeadroomIsBoundedAndTheFileKeepsIt) {
  FlapControllerParams p;
  for (double bad : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    p.mixer_headroom = bad;
    EXPECT_EQ(validateFlapControllerParams(p),
              "mixer_headroom must be in [0, 1] (of the rate range's span)");
  }
  p.mixer_headroom = 0.1;
  const std::vector<double> w(FlapUnitController::weightCount(p), 0.5);
  const std::string text = controllerToYaml(ControllerSpec{p, w}, "", {});
  EXPECT_NE(text.find("mixer_headroom: 0.1"), std::string::npos);
  EXPECT_EQ(controllerFromYaml(text, "m.yaml").params.mixer_headroom, 0.1);
  p.mixer_headroom = 0.0;
  EXPECT_EQ(controllerToYaml(ControllerSpec{p, w}, "", {}).find("mixer_headroom"),
            std::string::npos);
  try {
    controllerFromYaml(
        "flap_unit_controller: {mixer_headroom: 2, weights: [0, 0, 0, 0, 0, 0, "
        "0, 0, 0, 0, 0, 0]}",
        "m.yaml");
    ADD_FAILURE() << "mixer_headroom 2 was read";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "controller YAML m.yaml: mixer_headroom must be in [0, 1] (of the rate range's span)");
  }
}

// config/afc_1_mixer_seed_weights.yaml is what scripts/mixer_seed.py says it writes: the shed
// floor controller's weights, its output neurons' times 1/(1 + 2 x 0.1), headroom 0.1.
TEST(OutputMixer, TheMixerSeedIsItsSourceWithItsOutputLayerScaled) {
  const std::string config = std::string(FLAPSIM_SOURCE_DIR) + "/config/";
  const ControllerSpec source = loadControllerYaml(config + "afc_1_shed_floor_weights.yaml");
  const ControllerSpec seed = loadControllerYaml(config + "afc_1_mixer_seed_weights.yaml");
  EXPECT_EQ(source.params.mixer_headroom, 0.0);
  ASSERT_EQ(seed.params.mixer_headroom, 0.1);
  ASSERT_EQ(seed.weights.size(), source.weights.size());
  const size_t first = seed.weights.size() - 2 * (seed.params.hidden + 1);
  for (size_t i = 0; i < seed.weights.size(); ++i) {
    const double k = i < first ? 1.0 : 1.0 / (1.0 + 2.0 * 0.1);
    EXPECT_EQ(seed.weights[i], source.weights[i] * k) << "weight " << i;
  }
  FlapControllerParams p = seed.params;  // and every other setting is the source's
  p.mixer_headroom = 0.0;
  EXPECT_EQ(controllerToYaml(ControllerSpec{p, source.weights}, "", {}),
            controllerToYaml(ControllerSpec{source.params, source.weights}, "", {}));
}

}  // namespace
}  // namespace flapsim
