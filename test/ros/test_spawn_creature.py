#!/usr/bin/python3
"""rosrun flapsim spawn_creature against empty_world.launch (spawn_creature.test): gazebo_ros
spawn_model's flags, a relative -file read where the tool runs (outside the simulator's
urdf_roots), -param, -string, -J; refusals named; and the flapsim/spawn service refusing a
file outside urdf_roots (a launch argument) with the roots named."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rospkg
import rospy
import rostest
from flapsim.srv import GetState, SpawnCreature

PKG = rospkg.RosPack().get_path("flapsim")
TOOL = os.path.join(PKG, "scripts", "spawn_creature")


def run(*args, cwd=None, stdin=None):
    result = subprocess.run(["/usr/bin/python3", TOOL] + list(args), cwd=cwd, input=stdin,
                            capture_output=True, text=True, timeout=60)
    return result.returncode, result.stdout, result.stderr


def product(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rotation(roll, pitch, yaw):
    """URDF's rpy: Rz(yaw) Ry(pitch) Rx(roll), as a matrix."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    rx = [[1, 0, 0], [0, cr, -sr], [0, sr, cr]]
    ry = [[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]
    rz = [[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]
    return product(rz, product(ry, rx))


def matrix(q):
    x, y, z, w = q.x, q.y, q.z, q.w
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def largest_difference(a, b):
    return max(abs(a[i][j] - b[i][j]) for i in range(3) for j in range(3))


class SpawnCreatureTool(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_spawn_creature", anonymous=True)
        rospy.wait_for_service("/flapsim/spawn", timeout=60)
        cls.get_state = rospy.ServiceProxy("/flapsim/get_state", GetState)
        cls.dir = tempfile.mkdtemp(prefix="flapsim_spawn_")  # outside every urdf root
        shutil.copy(os.path.join(PKG, "urdf", "plate.urdf"), os.path.join(cls.dir, "mine.urdf"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def state(self, name):
        s = self.get_state(name=name, link="", reference_frame="")
        self.assertTrue(s.success, s.status_message)
        return s

    def test_a_relative_file_is_read_where_the_tool_runs_at_the_pose_given(self):
        code, out, err = run("-file", "mine.urdf", "-name", "mine", "-x", "1", "-y", "2", "-z",
                             "3", "-R", "0.1", "-P", "0.2", "-Y", "0.3", cwd=self.dir)
        self.assertEqual(code, 0, err)
        self.assertIn("spawned 'mine'", out)
        s = self.state("mine")
        self.assertEqual((s.pose.position.x, s.pose.position.y, s.pose.position.z), (1, 2, 3))
        self.assertLess(largest_difference(matrix(s.pose.orientation), rotation(0.1, 0.2, 0.3)),
                        1e-12)

    def test_param_string_stdin_and_joint_positions(self):
        with open(os.path.join(PKG, "urdf", "flap_unit.urdf")) as f:
            urdf = f.read()
        rospy.set_param("/test_urdf/robot_description", urdf)
        code, _, err = run("-param", "/test_urdf/robot_description", "-model", "from_param",
                           "-urdf", "-z", "5", "-J", "unit0_wing_left_joint", "0.3")
        self.assertEqual(code, 0, err)
        s = self.state("from_param")
        self.assertEqual(s.pose.position.z, 5.0)
        self.assertEqual(s.joint_positions[s.joint_names.index("unit0_wing_left_joint")], 0.3)
        self.assertEqual(s.joint_positions[s.joint_names.index("unit0_wing_right_joint")], 0.0)
        code, _, err = run("-string", urdf, "-name", "from_string", "-x", "4")
        self.assertEqual(code, 0, err)
        self.assertEqual(self.state("from_string").pose.position.x, 4.0)
        code, _, err = run("-stdin", "-name", "from_stdin", "-x", "8", stdin=urdf)
        self.assertEqual(code, 0, err)
        self.assertEqual(self.state("from_stdin").pose.position.x, 8.0)

    def test_refusals_name_their_cause(self):
        cases = [
            (["-file", "missing.urdf", "-name", "m"],
             f"cannot read {os.path.join(self.dir, 'missing.urdf')}"),
            (["-file", "mine.urdf"], "give the creature's name: -name NAME"),
            (["-name", "m"], "give exactly one of -file, -param, -string, -stdin"),
            (["-sdf", "-file", "mine.urdf", "-name", "m"], "-sdf is gazebo's"),
            (["-file", "mine.urdf", "-name", "m", "-x", "nan"], "-x: 'nan' is not finite"),
            (["-file", "mine.urdf", "-name", "m", "-x"], "-x needs a number"),
            (["-param", "/no/such/param", "-name", "m"], "parameter /no/such/param is not set"),
            (["-file", "mine.urdf", "-name", "9lives"], "must start with a letter"),
        ]
        for args, cause in cases:
            code, _, err = run(*args, cwd=self.dir)
            self.assertEqual(code, 1, args)
            self.assertIn(cause, err, args)
        run("-file", "mine.urdf", "-name", "taken", cwd=self.dir)
        code, _, err = run("-file", "mine.urdf", "-name", "taken", cwd=self.dir)
        self.assertEqual(code, 1)
        self.assertIn(f"{os.path.join(self.dir, 'mine.urdf')}: creature name 'taken' is taken", err)

    def test_the_spawn_service_names_the_urdf_roots_of_the_launch_argument(self):
        spawn = rospy.ServiceProxy("/flapsim/spawn", SpawnCreature)
        outside = os.path.join(self.dir, "mine.urdf")
        roots = rospy.get_param("/flapsim/urdf_roots")
        self.assertEqual(roots, f"{PKG}/urdf:/nonexistent")  # as launched
        reply = spawn(name="outside", urdf_file=outside)
        self.assertFalse(reply.success)
        self.assertEqual(reply.status_message,
                         f"urdf_file '{outside}' refused: it must be a readable regular file of "
                         f"at most 16 MiB under an allowed root (parameter ~urdf_roots: "
                         f"{PKG}/urdf, /nonexistent)")
        reply = spawn(name="inside", urdf_file=os.path.join(PKG, "urdf", "plate.urdf"))
        self.assertTrue(reply.success, reply.status_message)


if __name__ == "__main__":
    rostest.rosrun("flapsim", "spawn_creature", SpawnCreatureTool, sys.argv)
