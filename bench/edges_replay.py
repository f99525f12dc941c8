#!/usr/bin/python3
"""The edges campaign of doc/reliability.md, replayed: starts `roslaunch flapsim
empty_world.launch paused:=true` on a master of its own, makes the campaign's files in a
directory of its own (pile1000.urdf: one link of 1,000 boxes; sphere.urdf: a second collision
`<sphere/>` without a radius; twice.yaml: `roll_gain` twice; misspelt.yaml: `heigth_gain`;
fifo: a FIFO; config/afc_1_weights.yaml: a copy of the package's), runs each command there
and prints what it answered: for each, `$ command`, its output (colours and ROS log stamps
and this run's directory taken out), `exit N` (or `still running after S s`, then stopped), and `answer: ` the line
that answers (a service's status_message, argparse's error, else the first line of a usage
error's output, else the last line). The nodes' private parameters are deleted after each
command. Stops everything it started. Never passes or fails on the answers.

  source build/devel/setup.bash && bench/edges_replay.py
"""
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STAMP = re.compile(r"\x1b\[[0-9;]*m|(?<=\]) \[[0-9.]+\](?=:)")

# The campaign: each command as it is shown (run with `rosrun flapsim` before the tools').
COMMANDS = [
    "spawn_creature -file pile1000.urdf -model pile",
    "spawn_creature -file sphere.urdf -model dropped",
    "hover_controller _creature:=hover _rate:=0",
    "hover_controller _creature:=hover _gains_file:=twice.yaml",
    "hover_controller _creature:=hover _gains_file:=misspelt.yaml",
    "flight_check --hover --gains misspelt.yaml",
    "ann_controller _creature:=fu _weights:=config/afc_1_weights.yaml _rate:=1e-9",
    "spawn_creature -file fifo -model f -timeout 2",
    "spawn_creature -file fifo -model f -timeout 0",
    "evolve --out ''",
    "evolve --step-sizes 0.001,0.0005,",
    "evolve --seed 1 --seed 2",
    "render_movie.py --size abc",
    "rosservice call /flapsim/get_state '{name: fu, reference_frame: \"fu/\"}'",
    "rosservice call /flapsim/get_state '{name: fu, reference_frame: \"fu::\"}'",
]


def write_files(here):
    boxes = "".join(
        f'<collision><origin xyz="{0.01 * (i % 10)} {0.01 * (i // 10 % 10)} {0.01 * (i // 100)}"/>'
        '<geometry><box size="0.02 0.02 0.02"/></geometry></collision>' for i in range(1000))
    inertial = ('<inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" '
                'iyz="0" izz="1e-4"/></inertial>')
    with open(os.path.join(here, "pile1000.urdf"), "w") as f:
        f.write(f'<robot name="pile"><link name="heap">{inertial}{boxes}</link></robot>\n')
    with open(os.path.join(here, "sphere.urdf"), "w") as f:
        f.write(f'<robot name="dropped"><link name="wing">{inertial}<collision><geometry><box '
                'size="0.1 0.1 0.01"/></geometry></collision><collision><geometry><sphere/>'
                '</geometry></collision></link></robot>\n')
    with open(os.path.join(here, "twice.yaml"), "w") as f:
        f.write("roll_gain: 1.0\nroll_gain: 2.0\n")
    with open(os.path.join(here, "misspelt.yaml"), "w") as f:
        f.write("heigth_gain: 1.0\n")
    os.mkfifo(os.path.join(here, "fifo"))
    os.makedirs(os.path.join(here, "config"))
    shutil.copy(os.path.join(ROOT, "config", "afc_1_weights.yaml"),
                os.path.join(here, "config", "afc_1_weights.yaml"))
    shutil.copy(os.path.join(ROOT, "urdf", "flap_unit.urdf"), os.path.join(here, "fu.urdf"))


def run(command, here, env, seconds=30):
    """Runs `command` (a tool of the package, or rosservice) in `here`; its cleaned output
    lines and how it ended."""
    argv = shlex.split(command)
    if argv[0] != "rosservice":
        argv = ["rosrun", "flapsim"] + argv
    p = subprocess.Popen(argv, cwd=here, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=seconds)
        ended = f"exit {p.returncode}"
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGINT)
        try:
            out, _ = p.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            out, _ = p.communicate()
        ended = f"still running after {seconds} s"
    # The files by their names: the directory is this run's own.
    lines = [STAMP.sub("", line).rstrip().replace(here + os.sep, "") for line in out.split("\n")]
    for node in ("/hover_controller", "/ann_controller"):
        subprocess.run(["rosparam", "delete", node], env=env, capture_output=True)
    return [line for line in lines if line.strip()], ended


def answer(lines, ended):
    """The line of `lines` that answers (see the module's doc)."""
    for i, line in enumerate(lines):
        if line.strip().startswith("status_message:"):
            text = line.split(":", 1)[1].strip()
            for more in lines[i + 1:]:
                text = text.rstrip("\\") + more.strip().lstrip("\\")
            return text.strip('"')
    for line in lines:
        if ": error: " in line:
            return line.strip()
    if ended == "exit 2" and lines:
        return lines[0].strip()
    return lines[-1].strip() if lines else "(nothing)"


def main():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    here = tempfile.mkdtemp(prefix="edges_replay")
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}",
               ROS_HOME=os.path.join(here, "ros"))
    write_files(here)
    launch = subprocess.Popen(["roslaunch", "-p", str(port), "flapsim", "empty_world.launch",
                               "paused:=true"], cwd=here, env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        for _ in range(600):  # the simulator's spawn service, at most 60 s
            found = subprocess.run(["rosservice", "list"], env=env, capture_output=True,
                                   text=True).stdout
            if "/flapsim/spawn" in found.split():
                break
            time.sleep(0.1)
        else:
            sys.exit("edges_replay.py: empty_world.launch did not offer /flapsim/spawn in 60 s")
        lines, ended = run("spawn_creature -file fu.urdf -model fu", here, env)
        if ended != "exit 0":
            sys.exit("edges_replay.py: could not spawn fu: " + " / ".join(lines))
        for command in COMMANDS:
            lines, ended = run(command, here, env)
            print("$ " + command)
            for line in lines[-8:]:
                print("  " + line)
            print(ended)
            print("answer: " + answer(lines, ended), flush=True)
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)
            launch.wait()
        shutil.rmtree(here, ignore_errors=True)


if __name__ == "__main__":
    main()
