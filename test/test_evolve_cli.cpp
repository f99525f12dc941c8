// The evolve executable: a run stopped after generation 1 and continued with --resume
// writes the same fitness.csv and weights as the run that went through, and a checkpoint
// of the last generation.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"

namespace {

const std::string kFlags =
    " --population 4 --episodes 2 --duration 0.6 --seed 17 --threads 2 --no-plot";

int evolve(const std::string& args) {
  return std::system((std::string(FLAPSIM_EVOLVE_BIN) + args + " > /dev/null").c_str());
}

TEST(EvolveCli, ResumeEndsWithTheFilesOfTheUninterruptedRun) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("flapsim_evolve_cli_" + std::to_string(::getpid()));
  const std::string whole = (dir / "whole").string(), part = (dir / "part").string();
  ASSERT_EQ(evolve(kFlags + " --generations 3 --out " + whole), 0);
  ASSERT_EQ(evolve(kFlags + " --generations 1 --out " + part), 0);
  EXPECT_EQ(flapsim::readCheckpointFile(part + "/checkpoint.txt").generation, 1);
  ASSERT_EQ(evolve(" --resume " + part + " --generations 3 --no-plot"), 0);
  EXPECT_EQ(flapsim::readTextFile(part + "/fitness.csv", 1 << 20),
            flapsim::readTextFile(whole + "/fitness.csv", 1 << 20));
  const auto a = flapsim::loadControllerYaml(part + "/weights.yaml");
  const auto b = flapsim::loadControllerYaml(whole + "/weights.yaml");
  EXPECT_EQ(a.weights, b.weights);
  const auto c = flapsim::readCheckpointFile(part + "/checkpoint.txt");
  EXPECT_EQ(c.generation, 3);
  EXPECT_EQ(c.history.size(), 4u);
  EXPECT_NE(evolve(" --resume " + (dir / "nothing").string()), 0);  // no checkpoint there
  std::filesystem::remove_all(dir);
}

// Issue 27, case 8: a checkpoint whose args were given `--weights <elsewhere>` made
// `evolve --resume` write there. It is refused (exit 2) and nothing is written.
TEST(EvolveCli, ATamperedCheckpointWritesNothingOutsideTheRun) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("flapsim_evolve_tamper_" + std::to_string(::getpid()));
  const std::string run = (dir / "run").string(), elsewhere = (dir / "elsewhere.yaml").string();
  ASSERT_EQ(evolve(kFlags + " --generations 0 --out " + run), 0);
  flapsim::EvolveCheckpoint c = flapsim::readCheckpointFile(run + "/checkpoint.txt");
  c.args.insert(c.args.end(), {"--weights", elsewhere});
  flapsim::writeCheckpointFile(run + "/checkpoint.txt", c);
  EXPECT_EQ(evolve(" --resume " + run + " --generations 1 --no-plot") / 256, 2);
  EXPECT_FALSE(std::filesystem::exists(elsewhere));
  std::filesystem::remove_all(dir);
}

}  // namespace
