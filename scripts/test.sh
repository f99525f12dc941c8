#!/bin/bash
# Installs what is missing, builds, and runs every test (gtest and rostest). Ends with
# catkin_test_results' verdict and one line "N passed, M failed".
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh || exit 1
bash scripts/build.sh || exit 1
rm -rf build/test_results
cmake --build build --target tests -j2 -- --no-print-directory >/dev/null || exit 1
# Two at a time: the gtests with the tool checks, then the rostests with rviz, each phase one
# make goal (CMakeLists.txt: flapsim_tests_core, flapsim_tests_nodes). A rostest's nodes step
# in lockstep or against sim time and use under one core between them (node, controller and
# test wait on each other), and each starts its own master on a free port.
{
  cmake --build build --target flapsim_tests_core -j2 -- --no-print-directory 2>&1
  cmake --build build --target flapsim_tests_nodes -j2 -- --no-print-directory 2>&1
} | grep -E "^\[ *(RUN|OK|FAILED|PASSED) |^\[ *FAILED|FAILURE|ERROR|rostest|Ran [0-9]+ test" || true
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
        print(f"FAILED {f}: not valid XML")
        continue
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite")
    for s in suites:
        for case in s.iter("testcase"):
            bad = case.find("failure")
            bad = bad if bad is not None else case.find("error")
            if bad is not None:
                failed += 1
                # What failed and why, at the end of the log where a CI summary shows it.
                text = (bad.get("message") or "") + "\n" + (bad.text or "")
                lines = [l for l in text.strip().splitlines() if l.strip()][-12:]
                print(f"FAILED {s.get('name')}.{case.get('name')} ({f}):")
                print("\n".join("    " + l for l in lines))
            elif case.find("skipped") is not None:
                skipped += 1
            else:
                passed += 1
print(f"{passed} passed, {failed} failed" + (f", {skipped} skipped" if skipped else ""))
PY
exit $verdict
