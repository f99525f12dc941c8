#!/usr/bin/python3
"""Takes an rviz screenshot of a scenario at a sim time, headless.

screenshot.py --out FILE.png --at T [--size 800x600] LAUNCH [launch args ...]
screenshot.py --out FILE.png --at T [--size 800x600] --bag FILE.bag [replay.launch args ...]
screenshot.py --out FILE.png [--at T] [--size 800x600] --attach [--port N]
(each also with --rviz-config FILE: an rviz config of your own)
e.g. screenshot.py --out doc/flap_unit.png --at 3 flap_unit.launch

Starts a private X server and `roslaunch flapsim LAUNCH rviz:=true paused:=true` with a bare,
full-screen rviz; starts the flight once rviz receives flapsim's topics (so it sees t = 0),
pauses flapsim at sim time T, and saves the first screenshot in which rviz has drawn the
creatures. --summary FILE also writes (YAML) what rviz was given to draw: the creatures'
marker namespaces, markers per creature, marker frames that /tf never carried, and the
creature roots outside the camera's view (of frame flapsim/camera), and the height of each
creature root. With lockstep:=true among the launch arguments the controller steps the
simulator itself: the launch starts it once rviz receives flapsim, and the script passes
lockstep_duration:=T (unless given), so that the controller stops and flapsim stays paused at
T. With --bag, replays the bag instead (launch/replay.launch, which starts
playback once rviz listens) and pauses the playback at T. Prints the sim time and the creature and force-arrow pixel counts. Needs the
package on ROS_PACKAGE_PATH (source build/devel/setup.bash).

With --attach, films a simulation that is already running (the master of ROS_MASTER_URI, or
of localhost:N with --port N): starts only a bare rviz on a private X server, under a node name
of its own, and takes the first drawn screenshot once sim time reaches T (default: now); it
neither pauses nor unpauses the simulation.
"""
import argparse
import math
import os
import re
import sys

import rosgraph
import rospy
from std_srvs.srv import Empty, SetBool
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray
import yaml

import flapsim_views as views
import start_when_listening as starter

TOPICS = "/clock|/tf|/flapsim/(aero|creature|view)_markers"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True)
    parser.add_argument("--at", type=float, help="sim time of the screenshot (s)")
    parser.add_argument("--attach", action="store_true",
                        help="film the running simulation of ROS_MASTER_URI")
    parser.add_argument("--port", type=int, help="--attach to the master at localhost:PORT")
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--min-pixels", type=int, default=50,
                        help="creature pixels that count as drawn")
    parser.add_argument("--timeout", type=float, default=120.0, help="wall seconds at most")
    parser.add_argument("--bag", help="replay this bag instead of running a scenario")
    parser.add_argument("--summary", help="YAML file: the creature markers rviz was given")
    parser.add_argument("--rviz-config", help="an rviz config of your own")
    parser.add_argument("launch", nargs=argparse.REMAINDER, help="launch file and its args")
    args = parser.parse_args(argv)
    if args.attach or args.port:
        t, counts = shoot_attached(views.master_uri(args.port), args.out, args.at or 0.0,
                                   args.size, args.min_pixels, args.timeout, args.summary,
                                   args.rviz_config)
    elif args.at is None:
        parser.error("--at is needed (but with --attach)")
    elif args.bag:
        t, counts = shoot_replay(args.bag, args.out, args.at, args.size, args.min_pixels,
                                 args.timeout, args.launch, config=args.rviz_config)
    else:
        t, counts = shoot(args.launch, args.out, args.at, args.size, args.min_pixels,
                          args.timeout, summary=args.summary, config=args.rviz_config)
    print(f"{args.out}: t = {t:.2f} s, {counts[0]} creature pixels, {counts[1]} arrow pixels")
    return 0


# One screenshot per process: rospy initialises its node once.
def shoot(launch, out, at, size="800x600", min_pixels=50, timeout=120.0, log=None,
          summary=None, config=None):
    """Runs the scenario to sim time `at` and saves a screenshot; returns (t, pixel counts)."""
    width, height = (int(v) for v in size.split("x"))
    out = os.path.abspath(out)
    log = log or os.path.splitext(out)[0] + ".log"
    # lockstep:=true: the controller steps the paused simulator through flapsim/step; the
    # launch starts it once rviz receives flapsim and it flies `at` s (lockstep_duration), so
    # flapsim stays paused there. Unpausing it instead would run the world between the
    # controller's steps on stale commands (a flock filmed that way lay on the ground at 30 s).
    lockstep = "lockstep:=true" in launch
    extra = ["paused:=true"]
    if lockstep:
        extra = [] if any(a.startswith("lockstep_duration:=") for a in launch) else [
            f"lockstep_duration:={at}"]
    with views.xvfb(width, height) as display:
        with views.roslaunch(list(launch) + ["rviz:=true"] + extra +
                             [views.rviz_args(width, height, config=config)],
                             display, log) as (proc, env):
            latest = views.join(env, "flapsim_screenshot")
            seen = Seen(width / height)
            master = rosgraph.Master(rospy.get_name())
            pattern = re.compile(TOPICS if not config else "/clock|/tf")  # a config's own
            # rviz, and with record:=true the recorder too, before the flight starts
            listeners = ["/rviz"] + (["/record"] if "record:=true" in launch else [])
            views.wait_for(lambda: not any(starter.unconnected(master, "/flapsim", n, pattern)
                                           for n in listeners),
                           timeout, f"{' and '.join(listeners)} to receive flapsim's topics",
                           poll=0.1)
            if not lockstep:
                rospy.wait_for_service("/flapsim/unpause", timeout=timeout)
                rospy.ServiceProxy("/flapsim/unpause", Empty)()
            views.wait_for(lambda: latest[0] >= at, timeout, f"sim time {at} s")
            if not lockstep:
                rospy.ServiceProxy("/flapsim/pause", Empty)()
            t = latest[0]
            counts = views.shoot_until_drawn(display, out, min_pixels, 30.0)
            if summary:
                with open(summary, "w") as f:
                    yaml.safe_dump(seen.summary(), f)
            rospy.signal_shutdown("done")
            return t, counts


