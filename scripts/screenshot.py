#!/usr/bin/python3
"""Takes an rviz screenshot of a scenario at a sim time, headless.

screenshot.py --out FILE.png --at T [--size 800x600] LAUNCH [launch args ...]
e.g. screenshot.py --out doc/flap_unit.png --at 3 flap_unit.launch

Starts a private X server and `roslaunch flapsim LAUNCH rviz:=true paused:=true` with a bare,
full-screen rviz; starts the flight once rviz receives flapsim's topics (so it sees t = 0),
pauses flapsim at sim time T, and saves the first screenshot in which rviz has drawn the
creatures. Prints the sim time and the creature and force-arrow pixel counts. Needs the
package on ROS_PACKAGE_PATH (source build/devel/setup.bash).
"""
import argparse
import os
import sys

import flapsim_views as views

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
    parser.add_argument("launch", nargs=argparse.REMAINDER, help="launch file and its args")
    args = parser.parse_args(argv)
    t, counts = shoot(args.launch, args.out, args.at, args.size, args.min_pixels, args.timeout)
    print(f"{args.out}: t = {t:.2f} s, {counts[0]} creature pixels, {counts[1]} arrow pixels")
    return 0


def shoot(launch, out, at, size="800x600", min_pixels=50, timeout=120.0, log=None):
    """Runs the scenario to sim time `at` and saves a screenshot; returns (t, pixel counts)."""
    width, height = (int(v) for v in size.split("x"))
    out = os.path.abspath(out)
    log = log or os.path.splitext(out)[0] + ".log"
    with views.xvfb(width, height) as display:
        with views.roslaunch(list(launch) + ["rviz:=true", "paused:=true",
                                             views.rviz_args(width, height)],
                             display, log) as (proc, env):
            views.use_master(env)
            import rospy
            from rosgraph_msgs.msg import Clock
            from std_srvs.srv import Empty
            import start_when_listening as starter

            views.wait_for(lambda: _master_up(), 30, "the ROS master")
            rospy.init_node("flapsim_screenshot", anonymous=True, disable_signals=True)
            latest = [-1.0]
            rospy.Subscriber("/clock", Clock, lambda m: latest.__setitem__(0, m.clock.to_sec()))
            import rosgraph
            master = rosgraph.Master(rospy.get_name())
            import re
            pattern = re.compile(TOPICS)
            views.wait_for(lambda: not starter.unconnected(master, "/flapsim", "/rviz", pattern),
                           timeout, "rviz to receive flapsim's topics", poll=0.1)
            rospy.wait_for_service("/flapsim/unpause", timeout=timeout)
            rospy.ServiceProxy("/flapsim/unpause", Empty)()
            views.wait_for(lambda: latest[0] >= at, timeout, f"sim time {at} s")
            rospy.ServiceProxy("/flapsim/pause", Empty)()
            t = latest[0]
            counts = views.shoot_until_drawn(display, out, min_pixels, 30.0)
            rospy.signal_shutdown("done")
            return t, counts


def _master_up():
    import rosgraph
    return rosgraph.is_master_online()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
