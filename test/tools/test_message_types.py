#!/usr/bin/python3
"""Every message and service type doc/ros_interface.md names loads in Python from the devel
space, as `rostopic echo` and `rosservice call` load it (`rostopic echo /diagnostics` said
"Cannot load message class for [diagnostic_msgs/DiagnosticArray]": the install step lacked
python3-diagnostic-msgs). Argument: the devel prefix. With --gtest_output=xml:FILE also writes a
gtest-style result for catkin_test_results.
"""
import os
import re
import subprocess
import sys
import unittest

from gtest_xml import run_unittests

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DEVEL = sys.argv[1]
CHECK = """
import sys, roslib.message
bad = [t for t in sys.argv[1:] if (roslib.message.get_message_class(t)
       or roslib.message.get_service_class(t)) is None]
print(' '.join(bad))
"""


def documented_types():
    """The package/Type names in the Type column of doc/ros_interface.md's tables."""
    types = set()
    with open(os.path.join(ROOT, "doc", "ros_interface.md")) as f:
        for line in f:
            cells = line.split("|")
            if len(cells) > 3 and line.startswith("| `"):
                types.update(re.findall(r"\b([a-z][a-z0-9_]{2,}/[A-Z][A-Za-z0-9]*)\b", cells[2]))
    return sorted(types)


class MessageTypes(unittest.TestCase):
    def test_every_documented_type_loads_in_python(self):
        types = documented_types()
        for expected in ("diagnostic_msgs/DiagnosticArray", "nav_msgs/Odometry",
                         "flapsim/MotorPower", "flapsim/SetPhysics", "tf2_msgs/TFMessage"):
            self.assertIn(expected, types)  # the table was read
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("ROS_", "CMAKE_PREFIX", "PYTHONPATH", "LD_LIBRARY_PATH"))}
        cmd = (f"source '{os.path.join(DEVEL, 'setup.bash')}' && /usr/bin/python3 -c \"$0\" "
               + " ".join(types))
        r = subprocess.run(["bash", "-c", cmd, CHECK], capture_output=True, text=True,
                           timeout=120, env=env)
        self.assertEqual(r.returncode, 0, r.stderr[-500:])
        self.assertEqual(r.stdout.split(), [], f"these do not load: {r.stdout}")


if __name__ == "__main__":
    run_unittests(sys.argv, "message_types", "EveryDocumentedTypeLoads")
