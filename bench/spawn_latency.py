#!/usr/bin/python3
"""How long flapsim_node takes to spawn creatures with many shapes per link, and how long
flapsim/get_physics waits meanwhile.

Starts its own master on a free port and the node from this build (paused, no ground), then
spawns and deletes, --runs times each, one-link creatures of 256 boxes (kMaxShapesPerLink)
laid out as: a row of touching cubes, a pile of random axis-aligned boxes that overlap, and
a pile of boxes turned at random about z (overlapping pairs near kMaxTurnedOverlaps), and a
1,000-box link (refused by the limit). A second thread calls get_physics back to back all the
while. Prints the median spawn time per layout and the longest get_physics wait; never fails
on time.

  source build/devel/setup.bash && bench/spawn_latency.py [--runs 5]
"""
import argparse
import math
import os
import random
import statistics
import sys
import tempfile
import threading
import time

import rospy
from flapsim.srv import DeleteCreature, GetPhysics, SpawnCreature
from private_master import PrivateMaster

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if os.path.basename(ROOT) == "lib":
    PREFIX = os.path.dirname(ROOT)
else:
    PREFIX = os.path.join(ROOT, "build", "devel")

INERTIAL = ('<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" '
            'iyz="0" izz="0.01"/></inertial>')


def link(boxes):
    parts = ['<robot name="pile"><link name="heap">', INERTIAL]
    for (x, y, z, yaw, a, b, c) in boxes:
        parts.append(f'<collision><origin xyz="{x} {y} {z}" rpy="0 0 {yaw}"/><geometry>'
                     f'<box size="{a} {b} {c}"/></geometry></collision>')
    parts.append("</link></robot>")
    return "".join(parts)


def layouts():
    rng = random.Random(1)
    row = [(0.02 * i, 0, 0, 0, 0.02, 0.02, 0.02) for i in range(256)]
    aligned = [(rng.uniform(0, 0.3), rng.uniform(0, 0.3), rng.uniform(0, 0.3), 0,
                rng.uniform(0.01, 0.1), rng.uniform(0.01, 0.1), rng.uniform(0.01, 0.1))
               for _ in range(256)]
    # Turned boxes spread along x so that about 200 pairs overlap (the limit is 256).
    turned = [(0.045 * i, 0, 0, rng.uniform(0, math.pi / 2), 0.05, 0.05, 0.05)
              for i in range(256)]
    big = [(0.02 * (i % 50), 0.02 * (i // 50), 0, 0, 0.02, 0.02, 0.02) for i in range(1000)]
    return [("row of 256 cubes", link(row)), ("256 aligned, overlapping", link(aligned)),
            ("256 turned, overlapping", link(turned)), ("1000 boxes (refused)", link(big))]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--devel", default=PREFIX)
    args = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="flapsim_spawn_")
    master = PrivateMaster(os.path.join(tmp, "log.txt"))
    try:
        master.run(["rosparam", "set", "/flapsim/paused", "true"])
        master.run(["rosparam", "set", "/flapsim/ground", "false"])
        master.start([os.path.join(args.devel, "lib", "flapsim", "flapsim_node")])
        rospy.init_node("spawn_latency", anonymous=True, disable_signals=True)
        rospy.wait_for_service("/flapsim/get_physics", timeout=30)
        spawn = rospy.ServiceProxy("/flapsim/spawn", SpawnCreature, persistent=True)
        delete = rospy.ServiceProxy("/flapsim/delete", DeleteCreature, persistent=True)
        physics = rospy.ServiceProxy("/flapsim/get_physics", GetPhysics, persistent=True)
        waits, stop = [], threading.Event()

        def poll():
            while not stop.is_set():
                t = time.monotonic()
                physics()
                waits.append(time.monotonic() - t)

        poller = threading.Thread(target=poll)
        poller.start()
        for name, xml in layouts():
            times, answer = [], ""
            for _ in range(args.runs):
                t = time.monotonic()
                r = spawn(name="pile", urdf_xml=xml, urdf_file="")
                times.append(time.monotonic() - t)
                answer = r.status_message
                if r.success:
                    delete(name="pile")
            print(f"{name}: median spawn call {1e3 * statistics.median(times):.1f} ms "
                  f"({args.runs} runs): {answer[:110]}", flush=True)
        stop.set()
        poller.join()
        print(f"get_physics meanwhile: {len(waits)} calls, median "
              f"{1e3 * statistics.median(waits):.2f} ms, longest {1e3 * max(waits):.1f} ms")
    finally:
        master.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
