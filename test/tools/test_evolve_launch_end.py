#!/usr/bin/python3
"""`roslaunch flapsim evolve.launch` (and evolve_farm.launch, on one worker) of a tiny evolution
(one generation of two, half-second episodes) ends by itself, quietly: no "REQUIRED process ...
has died!" banner (required alone printed it on success too), the results written; one that
fails (an unknown preset) still ends with the banner naming evolve. Each runs roslaunch with its own master on a free port.
Argument: the devel prefix. With --gtest_output=xml:FILE also writes a gtest-style result.
"""
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import unittest

from gtest_xml import run_unittests

DEVEL = sys.argv[1]  # before unittest reads the command line
TIMEOUT = 120  # s: a bound on the launch, not a measurement


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def roslaunch(*args, launch="evolve.launch"):
    """roslaunch flapsim LAUNCH ARGS with its own master: (exit code, output)."""
    port = free_port()
    cmd = (f"source '{os.path.join(DEVEL, 'setup.bash')}' && "
           f"export ROS_MASTER_URI=http://localhost:{port} && "
           f"roslaunch -p {port} flapsim {launch} {' '.join(args)} < /dev/null")
    r = subprocess.run(["bash", "-c", cmd], capture_output=True, text=True, timeout=TIMEOUT)
    return r.returncode, r.stdout + r.stderr


class EvolveLaunchEnd(unittest.TestCase):
    def setUp(self):
        self.out = tempfile.mkdtemp(prefix="flapsim_evolve_launch_")

    def tearDown(self):
        shutil.rmtree(self.out, ignore_errors=True)

    def test_a_successful_evolution_ends_the_launch_quietly(self):
        code, output = roslaunch("preset:=paper", "generations:=1", "population:=2",
                                 "duration:=0.5", f"out:={self.out}")
        self.assertEqual(code, 0, output[-2000:])
        self.assertNotIn("REQUIRED process", output)
        self.assertNotIn("has died", output)
        self.assertIn("... shutting down processing monitor complete", output)
        self.assertTrue(os.path.isfile(os.path.join(self.out, "weights.yaml")), output[-2000:])

    def test_a_successful_farm_evolution_ends_the_launch_quietly(self):
        code, output = roslaunch("workers:=1", "preset:=paper", "generations:=1",
                                 "population:=2", "duration:=0.5", f"out:={self.out}",
                                 launch="evolve_farm.launch")
        self.assertEqual(code, 0, output[-2000:])
        self.assertNotIn("REQUIRED process", output)
        self.assertNotIn("has died", output)
        self.assertTrue(os.path.isfile(os.path.join(self.out, "weights.yaml")), output[-2000:])

    def test_a_failed_evolution_ends_the_launch_saying_so(self):
        code, output = roslaunch("preset:=nonsense", f"out:={self.out}")
        self.assertIn("evolve: --preset: 'nonsense' is not one of", output)
        self.assertIn("REQUIRED process [evolve-", output)
        self.assertIn("exit code 2", output)


if __name__ == "__main__":
    run_unittests(sys.argv, "evolve_launch_end", "EvolveLaunchEnd")
