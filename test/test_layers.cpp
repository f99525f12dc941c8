// The core stays ROS-free: no file under include/flapsim/ or src/core/ includes a ROS
// header (roscpp, messages, tf2, dynamic_reconfigure, XmlRpc, the package's generated
// interfaces or its ROS adapters).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The #include lines of the core that name a ROS header: "file:line: text".
std::vector<std::string> rosIncludes(const fs::path& dir) {
  // ros/..., <pkg>_msgs/..., <pkg>_srvs/..., tf2*/..., dynamic_reconfigure/..., XmlRpc*,
  // xmlrpcpp/..., flapsim_ros/..., and flapsim/<Capitalised>.h (generated messages).
  static const std::regex ros(
      R"re(^\s*#\s*include\s*[<"](ros/|[A-Za-z0-9_]+_(msgs|srvs)/|tf2[A-Za-z0-9_]*/|dynamic_reconfigure/|XmlRpc|xmlrpcpp/|flapsim_ros/|flapsim/[A-Z]))re");
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path());
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (std::regex_search(line, ros)) {
        found.push_back(entry.path().string() + ":" + std::to_string(n) + ": " + line);
      }
    }
  }
  return found;
}

TEST(Layers, CoreIncludesNoRosHeader) {
  const fs::path root(FLAPSIM_SOURCE_DIR);
  for (const char* dir : {"include/flapsim", "src/core"}) {
    ASSERT_TRUE(fs::is_directory(root / dir)) << dir;
    for (const std::string& hit : rosIncludes(root / dir)) ADD_FAILURE() << hit;
  }
}

// The check itself: it does flag ROS headers and lets the core's own through.
TEST(Layers, TheCheckFlagsRosHeadersOnly) {
  const fs::path dir = fs::temp_directory_path() / "flapsim_test_layers";
  fs::create_directories(dir);
  std::ofstream(dir / "bad.h") << "#include <ros/ros.h>\n#include \"flapsim/WingCommand.h\"\n"
                               << "#include <geometry_msgs/Pose.h>\n#include <tf2/LinearMath.h>\n";
  std::ofstream(dir / "good.h") << "#include \"flapsim/world.h\"\n#include <Eigen/Core>\n"
                                << "#include <BulletDynamics/btBulletDynamicsCommon.h>\n";
  EXPECT_EQ(rosIncludes(dir).size(), 4u);
  fs::remove_all(dir);
}

}  // namespace
