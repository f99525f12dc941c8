#!/usr/bin/python3
"""What a user sees, checked on screenshots: rviz under a private Xvfb, through the scripts a
user runs (scripts/screenshot.py, scripts/render_movie.py). An empty grid has no coloured
pixels; the creatures (yellow wings, blue bodies) and the force arrows (orange) do.

Run by `run_tests` (CMakeLists.txt); screenshots and logs stay in --out-dir.
"""
import argparse
import os
import re
import subprocess
import sys
import unittest

import rosbag
import rosgraph
import rospkg
import rospy
import yaml
from rosgraph_msgs.msg import Clock

PKG = rospkg.RosPack().get_path("flapsim")
SCRIPTS = os.path.join(PKG, "scripts")
sys.path.insert(0, SCRIPTS)
import flapsim_views as views  # noqa: E402
import start_when_listening as starter  # noqa: E402

OUT = os.path.join(os.environ.get("ROS_HOME", os.path.expanduser("~/.ros")), "flapsim_views")
MIN_CREATURE = 300  # pixels of 800 x 600: a flap unit at 2.5 m covers a few thousand
TIMEOUT = 180


def run(script, *args):
    """Runs a script of the package; returns its stdout (raises on failure, with its output)."""
    result = subprocess.run(["/usr/bin/python3", os.path.join(SCRIPTS, script)] + list(args),
                            capture_output=True, text=True, timeout=TIMEOUT)
    if result.returncode != 0:
        raise AssertionError(f"{script} failed ({result.returncode}):\n{result.stdout}\n"
                             f"{result.stderr[-3000:]}")
    return result.stdout


def shot_time(stdout):
    return float(re.search(r"t = ([0-9.]+) s", stdout).group(1))


