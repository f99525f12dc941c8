// The wing-command timeout as a policy of the world (World::setCommandTimeout): the wings held
// or released at the step the timeout falls due, however the steps are asked for; a new command
// and a reset starting it again, a reset giving back the command that lapsed; and several
// creatures commanded at once, all or nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::bitIdentical;
using test::loadUrdf;
using test::openSky;

const std::vector<StrokeCommand> kStroke = {StrokeCommand{35, 10, 0.7}, StrokeCommand{30, 12, 0.8}};

// A flap unit commanded at step 0, with a timeout of `seconds` (0.05 s: 50 steps of 1 ms).
void flapUnit(World& w, double seconds, CommandTimeout::Action action) {
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 2));
  w.setCommandTimeout(CommandTimeout{seconds, action});
  w.setWingCommands("u", {}, kStroke);
}

// What the simulator node did before the world had the policy: step to the timeout, then hold
// (or release) every wing joint.
void lapseByHand(World& w, CommandTimeout::Action action) {
  for (int j : w.model("u")->wing_joints) {
    const std::string& joint = w.model("u")->joints[j].name;
    if (action == CommandTimeout::Action::kHold) {
      w.holdJoint("u", joint);
    } else {
      w.clearJointCommand("u", joint);
    }
  }
}

TEST(CommandTimeout, HoldLapsesAtTheDueStepWithinOneLongStepCall) {
  World w(openSky()), by_hand(openSky());
  flapUnit(w, 0.05, CommandTimeout::Action::kHold);
  flapUnit(by_hand, 0.0, CommandTimeout::Action::kHold);
  w.step(200);
  by_hand.step(50);
  lapseByHand(by_hand, CommandTimeout::Action::kHold);
  by_hand.step(150);
  EXPECT_TRUE(bitIdentical(w.state("u"), by_hand.state("u")));
  const std::optional<CommandLapse> lapse = w.commandLapse("u");
  ASSERT_TRUE(lapse);
  EXPECT_EQ(lapse->commanded_step, 0u);
  EXPECT_EQ(lapse->step, 50u);
  // Held: the wing stays where it was at step 50 (within the hold servo's creep).
  EXPECT_EQ(w.wingCommand("u", "unit0_wing_right_joint").amplitude, 0.0);
}

TEST(CommandTimeout, ReleaseLeavesTheWingJointsPassiveAtTheDueStep) {
  World w(openSky()), by_hand(openSky());
  flapUnit(w, 0.05, CommandTimeout::Action::kRelease);
  flapUnit(by_hand, 0.0, CommandTimeout::Action::kRelease);
  w.step(120);
  by_hand.step(50);
  lapseByHand(by_hand, CommandTimeout::Action::kRelease);
  by_hand.step(70);
  EXPECT_TRUE(bitIdentical(w.state("u"), by_hand.state("u")));
  // Not trivially equal: without the lapse the wings would still stroke.
  World kept(openSky());
  flapUnit(kept, 0.0, CommandTimeout::Action::kRelease);
  kept.step(120);
  EXPECT_FALSE(bitIdentical(w.state("u"), kept.state("u")));
}

TEST(CommandTimeout, SingleStepsAndOneCallGiveTheSameTrajectory) {
  World one(openSky()), single(openSky());
  flapUnit(one, 0.033, CommandTimeout::Action::kHold);
  flapUnit(single, 0.033, CommandTimeout::Action::kHold);
  one.step(90);
  for (int k = 0; k < 90; ++k) single.step(1);
  EXPECT_TRUE(bitIdentical(one.state("u"), single.state("u")));
  ASSERT_TRUE(single.commandLapse("u"));
  EXPECT_EQ(single.commandLapse("u")->step, 33u);
}

TEST(CommandTimeout, ANewCommandStartsTheTimeoutAgain) {
  World w(openSky());
  flapUnit(w, 0.05, CommandTimeout::Action::kHold);
  w.step(30);
  w.setWingCommands("u", {}, kStroke);
  w.step(49);  // step 79: due at 80
  EXPECT_FALSE(w.commandLapse("u"));
  EXPECT_TRUE(w.takeCommandLapses().empty());
  w.step(1);
  ASSERT_TRUE(w.commandLapse("u"));
  EXPECT_EQ(w.commandLapse("u")->commanded_step, 30u);
  EXPECT_EQ(w.commandLapse("u")->step, 80u);
}