def shoot_attached(uri, out, at, size="800x600", min_pixels=50, timeout=120.0, summary=None,
                   config=None):
    """Starts an rviz of its own on the running simulation of master `uri`, and saves a
    screenshot once sim time reaches `at`; returns (t, pixel counts)."""
    width, height = (int(v) for v in size.split("x"))
    out = os.path.abspath(out)
    with views.xvfb(width, height) as display:
        with views.rviz_attached(uri, display, os.path.splitext(out)[0] + ".log",
                                 views.rviz_args(width, height, True, config)) as (_, name, env):
            latest = views.join(env, "flapsim_screenshot", f"the ROS master at {uri}")
            seen = Seen(width / height)
            master = rosgraph.Master(rospy.get_name())
            pattern = re.compile(TOPICS if not config else "/clock|/tf")  # a config's own
            missing = []

            def received():
                missing[:] = starter.unconnected(master, "/flapsim", name, pattern)
                return not missing

            try:
                views.wait_for(received, timeout, f"{name} to receive flapsim's topics", 0.1)
            except TimeoutError as e:
                raise TimeoutError(f"{e} from {uri}; not yet: {', '.join(missing)}") from None
            views.wait_for(lambda: latest[0] >= at, timeout, f"sim time {at} s")
            counts = views.shoot_until_drawn(display, out, min_pixels, 30.0, settle=0.0)
            t = latest[0]  # about what rviz drew (it goes on)
            if summary:
                with open(summary, "w") as f:
                    yaml.safe_dump(seen.summary(), f)
            rospy.signal_shutdown("done")
            return t, counts


class Seen:
    """The creature markers rviz is given, the frames /tf carries, and where the camera
    (frame flapsim/camera) sees each creature's root."""

    def __init__(self, aspect):
        self.aspect = aspect
        self.markers = []
        self.frames = set()
        self.in_world = {}  # latest transform of each frame whose parent is the world
        rospy.Subscriber("/flapsim/creature_markers", MarkerArray, self.on_markers)
        rospy.Subscriber("/tf", TFMessage, self.on_tf)
        rospy.Subscriber("/tf_static", TFMessage, self.on_tf)

    def on_markers(self, msg):
        self.markers = [m for m in msg.markers if m.action == Marker.ADD]

    def on_tf(self, msg):
        self.frames.update(t.child_frame_id for t in msg.transforms)
        for t in msg.transforms:
            if t.header.frame_id == "world":
                self.in_world[t.child_frame_id] = t.transform

    def out_of_view(self):
        """Creature roots outside the camera's view (rviz's 45 degree vertical field of view
        and the window's aspect), if the camera frame is known."""
        camera = self.in_world.get("flapsim/camera")
        if camera is None:
            return None
        half_up = math.tan(0.785398 / 2)
        outside = []
        for frame, t in sorted(self.in_world.items()):
            if frame.startswith("flapsim/"):
                continue
            r = [t.translation.x - camera.translation.x, t.translation.y - camera.translation.y,
                 t.translation.z - camera.translation.z]
            ahead, left, up = rotate_back(camera.rotation, r)
            if ahead <= 0 or abs(up) > half_up * ahead or abs(left) > self.aspect * half_up * ahead:
                outside.append(frame)
        return outside

    def summary(self):
        per_namespace = {}
        for m in self.markers:
            per_namespace[m.ns] = per_namespace.get(m.ns, 0) + 1
        return {"namespaces": sorted(per_namespace), "per_namespace": per_namespace,
                "frames_without_tf": sorted({m.header.frame_id for m in self.markers} -
                                            self.frames),
                "roots_out_of_view": self.out_of_view(),
                "root_heights": {frame: round(t.translation.z, 3)
                                 for frame, t in sorted(self.in_world.items())
                                 if not frame.startswith("flapsim/")}}


def rotate_back(q, v):
    """v rotated by the inverse of the unit quaternion q (a geometry_msgs Quaternion)."""
    x, y, z, w = -q.x, -q.y, -q.z, q.w
    # v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    c = [y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]]
    cc = [y * c[2] - z * c[1], z * c[0] - x * c[2], x * c[1] - y * c[0]]
    return [v[i] + 2 * w * c[i] + 2 * cc[i] for i in range(3)]


def shoot_replay(bag, out, at, size="800x600", min_pixels=50, timeout=120.0, launch_args=(),
                 log=None, config=None):
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
                             [views.rviz_args(width, height, config=config)],
                             display, log) as (proc, env):
            latest = views.join(env, "flapsim_screenshot")
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
