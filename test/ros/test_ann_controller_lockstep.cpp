// ann_controller in lockstep with a paused flapsim_node (see ann_controller_lockstep.test and
// ann_controller_lockstep_12.test): the root height sampled from odom every control period,
// averaged over the flight, is the in-process evaluation's of the same weights from the same
// start, to the last bit (holding `altitude` if given; the controller reads /afc/imu, through
// the weights file's attitude filter if it has one, as the episode does).
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <cmath>
#include <functional>
#include <map>

#include "flapsim/evolve.h"
#include "service_call.h"
#include "wait_for.h"

namespace {

using flapsim_test::waitFor;

TEST(AnnControllerLockstep, MatchesTheInProcessEvaluation) {
  ros::NodeHandle nh, pnh("~");
  std::string urdf, weights;
  double roll = 0, pitch = 0, start_height = 1, duration = 1, altitude = 0;
  ASSERT_TRUE(pnh.getParam("urdf", urdf));
  ASSERT_TRUE(pnh.getParam("weights", weights));
  pnh.getParam("roll", roll);
  pnh.getParam("pitch", pitch);
  pnh.getParam("start_height", start_height);
  pnh.getParam("duration", duration);
  const bool hold = pnh.getParam("altitude", altitude);

  const flapsim::ControllerSpec spec = flapsim::loadControllerYaml(weights);
  const double period = spec.params.control_period;
  const long samples = std::lround(duration / period);

  std::map<long, double> height;  // by control period index k (t = k P)
  ros::Subscriber sub = nh.subscribe<nav_msgs::Odometry>(
      "/afc/odom", 1000, [&](const nav_msgs::Odometry::ConstPtr& m) {
        const double k = m->header.stamp.toSec() / period;
        if (std::abs(k - std::round(k)) < 1e-6) height[std::lround(k)] = m->pose.pose.position.z;
      });
  ASSERT_TRUE(waitFor([&] { return sub.getNumPublishers() > 0; }, 60.0)) << "no /afc/odom";
  ASSERT_TRUE(ros::service::waitForService("/afc/ann_controller/start", ros::Duration(60.0)));
  std_srvs::Empty start;
  ASSERT_TRUE(flapsim_test::call("/afc/ann_controller/start", start));
  ASSERT_TRUE(waitFor([&] { return height.count(samples) > 0; }, 200.0))
      << "the lockstep flight did not reach t = " << duration << " s; got " << height.size()
      << " samples";

  double sum = 0.0;
  for (long k = 1; k <= samples; ++k) {
    ASSERT_TRUE(height.count(k)) << "no odom at t = " << k * period;
    sum += height[k];
  }
  const double ros_fitness = sum / static_cast<double>(samples);

  flapsim::EpisodeParams episode;
  episode.duration = duration;
  episode.start_height = start_height;
  const flapsim::AnnWingController ann(flapsim::FlapUnitController(spec.params, spec.weights));
  flapsim::EpisodeStart from = flapsim::attitudeStart(roll, pitch);
  if (hold) from.altitude = altitude;
  const flapsim::EpisodeResult in_process =
      flapsim::runEpisode(flapsim::loadCreatureModel(urdf), ann, period, episode, from, true);
  ASSERT_EQ(in_process.trace.size(), static_cast<size_t>(samples));
  // Diagnostics: where the two flights part, if they do.
  double in_process_sum = 0.0;
  for (long k = 1; k <= samples; ++k) in_process_sum += in_process.trace[k - 1].height;
  for (long k = 1; k <= samples; ++k) {
    const double d = height[k] - in_process.trace[k - 1].height;
    if (std::abs(d) > 1e-12) {
      std::printf("first difference at t = %.2f s: ROS %.15f, in process %.15f\n", k * period,
                  height[k], in_process.trace[k - 1].height);
      break;
    }
  }
  const double in_process_mean = in_process_sum / static_cast<double>(samples);
  std::printf("mean height over %g s: ROS lockstep %.6f m, in process %.6f m\n", duration,
              ros_fitness, in_process_mean);
  // Lockstep is bit-reproducible: the same heights to the last bit. (Whether the committed
  // controller flies is the claim of the afc_lockstep rostests and test_evolve.cpp.)
  EXPECT_EQ(ros_fitness, in_process_mean);
  if (!hold) {
    EXPECT_EQ(ros_fitness, in_process.fitness);  // climbing: the fitness is that mean
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ann_controller_lockstep");
  return RUN_ALL_TESTS();
}
