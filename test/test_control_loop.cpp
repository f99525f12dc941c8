// ControlLoop: the control period as a whole number of simulator steps, shared by evolution's
// episodes and the lockstep controller node.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "flapsim/control_loop.h"
#include "flapsim/types.h"

namespace flapsim {
namespace {

TEST(ControlLoop, APeriodOfWholeStepsGivesItsStepCount) {
  EXPECT_EQ(ControlLoop(0.02, 0.001).stepsPerPeriod(), 20);
  EXPECT_EQ(ControlLoop(0.02, 0.0005).stepsPerPeriod(), 40);
  EXPECT_EQ(ControlLoop(0.02, 0.00025).stepsPerPeriod(), 80);
  EXPECT_EQ(ControlLoop(0.001, 0.001).stepsPerPeriod(), 1);
  EXPECT_EQ(ControlLoop(1.0 / 50.0, 1.0 / 3000.0).stepsPerPeriod(), 60);
}

TEST(ControlLoop, APeriodOfPartStepsIsRefusedNamingBoth) {
  for (const auto& [period, step] : {std::pair{0.0205, 0.001},
                                     {0.0005, 0.001},
                                     {0.02, 0.003},
                                     {0.0, 0.001},
                                     {-0.02, 0.001},
                                     {NAN, 0.001},
                                     {0.02, 0.0},
                                     {0.02, INFINITY}}) {
    try {
      ControlLoop loop(period, step);
      ADD_FAILURE() << period << " / " << step << " accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("control period"), std::string::npos) << what;
      EXPECT_NE(what.find("simulator steps of"), std::string::npos) << what;
    }
  }
}

TEST(ControlLoop, PeriodsInADurationAreRoundedAndBounded) {
  const ControlLoop loop(0.02, 0.001);
  EXPECT_EQ(loop.periodsIn(60.0), 3000);
  EXPECT_EQ(loop.periodsIn(0.0), 0);
  EXPECT_EQ(loop.periodsIn(0.031), 2);  // 1.55 periods: the nearest whole number
  // 1e9 s is 5e10 periods: a count an int would wrap.
  EXPECT_EQ(loop.periodsIn(1e9), 50000000000);
  for (double bad : {-1.0, double{NAN}, double{INFINITY}, 1e30}) {
    EXPECT_THROW(loop.periodsIn(bad), InputError) << bad;
  }
}

}  // namespace
}  // namespace flapsim
