// A flapsim_worker process of a test's own (so that the test can kill it), in namespace `ns`.
// Needs FLAPSIM_WORKER_BIN, the worker executable's path.
#pragma once

#include <spawn.h>
#include <sys/types.h>

#include <string>
#include <vector>

extern char** environ;

inline pid_t startWorker(const std::string& ns, const std::string& name) {
  std::vector<std::string> args = {FLAPSIM_WORKER_BIN, "__ns:=" + ns, "__name:=" + name,
                                   "_threads:=1"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  return pid;
}
