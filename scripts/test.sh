#!/bin/bash
# Installs what is missing, builds, and runs every test (gtest and rostest). Ends with
# catkin_test_results' verdict and one line "N passed, M failed".
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh || exit 1
bash scripts/build.sh || exit 1
rm -rf build/test_results
cmake --build build --target tests -j2 -- --no-print-directory >/dev/null || exit 1
cmake --build build --target run_tests -j1 -- --no-print-directory 2>&1 |
  grep -E "^\[ *(RUN|OK|FAILED|PASSED) |^\[ *FAILED|FAILURE|ERROR|rostest|Ran [0-9]+ test" || true
catkin_test_results build/test_results
verdict=$?
/usr/bin/python3 - <<'PY'
import glob, xml.etree.ElementTree as ET
passed = failed = skipped = 0
for f in glob.glob("build/test_results/**/*.xml", recursive=True):
    try:
        root = ET.parse(f).getroot()
    except ET.ParseError:
        failed += 1
        continue
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite")
    for s in suites:
        for case in s.iter("testcase"):
            if case.find("failure") is not None or case.find("error") is not None:
                failed += 1
            elif case.find("skipped") is not None:
                skipped += 1
            else:
                passed += 1
print(f"{passed} passed, {failed} failed" + (f", {skipped} skipped" if skipped else ""))
PY
exit $verdict
