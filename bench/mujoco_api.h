// MuJoCo for the benchmarks and comparisons that run it (mujoco_bench, mujoco_wing): its
// functions from the library FLAPSIM_MUJOCO_LIBRARY names (set by the build), opened with
// RTLD_LOCAL | RTLD_DEEPBIND rather than linked: MuJoCo 3 exports the tinyxml2 it carries (a
// newer one than Debian's), which linked into one process with urdfdom (flapsim's URDF parser,
// on Debian's tinyxml2) would serve urdfdom's calls with the wrong ABI and crash. Opened
// locally and bound deep, each library keeps its own.
#pragma once

#include <dlfcn.h>
#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace flapsim_bench {

struct MujocoApi {
  decltype(&mj_loadXML) loadXML = nullptr;
  decltype(&mj_deleteModel) deleteModel = nullptr;
  decltype(&mj_makeData) makeData = nullptr;
  decltype(&mj_deleteData) deleteData = nullptr;
  decltype(&mj_step) step = nullptr;
  decltype(&mj_forward) forward = nullptr;
  decltype(&mj_versionString) versionString = nullptr;
  decltype(&mju_user_warning) user_warning = nullptr;  // the address of the handler pointer
};
inline MujocoApi mj;

// Opens the library and finds the functions; false (after a message naming `tool` and what is
// missing) if it cannot.
inline bool openMujoco(const char* library, const char* tool) {
  void* lib = dlopen(library, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
  if (!lib) {
    std::fprintf(stderr, "%s: cannot open %s: %s\n", tool, library, dlerror());
    return false;
  }
  bool ok = true;
  auto find = [&](auto& out, const char* name) {
    out = reinterpret_cast<std::remove_reference_t<decltype(out)>>(dlsym(lib, name));
    if (!out) {
      std::fprintf(stderr, "%s: %s has no %s\n", tool, library, name);
      ok = false;
    }
  };
  find(mj.loadXML, "mj_loadXML");
  find(mj.deleteModel, "mj_deleteModel");
  find(mj.makeData, "mj_makeData");
  find(mj.deleteData, "mj_deleteData");
  find(mj.step, "mj_step");
  find(mj.forward, "mj_forward");
  find(mj.versionString, "mj_versionString");
  find(mj.user_warning, "mju_user_warning");
  return ok;
}

// Suppresses MuJoCo's default warning handler (it writes MUJOCO_LOG.TXT in the working
// directory); warnings go to stderr instead.
inline void warningToStderr(const char* msg) { std::fprintf(stderr, "mujoco warning: %s\n", msg); }

// Compiles MJCF text through a temporary file (the in-memory file system's interface differs
// between MuJoCo 2 and 3; a file reads the same in both). Throws std::runtime_error with
// MuJoCo's message.
inline mjModel* compileMjcf(const std::string& xml) {
  std::string name = (std::filesystem::temp_directory_path() / "mujoco_bench_XXXXXX.xml").string();
  std::vector<char> path(name.begin(), name.end());
  path.push_back('\0');
  const int fd = mkstemps(path.data(), 4);
  if (fd < 0) throw std::runtime_error("cannot create a temporary file for the model");
  FILE* f = fdopen(fd, "w");
  const bool written = f && std::fwrite(xml.data(), 1, xml.size(), f) == xml.size();
  if (f) std::fclose(f);
  char error[1000] = "";
  mjModel* m = written ? mj.loadXML(path.data(), nullptr, error, sizeof(error)) : nullptr;
  std::remove(path.data());
  if (!written) throw std::runtime_error("cannot write the model to a temporary file");
  if (!m) throw std::runtime_error(std::string("mj_loadXML: ") + error);
  return m;
}

}  // namespace flapsim_bench
