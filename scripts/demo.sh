#!/bin/bash
# Installs what is missing, builds, and flies the default scenario (the flap unit) headless:
# prints a summary and leaves flap_unit.bag, flap_unit.csv and flap_unit.png in out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
set +u
source build/devel/setup.bash
set -u
exec /usr/bin/python3 scripts/demo.py --out out/demo "$@"
