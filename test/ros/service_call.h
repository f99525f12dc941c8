// A service call through a persistent connection, for rostests. roscpp (1.15.15 here) opens
// and closes a TCP connection per ros::service::call, and about one such call in 10^4 returns
// false without reaching the node's handler: its debug log shows the new connection's socket
// reported closed right after the previous call's connection on the same descriptor number
// was torn down. A persistent client connects once per service and keeps its socket; 30,000
// get_state calls through one returned true every time (doc/reliability.md).
#pragma once

#include <ros/ros.h>

#include <map>
#include <string>

namespace flapsim_test {

/// ros::service::call(service, srv) through one persistent client per service name, made
/// again whenever its connection is gone (the node or this process's ROS restarted). Returns
/// what the client's call returns: false if the call did not go through or the handler
/// returned false. Needs a ros::NodeHandle alive in the caller, as ros::service::call does
/// not (a client made while none is alive would start and stop the node).
template <class Srv>
bool call(const std::string& service, Srv& srv) {
  // Never destroyed: a client torn down after main returns would reach into roscpp's
  // singletons as they go.
  static auto* clients = new std::map<std::string, ros::ServiceClient>;
  ros::ServiceClient& client = (*clients)[service];
  if (!client.isValid()) client = ros::NodeHandle().serviceClient<Srv>(service, true);
  return client.call(srv);
}

}  // namespace flapsim_test
