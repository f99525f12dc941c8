#!/usr/bin/python3
"""Renders a bag of a flight (record:=true) into a movie with rviz, headless.

render_movie.py --bag FILE.bag --out FILE.mp4 [--size 640x480] [--speed 1] [--rate 0.5]
                [--fps 25] [--distance D] [--gif FILE.gif]
render_movie.py --attach [--port N] --duration S --out FILE.mp4 [--size 640x480] [--speed 1]
                [--fps 25] [--distance D] [--gif FILE.gif]

Plays the bag (launch/replay.launch) into a bare, full-screen rviz on a private X server
without a cursor, following the creatures (frame flapsim/view), and films the screen with
ffmpeg: the playback starts, from t = 0, once rviz receives it and ffmpeg has its first
frames. The bag plays at --rate (sim seconds per wall second: below 1
when rviz cannot draw in real time) and the movie shows the flight at --speed; frames
before rviz first draws a creature are cut. --gif also writes an animated GIF (6 frames per
second, 320 pixels wide). The camera is the recorded frame flapsim/camera; --distance D
orbits the creatures' centroid at D m instead (for a bag recorded without it). Needs the
package on ROS_PACKAGE_PATH.

With --attach, films a simulation that is already running (the master of ROS_MASTER_URI, or
of localhost:N with --port N) for --duration s of sim time from when its own rviz (a node of
its own name, on a private X server) has drawn it: the movie shows that stretch at --speed,
whatever real-time factor it ran at. It neither pauses nor unpauses the simulation.
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

import re

import rosbag
import rosgraph
import rospy
from std_srvs.srv import SetBool

import flapsim_views as views
import start_when_listening as starter

TOPICS = "/clock|/tf|/flapsim/(aero|creature|view)_markers"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bag")
    parser.add_argument("--attach", action="store_true",
                        help="film the running simulation of ROS_MASTER_URI")
    parser.add_argument("--port", type=int, help="--attach to the master at localhost:PORT")
    parser.add_argument("--duration", type=float, help="with --attach: s of sim time to film")
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", default="640x480")
    parser.add_argument("--speed", type=float, default=1.0, help="sim seconds per movie second")
    parser.add_argument("--rate", type=float, default=0.5, help="playback rate while filming")
    parser.add_argument("--fps", type=int, default=25)
    parser.add_argument("--distance", type=float, help="orbit camera distance (m)")
    parser.add_argument("--gif", help="also an animated GIF")
    parser.add_argument("--timeout", type=float, default=600.0, help="wall seconds at most")
    args = parser.parse_args(argv)
    if args.attach or args.port:
        if not args.duration or args.duration <= 0:
            parser.error("--attach needs --duration (s of sim time)")
        frames, cut, lead = render_attached(views.master_uri(args.port), args.out,
                                            args.duration, args.size, args.speed, args.fps,
                                            args.distance, args.timeout)
    elif not args.bag:
        parser.error("give --bag, or --attach")
    else:
        frames, cut, lead = render(args.bag, args.out, args.size, args.speed, args.rate,
                                   args.fps, args.distance, args.timeout)
    print(f"{args.out}: {frames} frames at {args.fps} fps ({args.speed}x), "
          f"{cut:.2f} s cut before the first drawn frame, {max(0.0, cut - lead):.2f} s of it "
          f"after the playback started")
    if args.gif:
        gif(args.out, args.gif)
        print(f"{args.gif}: {os.path.getsize(args.gif) // 1024} KiB")
    return 0


def bag_end(bag_path):
    with rosbag.Bag(bag_path) as bag:
        last = 0.0
        for _, msg, _ in bag.read_messages(topics=["/clock"]):
            last = msg.clock.to_sec()
        return last


def render(bag, out, size="640x480", speed=1.0, rate=0.5, fps=25, distance=None, timeout=600.0):
    """Films the replayed bag; returns (frames in the movie, seconds cut at the start, of which
    the first filmed before the playback started)."""
    width, height = (int(v) for v in size.split("x"))
    bag, out = os.path.abspath(bag), os.path.abspath(out)
    end = bag_end(bag)
    work = views.temp_dir("flapsim_movie_")
    raw = os.path.join(work, "raw.mkv")
    try:
        with views.xvfb(width, height) as display:
            with views.roslaunch(["replay.launch", f"bag:={bag}", f"rate:={rate}",
                                  f"distance:={distance or ''}", "start:=false",
                                  views.rviz_args(width, height)],
                                 display, os.path.join(work, "roslaunch.log")) as (proc, env):
                latest = views.join(env, "flapsim_movie")
                # The playback waits, paused, until rviz receives it and ffmpeg films: no
                # second of the flight is lost to ffmpeg's start-up.
                master = rosgraph.Master(rospy.get_name())
                pattern = re.compile(TOPICS)
                views.wait_for(lambda: not starter.unconnected(master, "/play", "/rviz", pattern),
                               min(timeout, 150.0), "rviz to receive the replay")
                progress = os.path.join(work, "progress.txt")
                ffmpeg = start_filming(display, raw, progress, fps, width, height)
                try:
                    rospy.wait_for_service("/play/pause_playback", timeout=30)
                    lead = filmed(progress) / fps  # s of film before the playback
                    rospy.ServiceProxy("/play/pause_playback", SetBool)(False)
                    views.wait_for(lambda: latest[0] >= end - 0.01 or proc.poll() is not None,
                                   timeout, "the replay to end", poll=0.1)
                finally:
                    ffmpeg.communicate(b"q", timeout=60)
                rospy.signal_shutdown("done")
        cut = first_drawn(raw, fps, work)
        encode(raw, out, cut, rate / speed, fps)  # movie seconds per wall second of filming
        return frame_count(out), cut, lead
    finally:
        shutil.rmtree(work, ignore_errors=True)


def start_filming(display, raw, progress, fps, width, height):
    """ffmpeg filming `display` into `raw`, once it has its first frames."""
    ffmpeg = subprocess.Popen(
        ["ffmpeg", "-loglevel", "error", "-y", "-progress", progress,
         "-stats_period", "0.1", "-f", "x11grab", "-draw_mouse", "0",
         "-framerate", str(fps), "-video_size", f"{width}x{height}", "-i", display,
         "-c:v", "libx264", "-preset", "ultrafast", "-qp", "0", raw],
        stdin=subprocess.PIPE)
    try:
        views.wait_for(lambda: filmed(progress) > 0, 30, "ffmpeg's first frames")
    except TimeoutError:
        ffmpeg.kill()
        ffmpeg.wait()
        raise
    return ffmpeg


def encode(raw, out, cut, stretch, fps, length=None):
    """The film from `cut` s on (for `length` s, or to its end), its wall seconds stretched by
    `stretch` into movie seconds."""
    until = ["-t", f"{length:.3f}"] if length else []
    subprocess.run(
        ["ffmpeg", "-loglevel", "error", "-y", "-ss", f"{cut:.3f}"] + until + ["-i", raw,
         "-vf", f"setpts={stretch:.6f}*(PTS-STARTPTS)", "-r", str(fps),
         "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "23", out], check=True)


def render_attached(uri, out, duration, size="640x480", speed=1.0, fps=25, distance=None,
                    timeout=600.0):
    """Films `duration` s of sim time of the running simulation of master `uri`; returns
    (frames in the movie, seconds cut at the start, of which the first filmed before it)."""
    width, height = (int(v) for v in size.split("x"))
    out = os.path.abspath(out)
    work = views.temp_dir("flapsim_movie_")
    raw = os.path.join(work, "raw.mkv")
    rviz_args = views.rviz_args(width, height, bare_args=True)
    if distance:
        rviz_args += f" --distance {distance}"
    try:
        with views.xvfb(width, height) as display:
            with views.rviz_attached(uri, display, os.path.join(work, "rviz.log"),
                                     rviz_args) as (_, name, env):
                latest = views.join(env, "flapsim_movie", f"the ROS master at {uri}")
                master = rosgraph.Master(rospy.get_name())
                pattern = re.compile(TOPICS)
                views.wait_for(lambda: not starter.unconnected(master, "/flapsim", name, pattern),
                               min(timeout, 150.0), f"rviz to receive flapsim from {uri}")
                views.wait_for(lambda: latest[0] >= 0, 30, "/clock")
                progress = os.path.join(work, "progress.txt")
                ffmpeg = start_filming(display, raw, progress, fps, width, height)
                try:
                    lead = filmed(progress) / fps  # s of film before the stretch
                    begin = (latest[0], time.monotonic())
                    views.wait_for(lambda: latest[0] >= begin[0] + duration, timeout,
                                   f"{duration} s of sim time", poll=0.05)
                    end = (latest[0], time.monotonic())
                finally:
                    ffmpeg.communicate(b"q", timeout=60)
                rospy.signal_shutdown("done")
        cut = max(lead, first_drawn(raw, fps, work))
        rate = (end[0] - begin[0]) / (end[1] - begin[1])  # sim s per wall s while filming
        encode(raw, out, cut, rate / speed, fps, length=end[1] - begin[1] - (cut - lead))
        return frame_count(out), cut, lead
    finally:
        shutil.rmtree(work, ignore_errors=True)


def filmed(progress):
    """Frames ffmpeg has filmed so far, from its -progress file (0 before the first)."""
    try:
        with open(progress) as f:
            counts = re.findall(r"^frame=(\d+)", f.read(), re.M)
    except FileNotFoundError:
        return 0
    return int(counts[-1]) if counts else 0


def first_drawn(video, fps, work, min_pixels=50):
    """Seconds into `video` of the first frame with creature pixels (0 if none)."""
    frames = os.path.join(work, "head")
    os.makedirs(frames)
    subprocess.run(["ffmpeg", "-loglevel", "error", "-t", "20", "-i", video,
                    os.path.join(frames, "%05d.png")], check=True)
    for i, name in enumerate(sorted(os.listdir(frames))):
        if views.pixel_counts(os.path.join(frames, name))[0] >= min_pixels:
            return i / fps
    return 0.0


def frame_count(video):
    result = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
         "-show_entries", "stream=nb_read_frames", "-of", "csv=p=0", video],
        check=True, capture_output=True, text=True)
    return int(result.stdout.strip())


def gif(video, out, fps=6, width=320):
    subprocess.run(
        ["ffmpeg", "-loglevel", "error", "-y", "-i", video, "-vf",
         f"fps={fps},scale={width}:-1:flags=lanczos,split[a][b];[a]palettegen=max_colors=32[p];"
         f"[b][p]paletteuse=dither=bayer", out], check=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
