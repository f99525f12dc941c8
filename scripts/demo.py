#!/usr/bin/python3
"""Runs the default scenario headless and leaves its outputs in one folder.

roslaunch flapsim flap_unit.launch (paused, as fast as possible, recording), unpauses once
the recorder listens, stops after --duration seconds of sim time, then turns the bag into a
CSV of the root trajectory, a PNG of its height, a movie of the flight as rviz shows it
(MP4, scripts/render_movie.py) and an animated GIF of it, and prints a summary.

Needs the package on ROS_PACKAGE_PATH (source build/devel/setup.bash).
"""
import argparse
import csv
import os
import signal
import subprocess
import sys
import time
from xmlrpc.client import ServerProxy

import rosbag
import rosgraph
import rospy
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

CREATURE = "flap_unit"
TOPICS = ["/clock", "/tf", f"/{CREATURE}/joint_states", f"/{CREATURE}/odom",
          f"/{CREATURE}/wing_command"]


def wait_for(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.05)
    raise RuntimeError(f"timed out after {timeout} s waiting for {what}")


def recorder_listening(master):
    """True once rosbag record is connected to a publisher of every topic it records."""
    publishers, _, _ = master.getSystemState()
    pubs = {topic: nodes for topic, nodes in publishers}
    for topic in TOPICS:
        connected = False
        for node in pubs.get(topic, []):
            try:
                code, _, bus = ServerProxy(master.lookupNode(node)).getBusInfo("/flapsim_demo")
            except Exception:  # a node still starting up
                continue
            connected = connected or (code == 1 and any(
                c[4] == topic and "record" in c[1] for c in bus))
        if not connected:
            return False
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", default="out/demo", help="output folder")
    parser.add_argument("--duration", type=float, default=6.0,
                        help="sim seconds to fly (open loop, the unit tips over after about 7 s)")
    parser.add_argument("--timeout", type=float, default=120.0, help="wall seconds at most")
    parser.add_argument("--rtf", type=float, default=5.0, help="real-time factor of the run")
    parser.add_argument("--no-movie", action="store_true", help="skip the MP4 and GIF")
    args = parser.parse_args()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    bag_path = os.path.join(out, f"{CREATURE}.bag")
    if os.path.exists(bag_path):
        os.remove(bag_path)

    launch = subprocess.Popen(
        ["roslaunch", "--screen", "flapsim", "flap_unit.launch",
         "record:=true", f"bag:={bag_path}", f"rtf:={args.rtf}", "paused:=true"],
        stdout=open(os.path.join(out, "roslaunch.log"), "w"), stderr=subprocess.STDOUT,
        start_new_session=True)
    wall_start = time.monotonic()
    try:
        master = rosgraph.Master("/flapsim_demo")
        wait_for(lambda: rosgraph.is_master_online(), 30, "the ROS master")
        rospy.init_node("flapsim_demo", anonymous=True, disable_signals=True)
        wait_for(lambda: recorder_listening(master), 60, "rosbag record to subscribe")
        rospy.wait_for_service("/flapsim/unpause", timeout=30)
        latest = [0.0]
        rospy.Subscriber("/clock", Clock, lambda m: latest.__setitem__(0, m.clock.to_sec()))
        fly_start = time.monotonic()
        rospy.ServiceProxy("/flapsim/unpause", Empty)()
        wait_for(lambda: latest[0] >= args.duration, args.timeout, f"{args.duration} s of sim time")
        rospy.ServiceProxy("/flapsim/pause", Empty)()
        fly_wall = time.monotonic() - fly_start
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)
    if launch.returncode not in (0, -signal.SIGINT, 1, 2):
        print(f"demo: roslaunch ended with {launch.returncode}, see {out}/roslaunch.log")

    # Bag -> CSV of the root link's odometry.
    csv_path = os.path.join(out, f"{CREATURE}.csv")
    rows = []
    counts = {}
    with rosbag.Bag(bag_path) as bag:
        info = bag.get_type_and_topic_info().topics
        counts = {t: info[t].message_count for t in info}
        stroke = next((m for _, m, _ in bag.read_messages(topics=[f"/{CREATURE}/wing_command"])),
                      None)
        for _, msg, _ in bag.read_messages(topics=[f"/{CREATURE}/odom"]):
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            v = msg.twist.twist.linear
            rows.append([msg.header.stamp.to_sec(), p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z])
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz"])
        w.writerows(rows)

    png_path = os.path.join(out, f"{CREATURE}.png")
    title = "flap unit"
    if stroke is not None and stroke.downstroke_rate:
        title += (f", w1 = {stroke.downstroke_rate[0]:g}, w2 = {stroke.upstroke_rate[0]:g} rad/s, "
                  f"amplitude {stroke.amplitude[0]:g} rad")
    plot = (f"set datafile separator ','; set terminal pngcairo size 800,500; "
            f"set output '{png_path}'; set grid; set key off; "
            f"set title '{title}'; "
            f"set xlabel 'sim time (s)'; set ylabel 'height of the body (m)'; "
            f"plot '{csv_path}' skip 1 using 1:4 with lines lw 2")
    plotted = subprocess.run(["gnuplot", "-e", plot]).returncode == 0

    if not rows:
        print("demo: no odometry recorded", file=sys.stderr)
        return 1
    movie_path, gif_path = os.path.join(out, f"{CREATURE}.mp4"), os.path.join(out, f"{CREATURE}.gif")
    movie = "skipped (--no-movie)"
    if not args.no_movie:
        # a process of its own: rospy initialises one node per process
        rendered = subprocess.run(
            ["/usr/bin/python3", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                              "render_movie.py"),
             "--bag", bag_path, "--out", movie_path, "--gif", gif_path],
            capture_output=True, text=True)
        movie = (rendered.stdout.strip().replace("\n", "; ") if rendered.returncode == 0
                 else f"failed: {rendered.stderr.strip()[-500:]}")
    z0, z1 = rows[0][3], rows[-1][3]
    print(f"flapsim demo: {CREATURE} flapped {rows[-1][0]:.2f} s of sim time in {fly_wall:.2f} s "
          f"wall (real-time factor {rows[-1][0] / fly_wall:.1f}, whole run {time.monotonic() - wall_start:.1f} s)")
    print(f"  height {z0:.3f} m -> {z1:.3f} m (gained {z1 - z0:+.3f} m), "
          f"max {max(r[3] for r in rows):.3f} m, drift x {rows[-1][1]:+.4f} m y {rows[-1][2]:+.4f} m")
    print(f"  bag  {bag_path}: " + ", ".join(f"{t} ({n})" for t, n in sorted(counts.items())))
    print(f"  csv  {csv_path} ({len(rows)} rows)")
    print(f"  plot {png_path}" + ("" if plotted else " (gnuplot failed)"))
    print(f"  movie {movie}")
    missing = [t for t in TOPICS if counts.get(t, 0) == 0]
    if missing:
        print(f"demo: nothing recorded on {missing}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
