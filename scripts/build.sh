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
