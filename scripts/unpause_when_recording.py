#!/usr/bin/python3
"""Unpauses flapsim once a recorder listens, so that a bag starts at t = 0.

unpause_when_recording.py [--recorder /record] [--topics REGEX] [--stay-paused] [--timeout S]

Waits until the recorder node is subscribed, and connected, to every topic that flapsim
publishes and REGEX matches (as rosbag record -e matches: the whole name), then calls
flapsim/unpause (not with --stay-paused) and exits. Exits 1 if that takes longer than the
timeout (wall seconds).
"""
import argparse
import re
import sys
import time
from xmlrpc.client import ServerProxy

import rosgraph
import rospy
from std_srvs.srv import Empty

SIMULATOR = "/flapsim"


def unconnected(master, recorder, pattern):
    """Topics of flapsim that `pattern` matches and `recorder` does not yet receive."""
    publishers, subscribers, _ = master.getSystemState()
    topics = sorted(t for t, nodes in publishers if SIMULATOR in nodes and pattern.fullmatch(t))
    if not topics:
        return ["(flapsim publishes nothing yet)"]
    subscribed = {t for t, nodes in subscribers if recorder in nodes}
    try:
        code, _, bus = ServerProxy(master.lookupNode(SIMULATOR)).getBusInfo(recorder)
    except Exception:  # flapsim still starting up
        return topics
    connected = {c[4] for c in bus if c[1] == recorder and c[2] == "o"} if code == 1 else set()
    return [t for t in topics if t not in subscribed or t not in connected]


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--recorder", default="/record")
    parser.add_argument("--topics", default="/clock|/tf")
    parser.add_argument("--stay-paused", action="store_true")
    parser.add_argument("--timeout", type=float, default=120.0)
    args, _ = parser.parse_known_args(rospy.myargv(argv))
    rospy.init_node("unpause_when_recording", disable_signals=True)
    master = rosgraph.Master(rospy.get_name())
    pattern = re.compile(args.topics)
    deadline = time.monotonic() + args.timeout
    missing = unconnected(master, args.recorder, pattern)
    while missing:
        if time.monotonic() > deadline or rospy.is_shutdown():
            rospy.logerr("%s does not record %s after %.0f s: flapsim stays paused",
                         args.recorder, ", ".join(missing), args.timeout)
            return 1
        time.sleep(0.1)  # polling the master; nothing to wait on
        missing = unconnected(master, args.recorder, pattern)
    if args.stay_paused:
        rospy.loginfo("%s records flapsim; flapsim stays paused", args.recorder)
        return 0
    rospy.wait_for_service(SIMULATOR + "/unpause", timeout=args.timeout)
    rospy.ServiceProxy(SIMULATOR + "/unpause", Empty)()
    rospy.loginfo("%s records flapsim: unpaused at t = 0", args.recorder)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
