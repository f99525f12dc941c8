// evolve --farm as evolve_farm.launch starts it (see evolve_farm.test), waiting for
// workers; once this test listens to /flapsim_farm/progress it starts two workers: the
// last progress line has the best and mean of the same evolution in process, bit for
// bit, and both workers up.
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <signal.h>
#include <sys/wait.h>

#include <string>
#include <vector>

#include "flapsim/FarmProgress.h"
#include "flapsim/evolve_args.h"
#include "start_worker.h"
#include "wait_for.h"

namespace {

TEST(EvolveFarmLaunch, ProgressEndsWithTheInProcessBestAndMean) {
  ros::NodeHandle nh;
  std::vector<flapsim::FarmProgress> seen;
  ros::Subscriber sub = nh.subscribe<flapsim::FarmProgress>(
      "/flapsim_farm/progress", 10, [&](const flapsim::FarmProgressConstPtr& m) {
        if (seen.empty() || seen.back().generation != m->generation) seen.push_back(*m);
      });
  // evolve is up (it advertises its progress first) and has nobody to work for it yet.
  ASSERT_TRUE(flapsim_test::waitFor([&] { return sub.getNumPublishers() > 0; }, 30.0));
  EXPECT_TRUE(seen.empty());
  const pid_t workers[2] = {startWorker("/flapsim_farm", "late_1"),
                            startWorker("/flapsim_farm", "late_2")};
  const bool done = flapsim_test::waitFor(
      [&] { return !seen.empty() && seen.back().generation == seen.back().generations; }, 90.0);
  for (pid_t w : workers) {
    if (w > 0) kill(w, SIGTERM);
    if (w > 0) waitpid(w, nullptr, 0);
  }
  ASSERT_TRUE(done);
  EXPECT_EQ(seen.size(), 3u);  // generations 0, 1, 2
  const flapsim::EvolveParams p =
      flapsim::parseEvolveArgs({"--preset", "robust", "--generations", "2", "--population", "4",
                                "--seed", "13", "--episodes", "2", "--duration", "1"})
          .params;
  const flapsim::EvolveResult in_process = flapsim::evolveFlapController(p);
  const flapsim::FarmProgress& last = seen.back();
  EXPECT_EQ(last.generations, 2);
  EXPECT_EQ(last.best, in_process.history.back().best);
  EXPECT_EQ(last.mean, in_process.history.back().mean);
  EXPECT_EQ(last.episodes, in_process.history.back().evaluations * 2);
  EXPECT_EQ(last.workers_up, 2);
  EXPECT_GE(last.episodes_per_second, 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_evolve_farm");
  return RUN_ALL_TESTS();
}
