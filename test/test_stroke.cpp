// The stroke state machine: down at w1 to -theta0, up at w2 to +theta0, repeat.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "flapsim/stroke.h"

namespace flapsim {
namespace {

TEST(Stroke, SwingsBetweenMinusAndPlusAmplitude) {
  StrokeGenerator g;
  g.setCommand(StrokeCommand{30.0, 10.0, 0.5});
  EXPECT_EQ(g.target(0.0), -30.0);  // starts with a downstroke
  EXPECT_EQ(g.target(-0.49), -30.0);
  EXPECT_EQ(g.target(-0.5), 10.0);  // reached -theta0: turn up
  EXPECT_EQ(g.target(0.2), 10.0);
  EXPECT_EQ(g.target(0.5), -30.0);  // reached +theta0: turn down
  EXPECT_EQ(g.phase(), StrokeGenerator::Phase::kDown);
  g.reset();
  EXPECT_EQ(g.target(-0.2), -30.0);
}

// Integrating the target exactly gives the stroke period 2 theta0 (1/w1 + 1/w2).
TEST(Stroke, PeriodFollowsRates) {
  StrokeGenerator g;
  const double w1 = 40.0, w2 = 10.0, a = 0.8, dt = 1e-5;
  g.setCommand(StrokeCommand{w1, w2, a});
  double q = a;  // start at the top
  g.target(q);
  int turns = 0;
  double t = 0.0, first_turn = -1.0;
  StrokeGenerator::Phase last = g.phase();
  while (turns < 3) {
    q += g.target(q) * dt;
    t += dt;
    if (g.phase() != last) {
      last = g.phase();
      if (++turns == 1) first_turn = t;
    }
  }
  // Each turn is seen at most two steps after the crossing.
  EXPECT_NEAR(first_turn, 2 * a / w1, 3 * dt);
  EXPECT_NEAR(t, 2 * a / w1 + 2 * a / w2 + 2 * a / w1, 9 * dt);
}

// With the step given, the targets integrate to the ideal triangle wave at any step size:
// every sample lies on the wave (turns on +-theta0, period 2 theta0 (1/w1 + 1/w2)) to
// rounding, also when a turn falls inside a step.
TEST(Stroke, TurnsExactlyWithinAStep) {
  const double w1 = 40.0, w2 = 10.0, a = 0.8;
  for (double dt : {0.002, 0.001, 0.0007, 0.00025}) {
    SCOPED_TRACE(dt);
    StrokeGenerator g;
    g.setCommand(StrokeCommand{w1, w2, a});
    double q = 0.0;
    const double period = 2 * a / w1 + 2 * a / w2;
    const int steps = static_cast<int>(std::lround(3.0 * period / dt));
    // The ideal wave from q = 0: down to -a by a / w1, up to +a, and so on.
    auto ideal = [&](double t) {
      const double s = std::fmod(t + a / w1, period);  // time since the last top
      return s < 2 * a / w1 ? a - w1 * s : -a + w2 * (s - 2 * a / w1);
    };
    double worst = 0.0;
    for (int i = 1; i <= steps; ++i) {
      q += g.target(q, dt) * dt;
      worst = std::max(worst, std::abs(q - ideal(i * dt)));
    }
    EXPECT_LT(worst, 1e-12);
  }
}

// The time to the next turning point at the phase's rate: from 0 down at 40 rad/s to -0.8
// takes 20 ms; past the point it is 0 (the turn is due); up at 10 rad/s from -0.8 to +0.8
// takes 160 ms; a stroke that does not move never turns.
TEST(Stroke, TimeToTurnAtThePhasesRate) {
  StrokeGenerator g;
  g.setCommand(StrokeCommand{40, 10, 0.8});
  EXPECT_DOUBLE_EQ(g.timeToTurn(0.0), 0.02);
  EXPECT_EQ(g.timeToTurn(-0.85), 0.0);
  g.target(-0.8);  // turns: now the upstroke
  ASSERT_EQ(g.phase(), StrokeGenerator::Phase::kUp);
  EXPECT_DOUBLE_EQ(g.timeToTurn(-0.8), 0.16);
  StrokeGenerator still;
  still.setCommand(StrokeCommand{0, 0, 0.8});
  EXPECT_TRUE(std::isinf(still.timeToTurn(0.0)));
}

TEST(Stroke, ValidationNamesTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validateStroke(StrokeCommand{1, 1, 0.5}), "");
  EXPECT_NE(validateStroke(StrokeCommand{nan, 1, 0.5}).find("downstroke"), std::string::npos);
  EXPECT_NE(validateStroke(StrokeCommand{1, -1, 0.5}).find("upstroke"), std::string::npos);
  EXPECT_NE(validateStroke(StrokeCommand{1, 1, INFINITY}).find("amplitude"), std::string::npos);
}

}  // namespace
}  // namespace flapsim
