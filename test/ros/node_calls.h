// Calling flapsim_node in rostests: its services, each call checked, and `rostopic echo` as a
// user runs it.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "flapsim/GetState.h"
#include "flapsim/Step.h"
#include "service_call.h"

namespace flapsim_test {

/// Calls `service` with `request` (a call that does not go through fails the test); returns
/// the response.
template <class Srv>
typename Srv::Response callService(const std::string& service,
                                   const typename Srv::Request& request = {}) {
  Srv s;
  s.request = request;
  EXPECT_TRUE(flapsim_test::call(service, s)) << service;
  return s.response;
}

/// flapsim/step of `n` steps, which must succeed; returns the new sim time.
inline ros::Time step(std::uint32_t n) {
  flapsim::Step::Request r;
  r.steps = n;
  const flapsim::Step::Response s = callService<flapsim::Step>("/flapsim/step", r);
  EXPECT_TRUE(s.success) << s.status_message;
  return s.sim_time;
}

/// A std_srvs/Empty service (pause, unpause, reset).
inline void callEmpty(const std::string& service) { callService<std_srvs::Empty>(service); }

/// flapsim/get_state of `link` of `name` (empty: the root) in `reference_frame`.
inline flapsim::GetState::Response getState(const std::string& name, const std::string& link = "",
                                            const std::string& reference_frame = "") {
  flapsim::GetState::Request r;
  r.name = name;
  r.link = link;
  r.reference_frame = reference_frame;
  return callService<flapsim::GetState>("/flapsim/get_state", r);
}

/// What `rostopic echo -n 1 TOPIC` prints within 20 s (wall).
inline std::string firstMessageOf(const std::string& topic) {
  const std::string cmd = "timeout 20 /usr/bin/python3 /usr/bin/rostopic echo -n 1 " + topic;
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    pclose(p);
  }
  return out;
}

}  // namespace flapsim_test
