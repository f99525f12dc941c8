#include "flapsim/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "flapsim/types.h"

namespace flapsim {

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

std::string readTextFile(const std::string& path, std::size_t max_bytes) {
  // Opened without blocking (a FIFO would wait for a writer), then checked on the descriptor:
  // what is read is what was checked.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path + ": cannot open file");
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    throw InputError(path + ": not a regular file");
  }
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) {
    throw InputError(path + ": " + std::to_string(info.st_size) + " bytes, over the limit of " +
                     std::to_string(max_bytes) + " bytes");
  }
  // In chunks, stopping past the limit: the file may have grown since fstat().
  std::string text;
  text.reserve(static_cast<size_t>(info.st_size));
  char chunk[65536];
  for (;;) {
    const ssize_t got = ::read(fd, chunk, sizeof chunk);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw InputError(path + ": cannot read");
    if (got == 0) break;
    text.append(chunk, static_cast<size_t>(got));
    if (text.size() > max_bytes) {
      throw InputError(path + ": over the limit of " + std::to_string(max_bytes) + " bytes");
    }
  }
  return text;
}

std::string shortestDecimal(double x) {
  char buf[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

std::string commentLines(const std::string& text) {
  std::istringstream lines(text);
  std::string out;
  for (std::string line; std::getline(lines, line);) out += "# " + line + "\n";
  return out;
}

}  // namespace flapsim
