#!/usr/bin/python3
"""A flapsim_worker (one thread) under the reliability campaign's calls (issue 27): after
each hostile call, a normal one (one robust-preset episode of 20 s) is timed, and the
worker's resident memory (VmRSS) and peak (VmHWM) are read from /proc. The campaign is sent
three times. On a master of its own; prints figures, never passes or fails.

  source build/devel/setup.bash && /usr/bin/python3 bench/worker_campaign.py [build/devel/lib/flapsim]
"""
import os
import random
import re
import subprocess
import sys
import tempfile
import time

BIN = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "build", "devel", "lib", "flapsim")
PORT = 20000 + random.randrange(20000)
os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % PORT
os.environ["ROS_HOME"] = tempfile.mkdtemp()

import rospy  # noqa: E402 (after ROS_MASTER_URI)
from flapsim.srv import EvaluateEpisodes, EvaluateEpisodesRequest  # noqa: E402

SERVICE = "/flapsim_farm/w/evaluate_episodes"
ROBUST = ["--preset", "robust"]


# The robust preset's weight count, learnt from the worker's refusal of a wrong one in main()
# ("1 weights, the controller has N"), so the campaign follows the network's size.
WEIGHTS = [None]


def request(spec, tasks=1, weight_count=None, episode=0, weights=None):
    weight_count = weight_count if weight_count is not None else WEIGHTS[0]
    return EvaluateEpisodesRequest(
        spec=spec, weight_count=weight_count,
        weights=weights if weights is not None else [0.1] * (weight_count * tasks),
        episodes=[episode] * tasks)


def campaign():
    return [
        ("1: --episodes 10000000", request(ROBUST + ["--episodes", "10000000"], episode=-1)),
        # 1e7 weights in all, as many tasks as that makes of the network's size.
        (f"2: {10**7 // WEIGHTS[0]:,} tasks (1e7 weights)",
         request(ROBUST, tasks=10**7 // WEIGHTS[0])),
        ("2: --step-sizes 0.000001", request(ROBUST + ["--step-sizes", "0.000001"])),
        ("2: --duration 4.3e7", request(ROBUST + ["--duration", "4.3e7"])),
        ("2: --pairs 3000", request(ROBUST + ["--pairs", "3000"])),
        ("2: 1024 tasks of 20 s", request(ROBUST, tasks=1024)),
        ("5: --duration 1e9", request(ROBUST + ["--duration", "1e9"])),
        ("a 16 MiB argument", request(["--preset", "r" * (16 << 20)])),
        ("NaN weights", request(ROBUST, weights=[float("nan")] * WEIGHTS[0])),
    ]


def memory_kb(pid):
    fields = {}
    with open("/proc/%d/status" % pid) as status:
        for line in status:
            key, _, value = line.partition(":")
            fields[key] = value.strip()
    return int(fields["VmRSS"].split()[0]), int(fields["VmHWM"].split()[0])


def main():
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(PORT)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = subprocess.Popen([os.path.join(BIN, "flapsim_worker"), "__ns:=/flapsim_farm",
                               "__name:=w", "_threads:=1"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        rospy.init_node("worker_campaign", anonymous=True, disable_signals=True)
        rospy.wait_for_service(SERVICE, timeout=30)
        call = rospy.ServiceProxy(SERVICE, EvaluateEpisodes)
        refusal = call(request(ROBUST, weight_count=1)).message
        found = re.search(r"the controller has (\d+)", refusal)
        if not found:
            sys.exit("worker_campaign: no weight count in the worker's refusal: " + refusal)
        WEIGHTS[0] = int(found.group(1))
        normal = request(ROBUST)
        call(normal)  # the runner of the normal spec is built once
        rss, hwm = memory_kb(worker.pid)
        print("load average at the start: %.2f %.2f %.2f" % os.getloadavg())
        print("worker at start: VmRSS %.1f MB, VmHWM %.1f MB" % (rss / 1024, hwm / 1024))
        print("%-32s %9s %10s %9s %9s  %s" % ("call", "answered", "normal s", "RSS MB",
                                              "peak MB", "message"))
        worst = 0.0
        for round_ in range(3):
            calls = campaign()
            for name, req in calls:
                t = time.monotonic()
                res = call(req)
                hostile = time.monotonic() - t
                t = time.monotonic()
                ok = call(normal)
                normal_s = time.monotonic() - t
                worst = max(worst, normal_s)
                rss, hwm = memory_kb(worker.pid)
                if round_ == 0 or name == calls[-1][0]:
                    print("%-32s %7.3f s %10.3f %9.1f %9.1f  %s" % (
                        name, hostile, normal_s, rss / 1024, hwm / 1024,
                        (res.message or "success")[:160]))
                assert ok.success, ok.message
            print("after round %d: VmRSS %.1f MB, VmHWM %.1f MB" % (round_ + 1, rss / 1024,
                                                                   hwm / 1024))
        print("slowest normal call: %.3f s" % worst)
        print("load average at the end: %.2f %.2f %.2f" % os.getloadavg())
    finally:
        rospy.signal_shutdown("done")
        worker.terminate()
        worker.wait()
        master.terminate()
        master.wait()


if __name__ == "__main__":
    main()