class Views(unittest.TestCase):
    bag = None

    @classmethod
    def setUpClass(cls):
        os.makedirs(OUT, exist_ok=True)

    @classmethod
    def flight_bag(cls):
        """A 6.5 s flap-unit flight recorded with record:=true, at twice real time: at rtf 0
        a recorder still opening its bag falls behind, and flapsim's publishers drop what it
        has not read (seen here once in 11 runs: the bag started at 1.59 s)."""
        if cls.bag:
            return cls.bag
        bag = os.path.join(OUT, "flap_unit.bag")
        if os.path.exists(bag):
            os.remove(bag)
        # screenshot.py's flight, with the recorder: the shot ends the run at t = 6.5 (the
        # open-loop unit tips over after about 7 s)
        run("screenshot.py", "--out", os.path.join(OUT, "recording.png"), "--at", "6.5",
            "--size", "320x240", "flap_unit.launch", "record:=true", f"bag:={bag}", "rtf:=2",
            "record_topics:=/rosout")
        cls.bag = bag
        return bag

    def test_flap_unit_at_6s_has_the_creature_in_frame(self):
        png = os.path.join(OUT, "flap_unit_6s.png")
        out = run("screenshot.py", "--out", png, "--at", "6", "flap_unit.launch", "rtf:=2")
        self.assertGreaterEqual(shot_time(out), 6.0)
        creature, arrows = views.pixel_counts(png)
        self.assertGreaterEqual(creature, MIN_CREATURE, f"{png}: the creature is not in view")

    def test_recorded_bag_starts_at_t0_with_what_a_replay_needs_and_the_flights_data(self):
        with rosbag.Bag(self.flight_bag()) as bag:
            first_clock = next(m for _, m, _ in bag.read_messages(topics=["/clock"])).clock
            topics = bag.get_type_and_topic_info().topics
        self.assertEqual(first_clock.to_nsec(), 0)
        for topic in ("/tf", "/tf_static", "/flapsim/creature_markers", "/flapsim/aero_markers",
                      "/flapsim/view_markers", "/flap_unit/robot_description",
                      "/flap_unit/imu", "/flapsim/creature_states", "/diagnostics",
                      "/rosout"):  # the last one asked for with record_topics
            self.assertIn(topic, topics)
        self.assertEqual(topics["/flap_unit/robot_description"].message_count, 1)

    def test_replayed_bag_at_6s_has_the_creature_in_frame(self):
        png = os.path.join(OUT, "replay_6s.png")
        out = run("screenshot.py", "--out", png, "--at", "6", "--bag", self.flight_bag(),
                  "rate:=2")
        self.assertGreaterEqual(shot_time(out), 6.0)
        creature, _ = views.pixel_counts(png)
        self.assertGreaterEqual(creature, MIN_CREATURE, f"{png}: the replay shows no creature")

    def test_movie_of_the_bag_shows_the_creature_in_every_sampled_frame(self):
        movie = os.path.join(OUT, "flap_unit.mp4")
        rate = 2.0
        out = run("render_movie.py", "--bag", self.flight_bag(), "--out", movie, "--size",
                  "480x360", "--rate", str(rate), "--fps", "10")
        # the film's seconds after the playback started and before rviz drew the creature
        cut = float(re.search(r"([0-9.]+) s of it after the playback started", out).group(1))
        duration = float(subprocess.run(
            ["ffprobe", "-v", "error", "-show_entries", "format=duration", "-of", "csv=p=0",
             movie], check=True, capture_output=True, text=True).stdout)
        # The movie (speed 1) runs from rviz's first drawn frame to the end of the 6.5 s
        # flight: with the flight seconds cut before that frame (`cut` wall seconds of the
        # replay at `rate`), about 6.5 s, or longer: filming runs in wall time, and on a busy
        # machine the replay falls behind its rate (no upper bound: it would test load). The
        # playback starts once ffmpeg films (before that, up to 2.4 s of the flight were lost
        # to its start-up); how soon rviz draws is load, but most of the flight is in it.
        self.assertGreater(duration + cut * rate, 5.5)
        self.assertLess(cut * rate, 3.0, "rviz drew the creature only halfway through")
        for i, t in enumerate((0.0, duration / 2, duration - 0.5)):
            png = os.path.join(OUT, f"movie_frame_{i}.png")
            subprocess.run(["ffmpeg", "-loglevel", "error", "-y", "-ss", f"{t:.2f}", "-i", movie,
                            "-frames:v", "1", png], check=True)
            creature, _ = views.pixel_counts(png)
            self.assertGreaterEqual(creature, MIN_CREATURE * 480 * 360 // (800 * 600),
                                    f"{png} (t = {t:.2f} s): no creature")

    def test_flock_of_4_is_drawn_from_markers_without_per_creature_displays(self):
        with open(os.path.join(PKG, "config", "flapsim.rviz")) as f:
            config = yaml.safe_load(f)
        displays = config["Visualization Manager"]["Displays"]
        # no display names a creature, so none can show an error for a missing one
        self.assertEqual(sorted(d["Class"] for d in displays),
                         ["rviz/Grid"] + ["rviz/MarkerArray"] * 3)
        png = os.path.join(OUT, "flock_4.png")
        summary = os.path.join(OUT, "flock_4.yaml")
        run("screenshot.py", "--out", png, "--summary", summary, "--at", "1", "flock.launch",
            "count:=4")
        with open(summary) as f:
            markers = yaml.safe_load(f)
        self.assertEqual(sorted(markers["namespaces"]), ["afc0", "afc1", "afc2", "afc3"])
        self.assertEqual(markers["frames_without_tf"], [])
        self.assertEqual(markers["per_namespace"], {f"afc{i}": 3 for i in range(4)})
        self.assertEqual(markers["roots_out_of_view"], [])
        creature, _ = views.pixel_counts(png)
        self.assertGreaterEqual(creature, 4 * 100, f"{png}: fewer creature pixels than 4 units")

    def test_a_lockstep_flock_of_8_is_filmed_aloft_and_in_view_at_exactly_its_time(self):
        """lockstep:=true: the controller steps the paused simulator, so screenshot.py must not
        unpause it (it did: the world then ran between the controller's steps on stale commands
        and at 30 s every member lay on the ground). The launch starts the controller once rviz
        receives flapsim, and lockstep_duration:=T (which screenshot.py passes) stops it at T,
        so the shot is of exactly T. Every member has climbed from 1 m to about 29 m by then
        (afc_1_weights.yaml climbs at about 0.93 m/s); lying on the ground they were at 0.03 m.
        In lockstep the flight does not depend on the machine's load (at rtf 2 without it, a
        member whose controller fell behind could lie on the ground); 14 s of wall time."""
        png = os.path.join(OUT, "flock_8_lockstep.png")
        summary = os.path.join(OUT, "flock_8_lockstep.yaml")
        out = run("screenshot.py", "--out", png, "--summary", summary, "--at", "30",
                  "flock.launch", "count:=8", "lockstep:=true", "rtf:=0")
        self.assertAlmostEqual(shot_time(out), 30.0, places=6)
        with open(summary) as f:
            markers = yaml.safe_load(f)
        # by 30 s the flock has spread over several metres and climbed: the camera (frame
        # flapsim/camera) has drawn back to keep every member in view
        self.assertEqual(len(markers["namespaces"]), 8)
        self.assertEqual(markers["roots_out_of_view"], [])
        creature, _ = views.pixel_counts(png)
        self.assertGreaterEqual(creature, 100, f"{png}: the flock is not drawn")
        heights = markers["root_heights"]
        self.assertEqual(sorted(heights), [f"afc{i}/unit0_body" for i in range(8)])
        for frame, z in heights.items():
            self.assertGreater(z, 25.0, f"{frame} at {z} m at 30 s")

    def test_robot_model_display_with_tf_prefix_draws_a_chain(self):
        """rviz's RobotModel display (config/robot_model_afc.rviz: afc/robot_description, TF
        prefix afc; no creature markers) draws the 4-unit chain from the tf tree."""
        png = os.path.join(OUT, "robot_model_afc_4.png")
        out = run("screenshot.py", "--out", png, "--at", "1", "--rviz-config",
                  os.path.join(PKG, "config", "robot_model_afc.rviz"), "afc.launch", "pairs:=4")
        self.assertGreaterEqual(shot_time(out), 1.0)
        creature, _ = views.pixel_counts(png)
        self.assertGreaterEqual(creature, 4 * MIN_CREATURE, f"{png}: the chain is not drawn")

    def test_attach_films_a_simulation_already_running(self):
        """screenshot.py and render_movie.py --port: a flight started on its own (a master of
        its own, no rviz) is filmed by an rviz they start on it, which they leave running."""
        png = os.path.join(OUT, "attached.png")
        movie = os.path.join(OUT, "attached.mp4")
        with views.roslaunch(["flap_unit.launch"], "", os.path.join(OUT, "attached_sim.log")) \
                as (proc, env):
            port = env["ROS_MASTER_URI"].rsplit(":", 1)[1]
            out = run("screenshot.py", "--out", png, "--port", port, "--at", "1",
                      "--size", "320x240")
            self.assertGreaterEqual(shot_time(out), 1.0)
            creature, _ = views.pixel_counts(png)
            self.assertGreaterEqual(creature, MIN_CREATURE * 320 * 240 // (800 * 600), png)
            out = run("render_movie.py", "--port", port, "--duration", "1", "--out", movie,
                      "--size", "320x240", "--fps", "10")
            self.assertIsNone(proc.poll(), "the simulation did not survive the filming")
        frames = int(re.search(r": (\d+) frames", out).group(1))
        # 1 s of sim time at speed 1 and 10 fps, less what was cut before rviz drew
        self.assertGreaterEqual(frames, 5, out)
        self.assertLessEqual(frames, 11, out)

    def test_a_scenario_with_rviz_starts_once_rviz_receives_it(self):
        """glide.launch rviz:=true (about 1 s of flight): flapsim waits, paused at t = 0, until
        rviz receives its topics; when sim time first passes 0, rviz already does."""
        pattern = re.compile(r"/clock|/tf|/flapsim/(aero|creature|view)_markers")
        with views.xvfb(320, 240) as display:
            with views.roslaunch(["glide.launch", "rviz:=true", views.rviz_args(320, 240)],
                                 display, os.path.join(OUT, "glide_waits.log")) as (proc, env):
                views.use_master(env)
                views.wait_for(rosgraph.is_master_online, 30, "the ROS master")
                rospy.init_node("test_rviz_waits", anonymous=True, disable_signals=True)
                master = rosgraph.Master(rospy.get_name())
                started = []  # rviz's missing topics when sim time first passed 0

                def on_clock(msg):
                    if msg.clock.to_sec() > 0 and not started:
                        started.append(starter.unconnected(master, "/flapsim", "/rviz", pattern))

                rospy.Subscriber("/clock", Clock, on_clock)
                views.wait_for(lambda: started, TIMEOUT, "sim time to pass 0")
                rospy.signal_shutdown("done")
        self.assertEqual(started[0], [], "flapsim ran before rviz received these")


def main():
    global OUT
    parser = argparse.ArgumentParser()
    parser.add_argument("--out-dir", default=OUT)
    args, rest = parser.parse_known_args()
    OUT = os.path.abspath(args.out_dir)
    import rosunit
    rosunit.unitrun("flapsim", "views", Views, sysargs=[sys.argv[0]] + rest)


if __name__ == "__main__":
    main()
