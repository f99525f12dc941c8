#!/usr/bin/python3
"""The rostests as scripts/test.sh runs them, two at a time: rostest writes each <test>'s
result to rosunit-<test-name>.xml in one directory, so two .test files naming the same
test-name would overwrite (or remove) each other's results. Every test-name of test/ros/*.test
is unique, and every .test file there is registered in CMakeLists.txt (else it never runs).
With --gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import glob
import os
import re
import sys
import unittest
import xml.etree.ElementTree as ET

from gtest_xml import run_unittests

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def test_names(path, given=None):
    """The test-name of every <test> in a .test file, with its $(arg NAME)s resolved, and in the
    .test files of test/ros it includes (the launch files it includes hold no <test>)."""
    root = ET.parse(path).getroot()
    args = {a.get("name"): a.get("value", a.get("default")) for a in root.findall("arg")}
    args.update(given or {})

    def resolve(text):
        return re.sub(r"\$\(arg (\w+)\)", lambda m: args[m.group(1)], text)

    names = [resolve(t.get("test-name")) for t in root.iter("test")]
    for inc in root.iter("include"):
        f = inc.get("file")
        if f.startswith("$(find flapsim)/test/ros/"):
            passed = {a.get("name"): resolve(a.get("value")) for a in inc.findall("arg")}
            names += test_names(os.path.join(os.path.dirname(path), os.path.basename(f)), passed)
    return names


class RostestNames(unittest.TestCase):
    def setUp(self):
        self.files = sorted(glob.glob(os.path.join(ROOT, "test", "ros", "*.test")))
        self.assertGreater(len(self.files), 40)

    def test_every_test_name_is_used_by_one_test_file_only(self):
        owners = {}
        for f in self.files:
            names = test_names(f)
            self.assertTrue(names, f"{os.path.basename(f)} has no <test>")
            for name in names:
                owners.setdefault(name, []).append(os.path.basename(f))
        shared = {n: fs for n, fs in owners.items() if len(fs) > 1}
        self.assertEqual(shared, {}, "test-names shared by .test files (rosunit-<name>.xml)")

    def test_every_test_file_is_registered_in_cmake(self):
        with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
            cmake = f.read()
        registered = set(re.findall(r"test/ros/([\w.]+\.test)", cmake))
        # Files registered in a loop: foreach(VAR a b c) ... test/ros/<prefix>${VAR}.test
        for var, items, body in re.findall(r"foreach\((\w+) ([^)]*)\)(.*?)endforeach", cmake,
                                           re.S):
            for prefix, suffix in re.findall(r"test/ros/(\w*)\$\{" + var + r"\}(\w*)\.test",
                                             body):
                registered |= {f"{prefix}{item}{suffix}.test" for item in items.split()}
        missing = [os.path.basename(f) for f in self.files
                   if os.path.basename(f) not in registered]
        self.assertEqual(missing, [], "test/ros/*.test files CMakeLists.txt never runs")


if __name__ == "__main__":
    run_unittests(sys.argv, "RostestNames", "every_name_unique_and_registered")