TEST(CommandTimeout, EachLapseIsTakenOnceAndANewCommandEndsIt) {
  World w(openSky());
  flapUnit(w, 0.01, CommandTimeout::Action::kHold);
  w.step(100);
  const std::vector<CommandLapse> lapses = w.takeCommandLapses();
  ASSERT_EQ(lapses.size(), 1u);
  EXPECT_EQ(lapses[0].creature, "u");
  EXPECT_EQ(lapses[0].step, 10u);
  EXPECT_TRUE(w.takeCommandLapses().empty());
  w.setWingCommands("u", {}, kStroke);
  EXPECT_FALSE(w.commandLapse("u"));
  EXPECT_EQ(w.wingCommand("u", "unit0_wing_right_joint").downstroke_rate, 30.0);
}

TEST(CommandTimeout, ResetGivesTheLapsedCommandBackAndStartsTheTimeoutAtZero) {
  World w(openSky()), fresh(openSky());
  flapUnit(w, 0.05, CommandTimeout::Action::kHold);
  flapUnit(fresh, 0.05, CommandTimeout::Action::kHold);
  w.step(200);
  ASSERT_TRUE(w.commandLapse("u"));
  w.reset();
  EXPECT_FALSE(w.commandLapse("u"));
  EXPECT_EQ(w.wingCommand("u", "unit0_wing_right_joint").downstroke_rate, 30.0);
  w.step(40);
  fresh.step(40);
  EXPECT_TRUE(bitIdentical(w.state("u"), fresh.state("u")));
  w.step(80);
  fresh.step(80);
  EXPECT_TRUE(bitIdentical(w.state("u"), fresh.state("u")));
  ASSERT_TRUE(w.commandLapse("u"));
  EXPECT_EQ(w.commandLapse("u")->step, 50u);
}

TEST(CommandTimeout, NoneByDefaultNoneUncommandedAndAnOverdueOneAtTheNextStep) {
  World w(openSky());
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 2));
  w.spawn("v", loadUrdf("flap_unit.urdf"), at(3, 0, 2));
  w.setWingCommands("u", {}, kStroke);
  w.step(100);
  EXPECT_FALSE(w.commandLapse("u"));
  w.setCommandTimeout(CommandTimeout{0.01, CommandTimeout::Action::kHold});
  w.step(100);
  EXPECT_FALSE(w.commandLapse("v"));
  ASSERT_TRUE(w.commandLapse("u"));
  EXPECT_EQ(w.commandLapse("u")->step, 101u);  // commanded at 0: overdue, it lapses at once
}

TEST(CommandTimeout, ABadTimeoutIsRefusedNamingIt) {
  World w(openSky());
  for (double s : {-1.0, std::nan(""), 2e6}) {
    try {
      w.setCommandTimeout(CommandTimeout{s, CommandTimeout::Action::kHold});
      ADD_FAILURE() << s << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("command timeout"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(w.commandLapse("nobody"), InputError);
}

TEST(WingCommands, SeveralCreaturesAllOrNothing) {
  World w(openSky());
  w.spawn("u", loadUrdf("flap_unit.urdf"), at(0, 0, 2));
  w.spawn("v", loadUrdf("flap_unit.urdf"), at(3, 0, 2));
  const std::vector<StrokeCommand> bad = {StrokeCommand{35, 10, 0.7}};  // one of two wings
  auto refused = [&](const std::vector<CreatureWingCommand>& commands, const std::string& what) {
    try {
      w.setWingCommands(commands);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    EXPECT_EQ(w.wingCommand("u", "unit0_wing_right_joint").downstroke_rate, 0.0);
  };
  refused({{"u", {}, kStroke}, {"v", {}, bad}}, "creature 'v': ");
  refused({{"u", {}, kStroke}, {"w", {}, kStroke}}, "unknown creature 'w'");
  refused({{"u", {}, kStroke}, {"u", {}, kStroke}}, "creature 'u' is named twice");
  w.setWingCommands({{"u", {}, kStroke}, {"v", {"unit0_wing_left_joint"}, bad}});
  EXPECT_EQ(w.wingCommand("u", "unit0_wing_right_joint").downstroke_rate, 30.0);
  EXPECT_EQ(w.wingCommand("v", "unit0_wing_left_joint").downstroke_rate, 35.0);
  EXPECT_EQ(w.wingCommand("v", "unit0_wing_right_joint").downstroke_rate, 0.0);
}

}  // namespace
}  // namespace flapsim
