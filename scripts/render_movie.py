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
import math
import os
import shutil
import stat
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
MAX_PIXELS = 8192  # a side of --size
MAX_NUMBER = 1e6  # --speed, --rate, --duration, --distance, --timeout


def size_value(text):
    """--size: WIDTHxHEIGHT, each in [16, MAX_PIXELS]."""
    m = re.fullmatch(r"(\d{1,9})x(\d{1,9})", text)
    if not m:
        raise argparse.ArgumentTypeError(f"'{text}' is not WIDTHxHEIGHT (e.g. 640x480)")
    width, height = int(m[1]), int(m[2])
    if not (16 <= width <= MAX_PIXELS and 16 <= height <= MAX_PIXELS):
        raise argparse.ArgumentTypeError(
            f"'{text}': width and height must be in [16, {MAX_PIXELS}] pixels")
    return f"{width}x{height}"


def positive(text):
    """A finite number in (0, MAX_NUMBER]."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (math.isfinite(v) and 0 < v <= MAX_NUMBER):
        raise argparse.ArgumentTypeError(f"'{text}' is not in (0, 1e6]")
    return v


def integer(low, high):
    def value(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from None
        if not low <= v <= high:
            raise argparse.ArgumentTypeError(f"'{text}' is not in [{low}, {high}]")
        return v
    return value


def regular_file_problem(path):
    """Why `path` cannot be read as a bag (None if it can): a regular file only, opened without
    blocking and checked on the descriptor, so a FIFO or a device is refused without a read."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as e:
        return f"cannot read {path}: {e.strerror}"
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return f"{path}: not a regular file"
    finally:
        os.close(fd)
    return None


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bag")
    parser.add_argument("--attach", action="store_true",
                        help="film the running simulation of ROS_MASTER_URI")
    parser.add_argument("--port", type=integer(1, 65535),
                        help="--attach to the master at localhost:PORT")
    parser.add_argument("--duration", type=positive, help="with --attach: s of sim time to film")
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", type=size_value, default="640x480",
                        help=f"WIDTHxHEIGHT, each in [16, {MAX_PIXELS}]")
    parser.add_argument("--speed", type=positive, default=1.0,
                        help="sim seconds per movie second")
    parser.add_argument("--rate", type=positive, default=0.5, help="playback rate while filming")
    parser.add_argument("--fps", type=integer(1, 240), default=25)
    parser.add_argument("--distance", type=positive, help="orbit camera distance (m)")
    parser.add_argument("--gif", help="also an animated GIF")
    parser.add_argument("--timeout", type=positive, default=600.0, help="wall seconds at most")
    args = parser.parse_args(argv)
    if args.bag is not None:
        problem = regular_file_problem(args.bag)
        if problem:
            parser.error(f"argument --bag: {problem}")
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
