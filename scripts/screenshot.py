#!/usr/bin/python3
"""Takes an rviz screenshot of a scenario at a sim time, headless.

screenshot.py --out FILE.png --at T [--size 800x600] LAUNCH [launch args ...]
screenshot.py --out FILE.png --at T [--size 800x600] --bag FILE.bag [replay.launch args ...]
e.g. screenshot.py --out doc/flap_unit.png --at 3 flap_unit.launch

Starts a private X server and `roslaunch flapsim LAUNCH rviz:=true paused:=true` with a bare,
full-screen rviz; starts the flight once rviz receives flapsim's topics (so it sees t = 0),
pauses flapsim at sim time T, and saves the first screenshot in which rviz has drawn the
creatures. --summary FILE also writes (YAML) what rviz was given to draw: the creatures'
marker namespaces, markers per creature, and marker frames that /tf never carried. With --bag, replays the bag instead (launch/replay.launch, which starts
playback once rviz listens) and pauses the playback at T. Prints the sim time and the creature and force-arrow pixel counts. Needs the
package on ROS_PACKAGE_PATH (source build/devel/setup.bash).
"""
import argparse
import os
import re
import sys

import rosgraph
import rospy
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty, SetBool
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray
import yaml

import flapsim_views as views
import start_when_listening as starter

TOPICS = "/clock|/tf|/flapsim/(aero|creature)_markers"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True)
    parser.add_argument("--at", type=float, required=True, help="sim time of the screenshot (s)")
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--min-pixels", type=int, default=50,
                        help="creature pixels that count as drawn")
    parser.add_argument("--timeout", type=float, default=120.0, help="wall seconds at most")
    parser.add_argument("--bag", help="replay this bag instead of running a scenario")
    parser.add_argument("--summary", help="YAML file: the creature markers rviz was given")
    parser.add_argument("launch", nargs=argparse.REMAINDER, help="launch file and its args")
    args = parser.parse_args(argv)
    if args.bag:
        t, counts = shoot_replay(args.bag, args.out, args.at, args.size, args.min_pixels,
                                 args.timeout, args.launch)
    else:
        t, counts = shoot(args.launch, args.out, args.at, args.size, args.min_pixels,
                          args.timeout, summary=args.summary)
    print(f"{args.out}: t = {t:.2f} s, {counts[0]} creature pixels, {counts[1]} arrow pixels")
    return 0


# One screenshot per process: rospy initialises its node once.
def shoot(launch, out, at, size="800x600", min_pixels=50, timeout=120.0, log=None,
          summary=None):
    """Runs the scenario to sim time `at` and saves a screenshot; returns (t, pixel counts)."""
    width, height = (int(v) for v in size.split("x"))
    out = os.path.abspath(out)
    log = log or os.path.splitext(out)[0] + ".log"
    with views.xvfb(width, height) as display:
        with views.roslaunch(list(launch) + ["rviz:=true", "paused:=true",
                                             views.rviz_args(width, height)],
                             display, log) as (proc, env):
            views.use_master(env)
            views.wait_for(rosgraph.is_master_online, 30, "the ROS master")
            rospy.init_node("flapsim_screenshot", anonymous=True, disable_signals=True)
            latest = [-1.0]
            rospy.Subscriber("/clock", Clock, lambda m: latest.__setitem__(0, m.clock.to_sec()))
            seen = Seen()
            master = rosgraph.Master(rospy.get_name())
            pattern = re.compile(TOPICS)
            # rviz, and with record:=true the recorder too, before the flight starts
            listeners = ["/rviz"] + (["/record"] if "record:=true" in launch else [])
            views.wait_for(lambda: not any(starter.unconnected(master, "/flapsim", n, pattern)
                                           for n in listeners),
                           timeout, f"{' and '.join(listeners)} to receive flapsim's topics",
                           poll=0.1)
            rospy.wait_for_service("/flapsim/unpause", timeout=timeout)
            rospy.ServiceProxy("/flapsim/unpause", Empty)()
            views.wait_for(lambda: latest[0] >= at, timeout, f"sim time {at} s")
            rospy.ServiceProxy("/flapsim/pause", Empty)()
            t = latest[0]
            counts = views.shoot_until_drawn(display, out, min_pixels, 30.0)
            if summary:
                with open(summary, "w") as f:
                    yaml.safe_dump(seen.summary(), f)
            rospy.signal_shutdown("done")
            return t, counts


class Seen:
    """The creature markers rviz is given, and the frames /tf carries."""

    def __init__(self):
        self.markers = []
        self.frames = set()
        rospy.Subscriber("/flapsim/creature_markers", MarkerArray, self.on_markers)
        rospy.Subscriber("/tf", TFMessage, self.on_tf)

    def on_markers(self, msg):
        self.markers = [m for m in msg.markers if m.action == Marker.ADD]

    def on_tf(self, msg):
        self.frames.update(t.child_frame_id for t in msg.transforms)

    def summary(self):
        per_namespace = {}
        for m in self.markers:
            per_namespace[m.ns] = per_namespace.get(m.ns, 0) + 1
        return {"namespaces": sorted(per_namespace), "per_namespace": per_namespace,
                "frames_without_tf": sorted({m.header.frame_id for m in self.markers} -
                                            self.frames)}


def shoot_replay(bag, out, at, size="800x600", min_pixels=50, timeout=120.0, launch_args=(),
                 log=None):
    """Replays `bag` into rviz, pauses the playback at sim time `at` and saves a screenshot;
    returns (t, pixel counts)."""
    width, height = (int(v) for v in size.split("x"))
    out = os.path.abspath(out)
    log = log or os.path.splitext(out)[0] + ".log"
    with views.xvfb(width, height) as display:
        # --keep-alive: the player stays after the bag's end, so that a shot near the end can
        # still pause it (on a busy machine the end may come before the pause).
        with views.roslaunch(["replay.launch", f"bag:={os.path.abspath(bag)}",
                              "play_args:=--keep-alive"] + list(launch_args) +
                             [views.rviz_args(width, height)],
                             display, log) as (proc, env):
            views.use_master(env)
            views.wait_for(rosgraph.is_master_online, 30, "the ROS master")
            rospy.init_node("flapsim_screenshot", anonymous=True, disable_signals=True)
            latest = [-1.0]
            rospy.Subscriber("/clock", Clock, lambda m: latest.__setitem__(0, m.clock.to_sec()))
            rospy.wait_for_service("/play/pause_playback", timeout=timeout)
            pause = rospy.ServiceProxy("/play/pause_playback", SetBool)
            views.wait_for(lambda: latest[0] >= at, timeout, f"sim time {at} s in the replay")
            pause(True)
            t = latest[0]
            counts = views.shoot_until_drawn(display, out, min_pixels, 30.0)
            rospy.signal_shutdown("done")
            return t, counts


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
