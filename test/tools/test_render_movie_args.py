#!/usr/bin/python3
"""scripts/render_movie.py's refusals of bad arguments, before any X server, rviz or bag is
started or read: a --size that is not WIDTHxHEIGHT, numbers out of range, a --bag that is not
a regular file (a FIFO is not waited on). Each is an argparse error (exit 2, the last line
naming the flag), no traceback, no movie written. With --gtest_output=xml:FILE also writes a
gtest-style result for catkin_test_results.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from gtest_xml import run_unittests

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
TOOL = os.path.join(ROOT, "scripts", "render_movie.py")
WAIT = 30  # s: bounds a run that would otherwise wait for ever (on a FIFO)


class RenderMovieArgs(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="flapsim_render_args_")
        self.out = os.path.join(self.dir, "out.mp4")
        self.bag = os.path.join(self.dir, "empty.bag")  # a regular file: passes the --bag check
        open(self.bag, "w").close()

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def assert_refused(self, args, line):
        result = subprocess.run(["/usr/bin/python3", TOOL, "--out", self.out] + args,
                                capture_output=True, text=True, timeout=WAIT)
        self.assertNotIn("Traceback", result.stderr, args)
        self.assertEqual(result.returncode, 2, (args, result.stderr))
        self.assertEqual(result.stderr.strip().splitlines()[-1], line, args)
        self.assertFalse(os.path.exists(self.out), args)

    def test_a_size_that_is_not_width_x_height_in_range_is_an_error_naming_size(self):
        for size, why in [
                ("abc", "'abc' is not WIDTHxHEIGHT (e.g. 640x480)"),
                ("640", "'640' is not WIDTHxHEIGHT (e.g. 640x480)"),
                ("640x480x3", "'640x480x3' is not WIDTHxHEIGHT (e.g. 640x480)"),
                ("640.5x480", "'640.5x480' is not WIDTHxHEIGHT (e.g. 640x480)"),
                ("0x480", "'0x480': width and height must be in [16, 8192] pixels"),
                ("640x100000", "'640x100000': width and height must be in [16, 8192] pixels")]:
            self.assert_refused(["--bag", self.bag, "--size", size],
                                f"render_movie.py: error: argument --size: {why}")

    def test_numbers_out_of_range_are_errors_naming_the_flag(self):
        for flag, value, why in [
                ("--speed", "nan", "'nan' is not in (0, 1e6]"),
                ("--speed", "0", "'0' is not in (0, 1e6]"),
                ("--rate", "-1", "'-1' is not in (0, 1e6]"),
                ("--rate", "inf", "'inf' is not in (0, 1e6]"),
                ("--distance", "0", "'0' is not in (0, 1e6]"),
                ("--timeout", "1e9", "'1e9' is not in (0, 1e6]"),
                ("--timeout", "abc", "'abc' is not a number"),
                ("--fps", "0", "'0' is not in [1, 240]"),
                ("--fps", "2.5", "'2.5' is not an integer"),
                ("--port", "70000", "'70000' is not in [1, 65535]"),
                ("--duration", "-1", "'-1' is not in (0, 1e6]")]:
            self.assert_refused(["--bag", self.bag, flag, value],
                                f"render_movie.py: error: argument {flag}: {why}")

    def test_a_bag_that_is_not_a_regular_file_is_refused_by_name_and_a_fifo_is_not_waited_on(self):
        fifo = os.path.join(self.dir, "fifo.bag")
        os.mkfifo(fifo)  # no writer: opening it to read blocks unless without blocking
        for path in (fifo, "/dev/zero", self.dir):
            self.assert_refused(["--bag", path],
                                f"render_movie.py: error: argument --bag: {path}: not a "
                                "regular file")
        missing = os.path.join(self.dir, "missing.bag")
        self.assert_refused(["--bag", missing], "render_movie.py: error: argument --bag: "
                            f"cannot read {missing}: No such file or directory")


if __name__ == "__main__":
    run_unittests(sys.argv, "render_movie_args", "RefusesBadArguments")
