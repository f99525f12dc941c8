#!/usr/bin/python3
"""Starts rviz with flapsim's config, adjusted for one scenario or for a recording.

rviz.py [--config FILE] [--distance D] [--yaw Y] [--pitch P] [--size WxH] [--bare] [rviz args]

The camera is the frame flapsim/camera, which the simulator (or a replayed bag) moves: it
looks at the creatures' smoothed centroid (frame flapsim/view) from farther as they spread.
--distance, --yaw and --pitch take the config's saved orbit camera around flapsim/view
instead, at that distance and those angles (a bag recorded before flapsim/camera existed
needs it); --size sets the window; --bare shows the 3D view only
(no panels; with rviz's --fullscreen, no menu or tool bar either), for screenshots and
movies. Other arguments (roslaunch's __name:=..., --fullscreen) go to rviz. The adjusted
config is written to a temporary file.

rviz (1.14, OGRE 1.12) now and then aborts while it creates its GL context under Xvfb
(SIGABRT right after "Forcing OpenGl version 0", once in about 30 starts here): an rviz killed
by a signal within STARTUP seconds is started again, up to RETRIES times. SIGINT and
SIGTERM are passed on to rviz; the exit status is rviz's.
"""
import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time

import rospkg
import yaml

STARTUP = 10.0  # s: an abort this soon after the start is the GL context's
RETRIES = 3


def adjusted(config, distance=None, yaw=None, pitch=None, size=None, bare=False):
    views = config["Visualization Manager"]["Views"]
    if any(v is not None for v in (distance, yaw, pitch)):
        views["Current"] = dict(next(v for v in views["Saved"] if v["Class"] == "rviz/Orbit"),
                                Name="Current View")
        for key, value in (("Distance", distance), ("Yaw", yaw), ("Pitch", pitch)):
            if value is not None:
                views["Current"][key] = value
    window = config.setdefault("Window Geometry", {})
    if size:
        window["Width"], window["Height"] = size
        window["X"], window["Y"] = 0, 0
    if bare:
        config["Panels"] = []
        window["Hide Left Dock"] = True
        window["Hide Right Dock"] = True
        window.pop("QMainWindow State", None)
    return config


def size_arg(text):
    w, h = text.lower().split("x")
    return int(w), int(h)


def main(argv):
    default = os.path.join(rospkg.RosPack().get_path("flapsim"), "config", "flapsim.rviz")
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--config", default=default)
    parser.add_argument("--distance", type=float)
    parser.add_argument("--yaw", type=float)
    parser.add_argument("--pitch", type=float)
    parser.add_argument("--size", type=size_arg, help="window size, e.g. 800x600")
    parser.add_argument("--bare", action="store_true", help="the 3D view only")
    args, rest = parser.parse_known_args(argv)
    with open(args.config) as f:
        config = yaml.safe_load(f)
    config = adjusted(config, args.distance, args.yaw, args.pitch, args.size, args.bare)
    fd, path = tempfile.mkstemp(prefix="flapsim_", suffix=".rviz")
    with os.fdopen(fd, "w") as f:
        yaml.safe_dump(config, f, default_flow_style=False)
    return run_rviz(["rviz", "-d", path] + rest)


def run_rviz(command):
    """Runs rviz, again if it dies of a signal during start-up; returns its exit status."""
    child, stopping = [None], [False]

    def forward(signum, _frame):
        stopping[0] = True
        if child[0] and child[0].poll() is None:
            child[0].send_signal(signum)

    signal.signal(signal.SIGINT, forward)
    signal.signal(signal.SIGTERM, forward)
    for attempt in range(1, RETRIES + 1):
        started = time.monotonic()
        child[0] = subprocess.Popen(command)
        code = child[0].wait()
        if (code >= 0 or stopping[0] or time.monotonic() - started > STARTUP or
                attempt == RETRIES):
            return code if code >= 0 else 128 - code
        print(f"rviz.py: rviz died of signal {-code} {time.monotonic() - started:.1f} s after "
              f"its start; starting it again ({attempt} of {RETRIES - 1})", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
