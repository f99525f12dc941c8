#!/usr/bin/python3
"""Every flag of flapsim_bench in each of its forms (the timing table, --check without and with
--urdf, --urdf, --energy): the form reads it, or refuses it by name and exits 2 before running
anything. The table below says which form reads which flag; the flags that choose the form
(--energy, --check, --urdf) are in each form's base command. Argument: the devel prefix. With
--gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import os
import subprocess
import sys
import unittest

from gtest_xml import run_unittests

DEVEL = sys.argv[1]  # before unittest reads the command line
BENCH = os.path.join(DEVEL, "lib", "flapsim", "flapsim_bench")
UNIT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "urdf",
                    "flap_unit.urdf")

# Each flag that does not choose the form, with a value if it takes one.
FLAGS = {"--runs": ["1"], "--seconds": ["0.001"], "--only": ["plate"], "--json": [],
         "--cpu-time": [], "--step": ["0.001"], "--turn-substep": ["0.0005"], "--no-ground": [],
         "--reference-step": ["0.0005"], "--height": ["5"], "--skip": ["0"],
         "--added-mass-products": ["kirchhoff"], "--motor-work": ["servo"]}
# (form, its base command, the exit code of the base command with any flag it reads, the flags
# it reads). The energy form is given a creature file that does not exist: it exits 1 (the file
# named) without auditing, after the flags are read.
FORMS = [
    ("timing table", ["--runs", "1", "--seconds", "0.001"], 0,
     {"--runs", "--seconds", "--only", "--json", "--cpu-time", "--step", "--turn-substep",
      "--no-ground"}),
    ("--check", ["--check", "0.001", "--only", "plate"], 0,
     {"--only", "--step", "--turn-substep", "--no-ground", "--reference-step"}),
    ("--check --urdf", ["--check", "0.001", "--urdf", UNIT], 0,
     {"--height", "--step", "--turn-substep", "--no-ground", "--reference-step"}),
    ("--urdf", ["--urdf", UNIT, "--runs", "1", "--seconds", "0.001"], 0,
     {"--height", "--skip", "--runs", "--seconds", "--cpu-time", "--step", "--turn-substep",
      "--no-ground"}),
    ("--energy", ["--energy", "--urdf", "/nonexistent/creature.urdf"], 1,
     {"--seconds", "--added-mass-products", "--motor-work"}),
]


def bench(args):
    return subprocess.run([BENCH] + args, capture_output=True, text=True, timeout=120)


class BenchFlags(unittest.TestCase):
    def test_every_flag_is_read_or_refused_by_name_in_every_form(self):
        for form, base, code, reads in FORMS:
            for flag, values in FLAGS.items():
                with self.subTest(form=form, flag=flag):
                    r = bench(base + [flag] + values)
                    if flag in reads:
                        self.assertEqual(r.returncode, code, r.stderr[-300:])
                        self.assertNotIn("does nothing", r.stderr)
                    else:
                        self.assertEqual(r.returncode, 2, r.stderr[-300:])
                        self.assertTrue(r.stderr.startswith(f"flapsim_bench: {flag} does nothing"),
                                        r.stderr[-300:])
                        self.assertEqual(r.stdout, "")  # refused before anything ran


if __name__ == "__main__":
    run_unittests(sys.argv, "bench_flags", "EveryFlagIsReadOrRefused")
