#!/usr/bin/python3
"""Real-time factor of flapsim_node at rtf 0 (as fast as possible), publishing at 100 Hz.

Starts its own master on a free port and the node from this build, flies one creature
(the flap unit or an N-unit chain) and reads sim time from /clock twice, --seconds of wall
time apart. Then times the core (flapsim_bench --urdf) on the same creature over the same
stretch of simulated flight, and prints the ratio. With --subscribe, subscribers on /tf,
odom and joint_states keep the node publishing everything (rospy.AnyMsg: no decoding).
Prints figures; never fails on time.

  source build/devel/setup.bash && bench/node_rtf.py [--pairs 1] [--seconds 10] [--subscribe]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import rospy
from private_master import PrivateMaster
from rosgraph_msgs.msg import Clock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Where the executables are: the source tree's build/devel, or, installed as
# <prefix>/lib/flapsim/node_rtf.py, that prefix.
if os.path.basename(ROOT) == "lib":
    PREFIX = os.path.dirname(ROOT)
else:
    PREFIX = os.path.join(ROOT, "build", "devel")


def sim_time(timeout=10.0):
    return rospy.wait_for_message("/clock", Clock, timeout=timeout).clock.to_sec()


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--pairs", type=int, default=1)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--subscribe", action="store_true")
    ap.add_argument("--devel", default=PREFIX)
    args = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="flapsim_rtf_")
    urdf = os.path.join(tmp, "creature.urdf")
    subprocess.run([os.path.join(args.devel, "lib", "flapsim", "make_creature"), "--pairs",
                    str(args.pairs), "--name", "c", "-o", urdf], check=True)
    params = os.path.join(tmp, "params.yaml")
    with open(params, "w") as f:
        f.write(f"""real_time_factor: 0.0
publish_rate: 100.0
ground: false
creatures:
  - name: c
    urdf_file: {urdf}
    pose: {{xyz: [0, 0, 1000], rpy: [0, 0, 0]}}
    wing_command: {{downstroke_rate: 30, upstroke_rate: 10, amplitude: 0.8}}
""")
    print("load average at the start: %.2f %.2f %.2f" % os.getloadavg(), flush=True)
    master = PrivateMaster(os.path.join(tmp, "log.txt"))
    try:
        master.run(["rosparam", "load", params, "/flapsim"])
        master.start([os.path.join(args.devel, "lib", "flapsim", "flapsim_node")])
        rospy.init_node("node_rtf", anonymous=True, disable_signals=True)
        if args.subscribe:
            for t in ["/tf", "/c/odom", "/c/joint_states"]:
                rospy.Subscriber(t, rospy.AnyMsg, lambda m: None, queue_size=1)
        sim_time(30.0)
        time.sleep(2.0)  # connections, warm-up
        s0, w0 = sim_time(), time.monotonic()
        time.sleep(args.seconds)
        s1, w1 = sim_time(), time.monotonic()
        node_rtf = (s1 - s0) / (w1 - w0)
        print(f"flapsim_node, {args.pairs}-unit creature, rtf 0, 100 Hz publishing"
              f"{' with subscribers on /tf, odom, joint_states' if args.subscribe else ''}: "
              f"sim {s1 - s0:.2f} s in {w1 - w0:.2f} s wall -> real-time factor "
              f"{node_rtf:.1f}", flush=True)
    finally:
        master.stop()
    # The core alone, same creature, same simulated stretch [s0, s1].
    out = subprocess.run([os.path.join(args.devel, "lib", "flapsim", "flapsim_bench"), "--urdf",
                          urdf, "--height", "1000", "--no-ground", "--skip", f"{s0:.3f}",
                          "--seconds", f"{s1 - s0:.3f}", "--runs", "1"],
                         check=True, capture_output=True, text=True).stdout.strip()
    core_rtf = float(out.rsplit(" ", 1)[1])
    print(f"core on the same stretch: {out}\nnode / core = {node_rtf / core_rtf:.3f}")
    print("load average at the end: %.2f %.2f %.2f" % os.getloadavg())
    return 0


if __name__ == "__main__":
    sys.exit(main())
