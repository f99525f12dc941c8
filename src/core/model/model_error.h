// The model parser's error: a ModelError naming the source (file or "<string>"). Private to
// flapsim_core.
#pragma once

#include <string>

#include "flapsim/types.h"

namespace flapsim {

[[noreturn]] inline void fail(const std::string& source, const std::string& what) {
  throw ModelError(source + ": " + what);
}

}  // namespace flapsim
