#!/usr/bin/python3
"""Starts a paused source once a listener receives it: a bag from t = 0, a replay or a
flight that rviz sees from its first frame.

start_when_listening.py --listener NODE [--topics REGEX] [--listener NODE2 --topics REGEX2 ...]
                        [--source /flapsim] [--start-service SERVICE] [--stay-paused]
                        [--timeout S]

Waits until each listener NODE is subscribed, and connected, to every topic that the source
node publishes and its REGEX matches (matched as rosbag record -e does: the whole name; the
n-th --topics goes with the n-th --listener, default /clock|/tf), then starts the source and
exits: flapsim through <source>/unpause (std_srvs/Empty), rosbag play
through <source>/pause_playback (std_srvs/SetBool false); with --start-service, by calling
that std_srvs/Empty service instead (a lockstep controller's ~start: the controller steps the
paused flapsim itself). With --stay-paused it only waits.
Exits 1 if that takes longer than the timeout (wall seconds).
"""
import argparse
import re
import sys
import time
from xmlrpc.client import ServerProxy

import rosgraph
import rospy
import rosservice
from std_srvs.srv import Empty, SetBool


def unconnected(master, source, listener, pattern):
    """Topics of `source` that `pattern` matches and `listener` does not yet receive."""
    publishers, subscribers, _ = master.getSystemState()
    topics = sorted(t for t, nodes in publishers if source in nodes and pattern.fullmatch(t))
    if not topics:
        return [f"(nothing from {source} yet)"]
    subscribed = {t for t, nodes in subscribers if listener in nodes}
    try:
        code, _, bus = ServerProxy(master.lookupNode(source)).getBusInfo(rospy.get_name())
    except Exception:  # the source is still starting up
        return topics
    connected = {c[4] for c in bus if c[1] == listener and c[2] == "o"} if code == 1 else set()
    return [t for t in topics if t not in subscribed or t not in connected]


def start(source, timeout, service=None):
    """Unpauses flapsim, or resumes rosbag play, whichever `source` is; or calls `service`
    (std_srvs/Empty) if given."""
    if service:
        rospy.wait_for_service(service, timeout=timeout)
        rospy.ServiceProxy(service, Empty)()
        return
    playback, unpause = source + "/pause_playback", source + "/unpause"
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        services = rosservice.get_service_list(node=source)
        if playback in services:
            rospy.ServiceProxy(playback, SetBool)(False)
            return
        if unpause in services:
            rospy.ServiceProxy(unpause, Empty)()
            return
        time.sleep(0.1)  # polling the master; nothing to wait on
    raise RuntimeError(f"{source} offers neither {playback} nor {unpause}")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--listener", required=True, action="append",
                        help="e.g. /record or /rviz (repeat for several)")
    parser.add_argument("--source", default="/flapsim", help="/flapsim or a rosbag play node")
    parser.add_argument("--topics", action="append", default=[],
                        help="what the listener before it must receive (default /clock|/tf)")
    parser.add_argument("--start-service",
                        help="call this std_srvs/Empty service to start (e.g. a lockstep "
                        "controller's ~start) instead of unpausing the source")
    parser.add_argument("--stay-paused", action="store_true")
    parser.add_argument("--timeout", type=float, default=120.0)
    args, _ = parser.parse_known_args(rospy.myargv(argv))
    rospy.init_node("start_when_listening", anonymous=True, disable_signals=True)
    master = rosgraph.Master(rospy.get_name())
    patterns = [re.compile(t) for t in args.topics]
    patterns += [re.compile("/clock|/tf")] * (len(args.listener) - len(patterns))
    listeners = " and ".join(args.listener)
    deadline = time.monotonic() + args.timeout
    while True:
        missing = [f"{listener}: {topic}" for listener, pattern in zip(args.listener, patterns)
                   for topic in unconnected(master, args.source, listener, pattern)]
        if not missing:
            break
        if time.monotonic() > deadline or rospy.is_shutdown():
            rospy.logerr("after %.0f s, not yet received: %s; %s stays paused", args.timeout,
                         ", ".join(missing), args.source)
            return 1
        time.sleep(0.1)  # polling the master; nothing to wait on
    if args.stay_paused:
        rospy.loginfo("%s receive %s, which stays paused", listeners, args.source)
        return 0
    start(args.source, args.timeout, args.start_service)
    rospy.loginfo("%s receive %s: started%s", listeners, args.source,
                  f" through {args.start_service}" if args.start_service else "")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
