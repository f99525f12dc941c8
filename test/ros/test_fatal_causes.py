#!/usr/bin/python3
"""Each node of the package started with a bad parameter (fatal_causes.test): it exits with
code 1 and its FATAL cause, "<node>: <cause>", is on its stderr and reaches a listener on
/rosout (this test, from the node's name) before the process ends. hover_controller used to exit 1
with nothing anywhere."""
import os
import subprocess
import threading
import unittest

import rospkg
import rospy
import rostest
from rosgraph_msgs.msg import Log

BIN = os.path.join(os.path.dirname(os.path.dirname(rospkg.RosPack().get_path("flapsim"))),
                   "build", "devel", "lib", "flapsim")

# (executable, private parameters, the cause its FATAL line must carry)
CASES = [
    ("flapsim_node", ["_step_size:=-1"], "flapsim: bad world parameters: step_size"),
    ("flapsim_worker", ["_threads:=0"], "flapsim_worker: ~threads must be in [1, 256]"),
    ("stroke_controller", ["_creature:=fu", "_pairs:=0"], "stroke_controller: "),
    ("ann_controller", ["_creature:=fu", "_rate:=0"], "ann_controller: "),
    ("hover_controller", ["_creature:=hover", "_rate:=0"], "hover_controller: "),
    ("hover_controller", ["_creature:=hover", "_altitude:=nan"], "hover_controller: "),
    ("hover_controller", ["_creature:=hover", "_height_gain:=nan"], "hover_controller: "),
    ("hover_controller", ["_creature:="], "hover_controller: parameter 'creature'"),
    ("disturbance", ["_creature:=afc", "_torque:=-0.1"], "disturbance: parameter 'torque'"),
    ("ann_controller", ["_creature:=fu", "_weights:=w", "_gyro_bias:=[0.01, 0.02]"],
     "ann_controller: parameter 'gyro_bias'"),
]


def executable(name):
    """The node's executable: this build's devel space, else the package's libexec dir."""
    for d in [BIN] + [os.path.join(p, "lib", "flapsim")
                      for p in os.environ.get("CMAKE_PREFIX_PATH", "").split(":") if p]:
        path = os.path.join(d, name)
        if os.access(path, os.X_OK):
            return path
    raise FileNotFoundError(name)


class FatalCauses(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("fatal_causes_test", anonymous=True)
        cls.logs = []
        cls.lock = threading.Condition()

        def keep(msg):
            with cls.lock:
                cls.logs.append(msg)
                cls.lock.notify_all()

        cls.sub = rospy.Subscriber("/rosout", Log, keep, queue_size=100)

    def fatal_on_rosout(self, node, text, timeout=10.0):
        """The FATAL message from `node` carrying `text` on /rosout, waited for."""
        def found():
            return [m for m in self.logs
                    if m.name == "/" + node and m.level == Log.FATAL and text in m.msg]
        with self.lock:
            self.lock.wait_for(found, timeout=timeout)
            return found()

    def test_every_node_says_its_fatal_cause_on_stderr_and_rosout(self):
        for k, (exe, params, cause) in enumerate(CASES):
            name = f"fatal_case_{k}"
            result = subprocess.run([executable(exe)] + params + [f"__name:={name}"],
                                    capture_output=True, text=True, timeout=60)
            what = f"{exe} {' '.join(params)}"
            self.assertEqual(result.returncode, 1, what + "\n" + result.stderr)
            fatal = [line for line in result.stderr.splitlines() if "[FATAL]" in line]
            self.assertEqual(len(fatal), 1, what + "\n" + result.stderr)
            self.assertIn(cause, fatal[0], what)
            cause_text = fatal[0].split("]: ", 1)[1].split("\x1b")[0]
            self.assertTrue(self.fatal_on_rosout(name, cause_text), what + ": " + cause_text)
            # The hover controller's bad values name the parameter.
            if exe == "hover_controller":
                key = params[-1].split(":=")[0].lstrip("_").split("/")[-1]
                self.assertIn(key, fatal[0], what)


if __name__ == "__main__":
    rostest.rosrun("flapsim", "fatal_causes", FatalCauses)
