// The node's input guards that need no master: the warning limiter and where spawn requests
// may read URDF files from.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/types.h"
#include "flapsim_ros/urdf_source.h"
#include "flapsim_ros/warning_limiter.h"

namespace {

using flapsim_ros::WarningLimiter;

TEST(WarningLimiter, OneMessagePerCausePerPeriod) {
  WarningLimiter w(10.0, 256);
  EXPECT_TRUE(w.allow("wing_command/no joint ''", "a", 0.0));
  EXPECT_FALSE(w.allow("wing_command/no joint ''", "a", 9.9));
  EXPECT_TRUE(w.allow("wing_command/no joint ''", "b", 9.9));       // another creature
  EXPECT_TRUE(w.allow("wing_command/differ in length", "a", 9.9));  // another kind
  EXPECT_TRUE(w.allow("wing_command/no joint ''", "a", 10.0));      // a period later
}

// A new unknown joint name in each bad command was a new key in the limiter's table: memory
// and the log grew by one entry per message.
TEST(WarningLimiter, DistinctBadNamesAreOneCauseAndTheTableIsBounded) {
  EXPECT_EQ(WarningLimiter::kindOf("creature 'a': no joint 'x1'"),
            WarningLimiter::kindOf("creature 'a': no joint 'y22'"));
  EXPECT_EQ(WarningLimiter::kindOf("3 commands for 2 wing joints"),
            WarningLimiter::kindOf("1 commands for 12 wing joints"));
  EXPECT_NE(WarningLimiter::kindOf("no joint 'x'"), WarningLimiter::kindOf("joint 'x' is fixed"));
  EXPECT_LE(WarningLimiter::kindOf(std::string(100000, 'x')).size(), 160u);

  WarningLimiter w(10.0, 256);
  int allowed = 0;
  for (int i = 0; i < 100000; ++i) {
    const std::string msg = "creature 'a': no joint 'j" + std::to_string(i) + "'";
    allowed += w.allow("wing_command/" + WarningLimiter::kindOf(msg), "a", 1e-3 * i);
  }
  EXPECT_EQ(allowed, 10);  // one per 10 s over 100 s
  for (int i = 0; i < 100000; ++i) w.allow("spawn", "name" + std::to_string(i), 0.0);
  EXPECT_LE(w.causes(), 256u);
}

// Issue 27, case 7: a full table was cleared, so a stream of distinct causes logged a line
// each. At most max_causes per period get through.
TEST(WarningLimiter, AStreamOfDistinctCausesIsBoundedPerPeriod) {
  WarningLimiter w(10.0, 256);
  int allowed = 0;
  for (int i = 0; i < 3000; ++i) allowed += w.allow("get_state/" + std::to_string(i), "", 1e-4 * i);
  EXPECT_EQ(allowed, 256);
  EXPECT_TRUE(w.allow("get_state/new", "", 10.0));  // the old ones have aged out
}

class SpawnFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string dir = (std::filesystem::temp_directory_path() / "flapsim_roots_XXXXXX").string();
    root_ = ::mkdtemp(&dir[0]);
    ::mkdir((root_ + "/allowed").c_str(), 0700);
    write(root_ + "/allowed/plate.urdf", "<robot name='p'/>");
    write(root_ + "/outside.urdf", "<robot name='o'/>");
    ::mkfifo((root_ + "/allowed/pipe.urdf").c_str(), 0600);
    ::symlink((root_ + "/outside.urdf").c_str(), (root_ + "/allowed/link.urdf").c_str());
    ::chmod(write(root_ + "/allowed/secret.urdf", "<robot/>").c_str(), 0);
  }
  void TearDown() override {
    for (const char* f : {"/allowed/plate.urdf", "/allowed/pipe.urdf", "/allowed/link.urdf",
                          "/allowed/secret.urdf", "/outside.urdf"}) {
      ::unlink((root_ + f).c_str());
    }
    ::rmdir((root_ + "/allowed").c_str());
    ::rmdir(root_.c_str());
  }
  static std::string write(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
  }
  std::string refusal(const std::string& path) const {
    try {
      flapsim_ros::readSpawnUrdf(path, {root_ + "/allowed"});
    } catch (const flapsim::InputError& e) {
      return e.what();
    }
    return "(read)";
  }
  std::string root_;
};

// Missing, unreadable, a directory, a FIFO (which blocked the node), outside the roots,
// through a link or "..": one text, so a reply does not tell which files exist.
TEST_F(SpawnFiles, EveryRefusedPathGetsTheSameText) {
  const std::string allowed = root_ + "/allowed";
  EXPECT_EQ(flapsim_ros::readSpawnUrdf(allowed + "/plate.urdf", {allowed}), "<robot name='p'/>");
  const std::vector<std::string> refused = {
      allowed + "/missing.urdf",
      allowed,
      allowed + "/pipe.urdf",
      allowed + "/link.urdf",
      root_ + "/outside.urdf",
      allowed + "/../outside.urdf",
      "/etc/hostname",
      "/dev/zero",
      "",
  };
  for (const std::string& path : refused) {
    EXPECT_EQ(refusal(path), flapsim_ros::refusedUrdfFileMessage(path, {allowed}, "")) << path;
  }
  if (::geteuid() != 0) {  // root reads a file whatever its mode
    EXPECT_EQ(refusal(allowed + "/secret.urdf"),
              flapsim_ros::refusedUrdfFileMessage(allowed + "/secret.urdf", {allowed}, ""));
  }
  // It names the roots, and where a relative path starts.
  EXPECT_EQ(flapsim_ros::refusedUrdfFileMessage("/x", {"/a", "/b"}, "/w"),
            "urdf_file '/x' refused: it must be a readable regular file of at most 16 MiB under "
            "an allowed root (parameter ~urdf_roots: /a, /b)");
  EXPECT_EQ(flapsim_ros::refusedUrdfFileMessage("my.urdf", {"/a"}, "/home/u/.ros"),
            "urdf_file 'my.urdf' refused: it must be a readable regular file of at most 16 MiB "
            "under an allowed root (parameter ~urdf_roots: /a); a relative path starts at the "
            "node's working directory, /home/u/.ros (spawn_creature -file reads a file where it "
            "runs)");
}

TEST(SpawnRoots, DefaultsAreThePackagePathAndTheWorkingDirectory) {
  EXPECT_EQ(flapsim_ros::defaultUrdfRoots("/a/src:/b::/c", "/home/u/.ros"),
            (std::vector<std::string>{"/a/src", "/b", "/c", "/home/u/.ros"}));
  EXPECT_EQ(flapsim_ros::defaultUrdfRoots(nullptr, "/w"), (std::vector<std::string>{"/w"}));
}

}  // namespace
