// Reading and writing the package's text files (weights, checkpoints, URDF): every read is of
// a regular file with a size limit. ROS-free.
#pragma once

#include <cstddef>
#include <string>

namespace flapsim {

/// Throws std::runtime_error if the file cannot be written.
void writeTextFile(const std::string& path, const std::string& text);

/// The text of a regular file of at most `max_bytes`: a directory, FIFO, device or socket is
/// refused without being read or waited on ("<path>: not a regular file"), a file over the
/// limit too ("<path>: N bytes, over the limit of M bytes"), so every read ends soon and a
/// SIGINT is seen. Throws InputError naming the path.
std::string readTextFile(const std::string& path, std::size_t max_bytes);

/// `text` as comment lines of a YAML or shell file: each line prefixed with "# ".
std::string commentLines(const std::string& text);

/// The shortest decimal that reads back as `x`, bit for bit (a number of a YAML file).
std::string shortestDecimal(double x);

}  // namespace flapsim
