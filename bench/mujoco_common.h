// MuJoCo helpers shared by the benchmarks and comparisons that run MuJoCo (Debian's 2.2.2).
#pragma once

#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

namespace flapsim_bench {

// Suppresses MuJoCo's default warning handler (it writes MUJOCO_LOG.TXT in the working
// directory); warnings go to stderr instead.
inline void warningToStderr(const char* msg) { std::fprintf(stderr, "mujoco warning: %s\n", msg); }

// Compiles MJCF text through MuJoCo's virtual file system. Throws std::runtime_error with
// MuJoCo's message.
inline mjModel* compileMjcf(const std::string& xml) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* file = "creature.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), file, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("cannot add the model to MuJoCo's VFS");
  }
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), file)], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(file, vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("mj_loadXML: ") + error);
  return m;
}

}  // namespace flapsim_bench
