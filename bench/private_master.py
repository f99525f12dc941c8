"""A ROS master of a benchmark's own (on a free port) and the processes it runs, stopped
together: bench/node_rtf.py and bench/spawn_latency.py."""
import os
import socket
import subprocess
import time


class PrivateMaster:
    """Starts roscore on a free port and points this process (and `env`) at it; `run` and
    `start` take commands against it; `stop` ends every process it started, newest first."""

    def __init__(self, log_path):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        self.env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{self.port}")
        os.environ["ROS_MASTER_URI"] = self.env["ROS_MASTER_URI"]
        self.log = open(log_path, "w")
        self.procs = [self.start(["roscore", "-p", str(self.port)])]
        for _ in range(100):  # until the master listens (at most 10 s)
            try:
                with socket.create_connection(("127.0.0.1", self.port), timeout=0.2):
                    break
            except OSError:
                time.sleep(0.1)

    def start(self, cmd):
        p = subprocess.Popen(cmd, env=self.env, stdout=self.log, stderr=self.log)
        if hasattr(self, "procs"):
            self.procs.append(p)
        return p

    def run(self, cmd):
        subprocess.run(cmd, env=self.env, check=True)

    def stop(self):
        for p in reversed(self.procs):
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
