// A figure a measured table of the docs reads from a test's output
// (scripts/doc_tables_registry.py runs the test binary with --gtest_filter and parses these).
#pragma once

#include <gtest/gtest.h>

#include <cstdarg>
#include <cstdio>
#include <string>

namespace flapsim {
namespace test {

/// Prints "[figure] Suite.Test name value" on stdout (value to full precision); `name` has no
/// spaces. The test that prints it still asserts on the value itself.
inline void printFigure(const std::string& name, double value) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::printf("[figure] %s.%s %s %.17g\n", info ? info->test_suite_name() : "-",
              info ? info->name() : "-", name.c_str(), value);
  std::fflush(stdout);
}

/// A figure's name from a printf format ("height_%gms", 0.5): a figure per case of a loop.
inline std::string figureName(const char* format, ...) {
  char name[200];
  va_list args;
  va_start(args, format);
  std::vsnprintf(name, sizeof name, format, args);
  va_end(args);
  return name;
}

}  // namespace test
}  // namespace flapsim
