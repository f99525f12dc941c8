#!/bin/bash
# Retakes the screenshots in doc/ (rviz under a private Xvfb, force arrows on): the flap unit
# climbing, the 12-unit chain, a flock of 4 and the gliding plates.
# Needs a build (bash scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
set +u
source build/devel/setup.bash
set -u
shot() { /usr/bin/python3 scripts/screenshot.py --size 800x600 "$@"; }
shot --out doc/flap_unit.png --at 2 flap_unit.launch
shot --out doc/afc_12.png --at 3 afc.launch pairs:=12
shot --out doc/flock_4.png --at 3 flock.launch count:=4
shot --out doc/glide.png --at 0.8 glide.launch
rm -f doc/flap_unit.log doc/afc_12.log doc/flock_4.log doc/glide.log
