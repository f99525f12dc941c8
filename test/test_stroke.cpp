// The stroke state machine: down at w1 to -theta0, up at w2 to +theta0, repeat.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "doc_figure.h"
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
  double worst_of_all = 0.0;
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
    worst_of_all = std::max(worst_of_all, worst);
  }
  test::printFigure("largest_error", worst_of_all);
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
  StrokeCommand c{1, 1, 0.5};
  c.downstroke_feather = 2.0;
  EXPECT_NE(validateStroke(c).find("downstroke feather"), std::string::npos);
  c.downstroke_feather = 0.0;
  c.offset = nan;
  EXPECT_NE(validateStroke(c).find("offset"), std::string::npos);
}

TEST(Stroke, ShapeNames) {
  EXPECT_EQ(strokeShapeFromString("sine"), StrokeShape::kSine);
  EXPECT_EQ(strokeShapeFromString("triangle"), StrokeShape::kTriangle);
  EXPECT_EQ(toString(StrokeShape::kSine), "sine");
  try {
    strokeShapeFromString("square");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'square'"), std::string::npos) << e.what();
  }
}

// The offset moves the triangle's turning points to offset -+ amplitude.
TEST(Stroke, OffsetMovesTheTurningPoints) {
  StrokeGenerator g;
  StrokeCommand c{30.0, 10.0, 0.5};
  c.offset = 0.2;
  g.setCommand(c);
  EXPECT_EQ(g.target(0.0), -30.0);
  EXPECT_EQ(g.target(-0.29), -30.0);
  EXPECT_EQ(g.target(-0.3), 10.0);  // offset - amplitude: turn up
  EXPECT_EQ(g.target(0.69), 10.0);
  EXPECT_EQ(g.target(0.71), -30.0);  // past offset + amplitude: turn down
  EXPECT_DOUBLE_EQ(g.timeToTurn(0.4), 0.7 / 30.0);
}

// A sine stroke, its velocity targets integrated as a servo that reaches them (q += v dt),
// lies on half cosines: from the start angle 0 down to -a in 2 a / w1, then up to +a in
// 2 a / w2 (a split cycle), and so on, to rounding, at any step.
TEST(Stroke, SineFollowsHalfCosinesBetweenTheTurningPoints) {
  const double w1 = 40.0, w2 = 20.0, a = 0.8, t1 = 2 * a / w1, t2 = 2 * a / w2;
  auto ideal = [&](double t) {
    if (t <= t1) return -a * (0.5 - 0.5 * std::cos(M_PI * t / t1));
    const double s = std::fmod(t - t1, t1 + t2);  // since the last bottom
    if (s <= t2) return -a + 2 * a * (0.5 - 0.5 * std::cos(M_PI * s / t2));
    return a - 2 * a * (0.5 - 0.5 * std::cos(M_PI * (s - t2) / t1));
  };
  for (double dt : {0.002, 0.001, 0.0007}) {
    SCOPED_TRACE(dt);
    StrokeGenerator g;
    StrokeCommand c{w1, w2, a};
    c.shape = StrokeShape::kSine;
    g.setCommand(c);
    double q = 0.0, worst = 0.0;
    const int steps = static_cast<int>(std::lround(3 * (t1 + t2) / dt));
    for (int i = 1; i <= steps; ++i) {
      q += g.target(q, dt) * dt;
      worst = std::max(worst, std::abs(q - ideal(i * dt)));
    }
    EXPECT_LT(worst, 1e-12);
  }
  // Mid-way up, the velocity peaks at pi / 2 times the rate.
  StrokeGenerator g;
  StrokeCommand c{w1, w2, a};
  c.shape = StrokeShape::kSine;
  g.setCommand(c);
  g.target(0.0, t1 + t2 / 2);
  EXPECT_NEAR(g.target(0.0), M_PI / 2 * w2, 1e-9);
  EXPECT_NEAR(g.timeToTurn(0.0), t2 / 2, 1e-12);
}

// A new amplitude or offset takes effect at the next turn, without a jump: the half-stroke
// under way still ends where it was going, the next one goes to the new turning point.
TEST(Stroke, SineTakesANewAmplitudeAndOffsetAtTheNextTurn) {
  StrokeGenerator g;
  StrokeCommand c{40.0, 40.0, 0.8};
  c.shape = StrokeShape::kSine;
  g.setCommand(c);
  const double dt = 0.001;
  double q = 0.0, biggest_move = 0.0, lowest = 0.0, highest = 0.0;
  for (int i = 0; i < 400; ++i) {
    if (i == 30) {  // mid-way down to -0.8
      c.amplitude = 0.5;
      c.offset = 0.1;
      c.downstroke_rate = c.upstroke_rate = 25.0;  // the same 40 ms half-strokes
      g.setCommand(c);
    }
    const double v = g.target(q, dt);
    biggest_move = std::max(biggest_move, std::abs(v * dt));
    q += v * dt;
    lowest = std::min(lowest, q);
    if (i > 100) highest = std::max(highest, q);
  }
  EXPECT_NEAR(lowest, -0.8, 1e-12);  // the half-stroke under way ended at -0.8
  EXPECT_NEAR(highest, 0.6, 1e-12);  // then offset + amplitude
  // The fastest half-stroke, -0.8 to 0.6 in 40 ms, peaks at pi / 2 1.4 / 0.04 = 55 rad/s:
  // 0.055 rad a step. Jumping to the new stroke at once would move 0.3 rad.
  EXPECT_LT(biggest_move, 0.056);
}

// The feather angle of a sine stroke: the half-stroke's own mid-stroke, half-way between the
// two at the turn, along a quarter sine within kSineFlipFraction of a half-stroke of it.
TEST(Stroke, SineFeatherTurnsSmoothlyAcrossTheTurn) {
  StrokeGenerator g;
  StrokeCommand c{10.0, 10.0, 0.5};  // 0.1 s half-strokes
  c.shape = StrokeShape::kSine;
  c.downstroke_feather = 0.6;
  c.feather = -0.6;
  g.setCommand(c);
  g.target(0.5, 0.05);  // starting at the top: half-way down
  EXPECT_DOUBLE_EQ(g.featherTarget(), 0.6);
  g.target(0.0, 0.05 - 0.25 * 0.1 * 0.5);  // half of the flip window before the turn
  EXPECT_NEAR(g.featherTarget(), 0.6 * std::sin(0.25 * M_PI), 1e-12);
  g.target(0.0, 0.25 * 0.1 * 0.5);  // at the turn
  EXPECT_NEAR(g.featherTarget(), 0.0, 1e-9);
  g.target(0.0, 0.03);  // the flip done
  EXPECT_DOUBLE_EQ(g.featherTarget(), -0.6);
  EXPECT_EQ(g.phase(), StrokeGenerator::Phase::kUp);
  // A triangle stroke pitches per half-stroke.
  StrokeGenerator t;
  c.shape = StrokeShape::kTriangle;
  t.setCommand(c);
  t.target(0.0);
  EXPECT_EQ(t.featherTarget(), 0.6);
  t.target(-0.5);
  EXPECT_EQ(t.featherTarget(), -0.6);
}

}  // namespace
}  // namespace flapsim
