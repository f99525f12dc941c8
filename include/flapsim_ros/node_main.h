// The body of every flapsim node's main(): a node that cannot run says why before it exits.
#pragma once

#include <functional>
#include <string>

namespace flapsim_ros {

/// Runs `body` (after ros::init) and returns its exit code. An exception from it is the
/// node's fatal cause: logged as FATAL "<node>: <what>" (stderr and rosout) while roscpp is
/// still up, and, when a master answers, held until the rosout node has published it on
/// /rosout_agg (at most 2 s of wall time), so that it reaches rosout and the node's log before
/// the process ends; then 1 is returned.
int runNode(const std::string& node, const std::function<int()>& body);

}  // namespace flapsim_ros
