#!/usr/bin/python3
"""`rosrun flapsim <tool> --help` for every tool, from the devel space of scripts/build.sh's build
(./build, whose executables rosrun would skip: scripts/build.sh links them into ./bin) and from
an install space (`cmake --install` into a temporary prefix): each prints its usage on
standard output and exits 0. Arguments: the devel prefix and the build directory. With
--gtest_output=xml:FILE also writes a gtest-style result for catkin_test_results.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from gtest_xml import run_unittests

# (tool, its help flag, the start of its usage)
TOOLS = [
    ("evolve", "--help", "usage: evolve"),
    ("flight_check", "--help", "usage: flight_check"),
    ("make_creature", "--help", "usage: make_creature"),
    ("sweep", "--help", "usage: sweep"),
    ("disturbance", "--help", "usage: disturbance"),
    ("flapsim_bench", "--help", "usage: flapsim_bench"),
    ("spawn_creature", "-h", "Spawns a creature into a running flapsim"),
    ("render_movie.py", "--help", "usage: render_movie.py"),
    ("screenshot.py", "--help", "usage: screenshot.py"),
    ("rviz.py", "--help", "usage: rviz.py"),
    ("demo.py", "--help", "usage: demo.py"),
    ("node_rtf.py", "--help", "usage: node_rtf.py"),
    ("flapsim_record", "-h", "usage: flapsim_record"),
]
DEVEL, BUILD = sys.argv[1], sys.argv[2]  # before unittest reads the command line


def rosrun(prelude, tool, flag):
    """`rosrun flapsim tool flag` in a shell that runs `prelude` first, from an environment
    without this build's (no ROS_*, CMAKE_PREFIX_PATH, PYTHONPATH, LD_LIBRARY_PATH)."""
    cmd = f"{prelude} && rosrun flapsim {tool} {flag} < /dev/null"
    return subprocess.run(["bash", "-c", cmd], capture_output=True, text=True, timeout=60,
                          env={k: v for k, v in os.environ.items()
                               if not k.startswith(("ROS_", "CMAKE_PREFIX", "PYTHONPATH",
                                                    "LD_LIBRARY_PATH"))})


class RosrunHelp(unittest.TestCase):
    def check(self, prelude):
        for tool, flag, usage in TOOLS:
            r = rosrun(prelude, tool, flag)
            self.assertEqual(r.returncode, 0, f"{tool}: {r.stdout[-300:]} {r.stderr[-300:]}")
            self.assertTrue(r.stdout.startswith(usage), f"{tool}: {r.stdout[:200]}")

    def test_every_tool_answers_help_from_the_devel_space(self):
        self.check(f"source '{os.path.join(DEVEL, 'setup.bash')}'")

    def test_every_tool_answers_help_from_an_install_space(self):
        prefix = tempfile.mkdtemp(prefix="flapsim_install_")
        try:
            subprocess.run(["cmake", "--install", BUILD, "--prefix", prefix], check=True,
                           capture_output=True, timeout=300)
            # A standalone package's install has no setup.bash: its paths, as a workspace's
            # setup would set them.
            self.check(f"export CMAKE_PREFIX_PATH='{prefix}:/usr' ROS_PACKAGE_PATH='{prefix}/share'"
                       f" LD_LIBRARY_PATH='{prefix}/lib'"
                       f" PYTHONPATH='{prefix}/lib/python3/dist-packages'")
        finally:
            shutil.rmtree(prefix, ignore_errors=True)


if __name__ == "__main__":
    run_unittests(sys.argv, "rosrun_help", "EveryToolAnswersHelp")
