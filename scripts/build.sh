#!/bin/bash
# Configures and builds flapsim standalone (no catkin workspace) into ./build.
set -euo pipefail
cd "$(dirname "$0")/.."
# catkin puts the devel space's Python packages (the generated flapsim.msg/srv) on the tests'
# PYTHONPATH only if their directory exists when it configures: on a fresh clone it does not yet.
mkdir -p build/devel/lib/python3/dist-packages
cmake -S . -B build -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 -- --no-print-directory 2>&1 | grep -E "warning|error|Error" || true
test -x build/devel/lib/flapsim/make_creature
# rosrun skips every path under <package>/build/ (its find excludes it): link the compiled
# executables into <package>/bin, where `rosrun flapsim <tool>` finds them (the Python ones it
# finds in scripts/ and bench/). A catkin workspace or an install space needs none of this.
mkdir -p bin
for exe in build/devel/lib/flapsim/*; do
  case "$(basename "$exe")" in test_*) continue ;; esac
  if [ -f "$exe" ] && [ -x "$exe" ] && [ "$(head -c 4 "$exe" | tr -d '\0')" = $'\x7fELF' ]; then
    ln -sfn "../$exe" "bin/$(basename "$exe")"
  fi
done
