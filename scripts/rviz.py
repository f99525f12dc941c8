#!/usr/bin/python3
"""Starts rviz with flapsim's config, adjusted for one scenario or for a recording.

rviz.py [--config FILE] [--distance D] [--yaw Y] [--pitch P] [--size WxH] [--bare] [rviz args]

--distance, --yaw and --pitch set the orbit camera around the frame flapsim/view (the
smoothed centroid of the creatures); --size sets the window; --bare shows the 3D view only
(no panels; with rviz's --fullscreen, no menu or tool bar either), for screenshots and
movies. Other arguments (roslaunch's __name:=..., --fullscreen) go to rviz. The adjusted
config is written to a temporary file.
"""
import argparse
import os
import sys
import tempfile

import rospkg
import yaml


def adjusted(config, distance=None, yaw=None, pitch=None, size=None, bare=False):
    view = config["Visualization Manager"]["Views"]["Current"]
    for key, value in (("Distance", distance), ("Yaw", yaw), ("Pitch", pitch)):
        if value is not None:
            view[key] = value
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
    os.execvp("rviz", ["rviz", "-d", path] + rest)


if __name__ == "__main__":
    main(sys.argv[1:])
