// stroke_controller publishes the stroke of its parameters on <creature>/wing_command (two
// wings per pair), re-reads them while running (rosparam set changes the stroke) and keeps
// the last good stroke when a re-read value is bad.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include "flapsim/WingCommand.h"
#include "wait_for.h"

namespace {

using flapsim_test::waitFor;

TEST(StrokeController, PublishesItsParametersAndRereadsThem) {
  ros::NodeHandle nh;
  flapsim::WingCommand last;
  bool got = false;
  ros::Subscriber sub = nh.subscribe<flapsim::WingCommand>(
      "/flap_unit/wing_command", 10, [&](const flapsim::WingCommand::ConstPtr& m) {
        last = *m;
        got = true;
      });
  ASSERT_TRUE(waitFor([&] { return got; }, 30.0)) << "no /flap_unit/wing_command";
  ASSERT_EQ(last.downstroke_rate.size(), 2u);
  EXPECT_EQ(last.downstroke_rate[0], 35.0);
  EXPECT_EQ(last.downstroke_rate[1], 35.0);
  EXPECT_EQ(last.upstroke_rate[0], 10.0);
  EXPECT_EQ(last.amplitude[1], 0.8);
  // rosparam set: the controller publishes the new rate (it re-reads every 0.2 s here).
  nh.setParam("/flap_unit/stroke_controller/downstroke_rate", 22.5);
  EXPECT_TRUE(waitFor(
      [&] {
        return last.downstroke_rate.size() == 2 && last.downstroke_rate[0] == 22.5 &&
               last.downstroke_rate[1] == 22.5;
      },
      10.0))
      << "still " << (last.downstroke_rate.empty() ? -1.0 : last.downstroke_rate[0]);
  // A bad value is refused and the last good stroke kept.
  nh.setParam("/flap_unit/stroke_controller/downstroke_rate", -3.0);
  int fresh = 0;  // messages after the bad value: wait for several re-reads' worth
  ros::Subscriber count = nh.subscribe<flapsim::WingCommand>(
      "/flap_unit/wing_command", 10, [&](const flapsim::WingCommand::ConstPtr&) { ++fresh; });
  ASSERT_TRUE(waitFor([&] { return fresh >= 20; }, 30.0));
  EXPECT_EQ(last.downstroke_rate[0], 22.5);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_stroke_controller");
  return RUN_ALL_TESTS();
}
