// evolve --farm against hostile workers (farm_hostile.test starts two fake workers under
// /flapsim_farm: one answers NaN, one refuses). Alone they end the run with an error naming
// them, exit status 1 and no crash (issue 27, case 4: "terminate called ... lock_error" as the
// calling threads outlived ROS); beside a healthy flapsim_worker both are dropped by name and
// the run's files are those of the in-process run, bit for bit (case 3).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/text_file.h"
#include "flapsim_ros/episode_farm.h"
#include "start_worker.h"
#include "wait_for.h"

namespace {

const std::vector<std::string> kRun = {
    "--preset",   "robust", "--population", "4",  "--generations", "2",         "--episodes", "2",
    "--duration", "0.5",    "--seed",       "21", "--no-plot",     "--threads", "2"};
const std::string kNan = "/flapsim_farm/nan_worker/evaluate_episodes";
const std::string kRefuser = "/flapsim_farm/refuser/evaluate_episodes";

struct EvolveRun {
  int status = -1;   // the exit status, or 128 + the signal
  std::string text;  // stdout and stderr
};

// Runs evolve with `args` and `--out dir`, its output in dir.log.
EvolveRun evolve(std::vector<std::string> args, const std::string& dir) {
  args.insert(args.begin(), FLAPSIM_EVOLVE_BIN);
  args.insert(args.end(), {"--out", dir});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log = dir + ".log";
  std::filesystem::create_directories(std::filesystem::path(dir).parent_path());
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&files, 1, 2);
  pid_t pid = 0;
  EvolveRun run;
  if (posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ) == 0) {
    int status = 0;
    waitpid(pid, &status, 0);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  posix_spawn_file_actions_destroy(&files);
  run.text = flapsim::readTextFile(log, 1 << 24);
  return run;
}

std::string tempDir(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("flapsim_farm_hostile_" + std::to_string(::getpid())) / name)
      .string();
}

bool listed(const std::string& service) {
  return flapsim_ros::findWorkers("/flapsim_farm").count(service) > 0;
}

TEST(FarmHostile, HostileWorkersAloneEndTheRunByNameWithoutACrash) {
  ASSERT_TRUE(flapsim_test::waitFor([] { return listed(kNan) && listed(kRefuser); }, 30.0));
  for (int k = 0; k < 3; ++k) {  // the crash came in 5 of 5 runs
    std::vector<std::string> args = kRun;
    args.insert(args.end(), {"--farm", "--farm-wait", "30"});
    const EvolveRun run = evolve(args, tempDir("alone" + std::to_string(k)));
    EXPECT_EQ(run.status, 1) << run.text;
    EXPECT_NE(run.text.find("worker " + kNan + " answered fitness nan for task"), std::string::npos)
        << run.text;
    EXPECT_NE(run.text.find("evolve: farm: no worker left, and worker " + kRefuser +
                            " refused a call: fake worker: refusing"),
              std::string::npos)
        << run.text;
    EXPECT_EQ(run.text.find("terminate called"), std::string::npos) << run.text;
  }
}

TEST(FarmHostile, BesideAHealthyWorkerTheyAreDroppedAndTheRunIsTheInProcessOne) {
  const pid_t healthy = startWorker("/flapsim_farm", "healthy");
  ASSERT_GT(healthy, 0);
  ASSERT_TRUE(flapsim_test::waitFor(
      [] { return listed("/flapsim_farm/healthy/evaluate_episodes"); }, 30.0));
  std::vector<std::string> args = kRun;
  args.push_back("--farm");
  const EvolveRun farm = evolve(args, tempDir("farm"));
  const EvolveRun in_process = evolve(kRun, tempDir("in_process"));
  kill(healthy, SIGTERM);
  waitpid(healthy, nullptr, 0);
  ASSERT_EQ(farm.status, 0) << farm.text;
  ASSERT_EQ(in_process.status, 0) << in_process.text;
  EXPECT_NE(farm.text.find("worker " + kNan + " was dropped: answered fitness nan for task"),
            std::string::npos)
      << farm.text;
  EXPECT_NE(farm.text.find("worker " + kRefuser + " was dropped: refused a call"),
            std::string::npos)
      << farm.text;
  // The checkpoint holds every fitness and gene as a hex float: equal text, equal bits.
  for (const std::string file : {"checkpoint.txt", "fitness.csv", "rates.csv"}) {
    EXPECT_EQ(flapsim::readTextFile(tempDir("farm") + "/" + file, 1 << 24),
              flapsim::readTextFile(tempDir("in_process") + "/" + file, 1 << 24))
        << file;
  }
  std::filesystem::remove_all(std::filesystem::path(tempDir("farm")).parent_path());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_farm_hostile");
  return RUN_ALL_TESTS();
}
