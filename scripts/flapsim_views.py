"""Shared by screenshot.py, render_movie.py and the rviz tests: a private X server (Xvfb),
a roslaunch with its own master, screenshots and a count of the creatures' pixels.

Nothing here is ROS-launch specific beyond `roslaunch`; it needs Xvfb, ImageMagick's
`import`, ffmpeg and python3-pil (scripts/install_deps.sh).
"""
import colorsys
import contextlib
import os
import signal
import socket
import subprocess
import tempfile
import time

import rosgraph
import rospy
from PIL import Image
from rosgraph_msgs.msg import Clock

# Colours of rviz's background (48, 48, 48) and grid are grey; the creatures' materials
# (wings and plates 0.95 0.8 0.3, bodies 0.25 0.3 0.45) are not, nor are the force arrows
# (1 0.5 0, hue 30 degrees). Saturation is relative: a wing lit edge-on is a dark olive
# such as (49, 41, 15), within 40 levels of grey but as saturated as a lit one.
SATURATION = 0.35  # (max - min) / max of r, g, b above which a pixel is coloured
DARKEST = 24  # max of r, g, b (0..255) below which a pixel counts as black
ARROW_HUES = (20.0, 38.0)  # degrees: the orange of the force arrows


def pixel_counts(png):
    """(creature pixels, arrow pixels) of an image: coloured pixels, split by hue."""
    creature = arrows = 0
    with Image.open(png) as im:
        for (r, g, b), n in _colours(im.convert("RGB")):
            brightest = max(r, g, b)
            if brightest < DARKEST or brightest - min(r, g, b) <= SATURATION * brightest:
                continue
            hue = 360.0 * colorsys.rgb_to_hsv(r / 255, g / 255, b / 255)[0]
            if ARROW_HUES[0] <= hue <= ARROW_HUES[1]:
                arrows += n
            else:
                creature += n
    return creature, arrows


def _colours(im):
    colours = im.getcolors(maxcolors=im.width * im.height)
    return [(c, n) for n, c in colours]


def wait_for(predicate, timeout, what, poll=0.05):
    """Polls `predicate` until it holds; raises TimeoutError after `timeout` wall seconds."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise TimeoutError(f"timed out after {timeout:.0f} s waiting for {what}")
        time.sleep(poll)


@contextlib.contextmanager
def xvfb(width, height):
    """A private X server of width x height; yields its DISPLAY (":N")."""
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_fd), "-screen", "0", f"{width}x{height}x24",
         "-nolisten", "tcp", "-nocursor"],
        pass_fds=(write_fd,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_fd)
    try:
        with os.fdopen(read_fd) as f:
            number = f.readline().strip()
        if not number:
            raise RuntimeError("Xvfb did not start")
        yield f":{number}"
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def roslaunch(args, display, log_path):
    """roslaunch flapsim ARGS with a master of its own on a free port and DISPLAY set.
    Yields the environment (ROS_MASTER_URI) for the caller's ROS clients; the caller's own
    process must use that master too (see use_master)."""
    port = free_port()
    env = dict(os.environ, DISPLAY=display, ROS_MASTER_URI=f"http://localhost:{port}")
    with open(log_path, "w") as log:
        proc = subprocess.Popen(["roslaunch", "-p", str(port), "flapsim"] + list(args), env=env,
                                stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        yield proc, env
    finally:
        stop(proc)


def stop(proc):
    """Interrupts a process group started with start_new_session (SIGKILL after 30 s)."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


@contextlib.contextmanager
def rviz_attached(master_uri, display, log_path, rviz_args):
    """rviz (scripts/rviz.py with `rviz_args`) on `display`, a node of the running master at
    `master_uri` under a name of its own (not /rviz: a user's rviz keeps running); yields
    (its process, its node name, the environment)."""
    name = f"/flapsim_view_{os.getpid()}"
    env = dict(os.environ, DISPLAY=display, ROS_MASTER_URI=master_uri)
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "rviz.py")
    with open(log_path, "w") as log:
        proc = subprocess.Popen(["/usr/bin/python3", script] + rviz_args.split() +
                                [f"__name:={name[1:]}"], env=env, stdout=log,
                                stderr=subprocess.STDOUT, start_new_session=True)
    try:
        yield proc, name, env
    finally:
        stop(proc)


def master_uri(port):
    """The master to attach to: localhost:`port`, or ROS_MASTER_URI without a port."""
    if port:
        return f"http://localhost:{port}"
    uri = os.environ.get("ROS_MASTER_URI")
    if not uri:
        raise RuntimeError("--attach needs ROS_MASTER_URI (or --port)")
    return uri


def join(env, node, what="the ROS master"):
    """Makes this process a node `node` (anonymous) of the master of `env` once it is up, and
    follows its /clock; returns a one-element list that holds the latest sim time (-1 before
    the first)."""
    use_master(env)
    wait_for(rosgraph.is_master_online, 30, what)
    rospy.init_node(node, anonymous=True, disable_signals=True)
    latest = [-1.0]
    rospy.Subscriber("/clock", Clock, lambda m: latest.__setitem__(0, m.clock.to_sec()))
    return latest


def use_master(env):
    """Points this process's rospy at the master of `env` (before rospy.init_node)."""
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]


def screenshot(display, path):
    subprocess.run(["import", "-display", display, "-window", "root", path], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return path


def shoot_until_drawn(display, path, min_pixels, timeout, settle=15.0):
    """Takes screenshots until one shows at least `min_pixels` creature pixels (rviz has drawn
    the creatures), then, of a still scene, until two in a row are the same (a busy rviz has
    caught up with what it was sent; at most `settle` s more); returns the last one's
    (creature, arrow) pixel counts. On timeout the last shot is kept at `path` and
    TimeoutError raised with its counts."""
    counts = [(0, 0)]

    def drawn():
        counts[0] = pixel_counts(screenshot(display, path))
        return counts[0][0] >= min_pixels

    try:
        wait_for(drawn, timeout, "rviz to draw the creatures", poll=0.2)
    except TimeoutError as e:
        raise TimeoutError(f"{e}; last screenshot {path} has {counts[0][0]} creature and "
                           f"{counts[0][1]} arrow pixels") from None
    if settle <= 0:
        return counts[0]
    last = [_pixels(path)]

    def settled():
        screenshot(display, path)
        now, last[0] = _pixels(path), last[0]
        same, last[0] = now == last[0], now
        return same

    try:
        wait_for(settled, settle, "rviz to settle", poll=0.3)
    except TimeoutError:
        pass  # a scene that moves (a replay still playing) never settles: the last shot
    return pixel_counts(path)


def _pixels(png):
    with Image.open(png) as im:
        return im.convert("RGB").tobytes()


def rviz_args(width, height, bare_args=False, config=None):
    """rviz.py arguments for a bare, full-screen 3D view (no panels, menus or cursor), of
    `config` (default: the package's): as a launch argument, or (bare_args) as they are."""
    args = f"--bare --size {width}x{height} --fullscreen"
    if config:
        args += f" --config {os.path.abspath(config)}"
    return args if bare_args else f"rviz_args:={args}"


def temp_dir(prefix):
    return tempfile.mkdtemp(prefix=prefix)
