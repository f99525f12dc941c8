#!/usr/bin/python3
"""rosrun flapsim spawn_creature against empty_world.launch (spawn_creature.test): gazebo_ros
spawn_model's flags, a relative -file read where the tool runs (outside the simulator's
urdf_roots), -param, -string, -J; refusals named; and the flapsim/spawn service refusing a
file outside urdf_roots (a launch argument) with the roots named. Hostile input: files that
are not regular, texts over 16 MiB, standard input left open, no master (none, silent, or
half alive), bad flag values, a -J that fails (checked before the spawn, or the creature
deleted again)."""
import math
import os
import shutil
import socket
import socketserver
import subprocess
import sys
import tempfile
import threading
import unittest
import xmlrpc.server

import rospkg
import rospy
import rostest
from flapsim.srv import (DeleteCreature, DeleteCreatureResponse, GetState, SetState,
                         SetStateResponse, SpawnCreature, SpawnCreatureResponse)

PKG = rospkg.RosPack().get_path("flapsim")
TOOL = os.path.join(PKG, "scripts", "spawn_creature")


MAX_URDF_BYTES = 16 << 20  # kMaxUrdfFileBytes
# A wait bounded by -timeout ends within it, the tool's 1 s grace and this (start-up, load).
MARGIN = 15


def run(*args, cwd=None, stdin=None, env=None, timeout=60):
    result = subprocess.run(["/usr/bin/python3", TOOL] + list(args), cwd=cwd, input=stdin,
                            capture_output=True, text=True, timeout=timeout, env=env)
    return result.returncode, result.stdout, result.stderr


def with_master(uri):
    return dict(os.environ, ROS_MASTER_URI=uri)


def closed_port():
    """A local port nothing listens on (just released)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class ThreadingXMLRPCServer(socketserver.ThreadingMixIn, xmlrpc.server.SimpleXMLRPCServer):
    daemon_threads = True


class HalfAliveMaster:
    """An XML-RPC server that answers getPid as a ROS master does and no other call (each
    waits until the server is closed)."""

    def __init__(self):
        self.release = threading.Event()
        self.server = ThreadingXMLRPCServer(("127.0.0.1", 0), logRequests=False)
        self.server.register_instance(self)
        self.uri = f"http://127.0.0.1:{self.server.server_address[1]}/"
        threading.Thread(target=self.server.serve_forever, daemon=True).start()

    def _dispatch(self, method, params):
        if method == "getPid":
            return [1, "", os.getpid()]
        self.release.wait()
        return [-1, "closed", 0]

    def close(self):
        self.release.set()
        self.server.shutdown()
        self.server.server_close()


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
            (["-sdf", "-file", "mine.urdf", "-name", "m"],
             "-sdf is gazebo's: flapsim spawns URDF"),
            (["-reference_frame", "x", "-file", "mine.urdf", "-name", "m"],
             "-reference_frame is gazebo's: flapsim spawns in the world frame"),
            (["-gazebo_namespace", "a b"], "-gazebo_namespace: 'a b' is not a node name"),
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

    def assert_one_line_error(self, code, err, start, args):
        self.assertEqual(code, 1, (args, err))
        self.assertNotIn("Traceback", err, args)
        self.assertEqual(len(err.strip().splitlines()), 1, (args, err))
        self.assertTrue(err.startswith("spawn_creature: " + start), (args, err))

    def assert_absent(self, name):
        s = self.get_state(name=name, link="", reference_frame="")
        self.assertFalse(s.success, f"'{name}' is spawned")

    def test_help_exits_0_with_the_usage_on_standard_output(self):
        for flag in ("-h", "-help", "--help"):
            code, out, err = run(flag)
            self.assertEqual(code, 0, (flag, err))
            self.assertIn("rosrun flapsim spawn_creature (-file FILE", out)
            self.assertEqual(err, "")

    def test_bad_flag_values_are_one_line_errors_naming_the_flag_without_a_traceback(self):
        urdf = ["-file", "mine.urdf", "-name", "m"]
        cases = [
            (["-timeout", "0"], "-timeout: '0' is not in (0, 1e6] s"),
            (["-timeout", "-1"], "-timeout: '-1' is not in (0, 1e6] s"),
            (["-timeout", "1e7"], "-timeout: '1e7' is not in (0, 1e6] s"),
            (["-timeout", "nan"], "-timeout: 'nan' is not finite"),
            (["-timeout", "inf"], "-timeout: 'inf' is not finite"),
            (["-timeout", "abc"], "-timeout: 'abc' is not a number"),
            (["-timeout"], "-timeout needs seconds"),
            (["-x", "abc"], "-x: 'abc' is not a number"),
            (["-y", "-inf"], "-y: '-inf' is not finite"),
            (["-z", "1e999"], "-z: '1e999' is not finite"),
            (["-R", "NaN"], "-R: 'NaN' is not finite"),
            (["-P", ""], "-P: '' is not a number"),
            (["-Y", "0x10"], "-Y: '0x10' is not a number"),
            (["-J", "unit0_wing_left_joint", "abc"], "-J: 'abc' is not a number"),
            (["-J", "unit0_wing_left_joint", "nan"], "-J: 'nan' is not finite"),
            (["-J", "unit0_wing_left_joint"], "-J needs a position"),
            (["-J"], "-J needs a joint name and a position"),
            (["-J", "a", "1", "-J", "a", "2"], "-J: joint 'a' is given twice"),
            (["-simulator", "/"], "-simulator: '/' is not a node name"),
            (["-simulator", "a b"], "-simulator: 'a b' is not a node name"),
        ]
        for args, cause in cases:
            code, _, err = run(*(urdf + args), cwd=self.dir)
            self.assert_one_line_error(code, err, cause, args)

    def test_a_fifo_dev_zero_and_a_directory_are_refused_as_not_regular_files(self):
        fifo = os.path.join(self.dir, "fifo.urdf")
        os.mkfifo(fifo)  # no writer: opening it to read blocks unless without blocking
        for path in (fifo, "/dev/zero", self.dir):
            code, _, err = run("-file", path, "-name", "m", timeout=MARGIN)
            self.assert_one_line_error(code, err, f"{path}: not a regular file", path)

    def test_a_file_over_16_mib_is_refused_by_size_before_the_master_is_asked(self):
        # Without a master, a text within the limit waits for one: the refusal comes first.
        env = with_master(f"http://127.0.0.1:{closed_port()}")
        big = os.path.join(self.dir, "big.urdf")
        for size, cause in [
                (MAX_URDF_BYTES + 1, f"{big}: {MAX_URDF_BYTES + 1} bytes, over the limit of "
                                     f"{MAX_URDF_BYTES} bytes (16 MiB)"),
                (MAX_URDF_BYTES, "no answer from the ROS master")]:
            with open(big, "wb") as f:
                f.truncate(size)  # sparse: zeros, no disk
            code, _, err = run("-file", big, "-name", "m", "-timeout", "1", env=env,
                               timeout=1 + MARGIN)
            self.assert_one_line_error(code, err, cause, size)

    def test_standard_input_over_16_mib_is_refused_by_name_before_the_master_is_asked(self):
        env = with_master(f"http://127.0.0.1:{closed_port()}")
        for size, cause in [
                (MAX_URDF_BYTES + 1, f"standard input: more than {MAX_URDF_BYTES} bytes, over "
                                     "the limit of 16 MiB"),
                (MAX_URDF_BYTES, "no answer from the ROS master")]:
            code, _, err = run("-stdin", "-name", "m", "-timeout", "1", stdin=" " * size,
                               env=env, timeout=1 + MARGIN)
            self.assert_one_line_error(code, err, cause, size)

    def test_standard_input_left_open_ends_at_the_timeout_naming_standard_input(self):
        tool = subprocess.Popen(["/usr/bin/python3", TOOL, "-stdin", "-name", "m", "-timeout",
                                 "2"], stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True)
        try:
            tool.stdin.write("<robot name='r'>")  # and not closed until the tool has ended
            tool.stdin.flush()
            tool.wait(timeout=2 + MARGIN)  # TimeoutExpired if it waits on
            err = tool.stderr.read()
        finally:
            tool.kill()
            tool.wait()
            tool.stdin.close()
            tool.stderr.close()
        self.assert_one_line_error(tool.returncode, err, "standard input not ended (no end "
                                   "of file) after 2 s (-timeout)", "-stdin")

    def test_without_a_master_the_timeout_ends_the_wait_naming_the_master(self):
        silent = socket.socket()  # accepts connections (the kernel's backlog), never answers
        silent.bind(("127.0.0.1", 0))
        silent.listen(8)
        half_alive = HalfAliveMaster()
        try:
            for uri, waited_for in [
                    (f"http://127.0.0.1:{closed_port()}", "no answer from the ROS master at"),
                    (f"http://127.0.0.1:{silent.getsockname()[1]}",
                     "no answer from the ROS master at"),
                    (half_alive.uri, "no registration with the ROS master at")]:
                code, _, err = run("-file", "mine.urdf", "-name", "m", "-timeout", "2",
                                   cwd=self.dir, env=with_master(uri), timeout=2 + MARGIN)
                self.assert_one_line_error(code, err, f"{waited_for} {uri} after 2 s "
                                           "(-timeout)", uri)
        finally:
            silent.close()
            half_alive.close()

    def test_without_the_simulator_the_timeout_ends_the_wait_naming_the_service(self):
        # -gazebo_namespace is spawn_model's name for -simulator: the same flag
        for flag in ("-simulator", "-gazebo_namespace"):
            code, _, err = run("-file", "mine.urdf", "-name", "m", "-timeout", "2", flag,
                               "/nobody", cwd=self.dir, timeout=2 + MARGIN)
            self.assert_one_line_error(code, err, "no service /nobody/spawn after 2 s (-timeout)",
                                       f"{flag} /nobody")

    def test_an_unknown_or_fixed_J_joint_is_refused_before_the_spawn(self):
        flap_unit = os.path.join(PKG, "urdf", "flap_unit.urdf")
        copter = os.path.join(PKG, "urdf", "bamboo_copter.urdf")
        for path, joint, cause in [
                (flap_unit, "no_such_joint",
                 f"-J: {flap_unit} has no joint 'no_such_joint' (its movable joints: "
                 "unit0_wing_left_joint, unit0_wing_right_joint); nothing spawned"),
                (copter, "blade_left_joint",
                 f"-J: joint 'blade_left_joint' of {copter} is fixed; nothing spawned")]:
            code, _, err = run("-file", path, "-name", "j_checked", "-J", joint, "0.3")
            self.assert_one_line_error(code, err, cause, joint)
            self.assert_absent("j_checked")
        code, _, err = run("-file", flap_unit, "-name", "j_checked", "-J",
                           "unit0_wing_left_joint", "0.3")
        self.assertEqual(code, 0, err)
        s = self.state("j_checked")
        self.assertEqual(s.joint_positions[s.joint_names.index("unit0_wing_left_joint")], 0.3)

    def test_a_J_position_the_simulator_refuses_deletes_the_creature_it_spawned(self):
        flap_unit = os.path.join(PKG, "urdf", "flap_unit.urdf")
        for _ in range(2):  # the same command again: not "name taken"
            code, out, err = run("-file", flap_unit, "-name", "j_refused", "-J",
                                 "unit0_wing_left_joint", "2")
            self.assertIn("spawned 'j_refused'", out)
            self.assert_one_line_error(code, err, "-J: ", "-J 2")
            self.assertIn("outside its limits", err)
            self.assertIn("deleted 'j_refused' again: nothing is spawned", err)
            self.assert_absent("j_refused")
        code, _, err = run("-file", flap_unit, "-name", "j_refused", "-J",
                           "unit0_wing_left_joint", "1")
        self.assertEqual(code, 0, err)

    def test_a_failed_J_whose_delete_fails_too_says_the_creature_is_spawned(self):
        deleted = []

        def delete(req):
            deleted.append(req.model_name)  # the tool sends gazebo_msgs' name
            return DeleteCreatureResponse(success=False, status_message="delete refused")

        services = [
            rospy.Service("/fake_sim/spawn", SpawnCreature,
                          lambda req: SpawnCreatureResponse(success=True,
                                                            status_message="spawned 'f'")),
            rospy.Service("/fake_sim/set_state", SetState,
                          lambda req: SetStateResponse(success=False,
                                                       status_message="set_state refused")),
            rospy.Service("/fake_sim/delete", DeleteCreature, delete)]
        try:
            code, _, err = run("-file", os.path.join(PKG, "urdf", "flap_unit.urdf"), "-name",
                               "f", "-J", "unit0_wing_left_joint", "0.3", "-simulator",
                               "/fake_sim")
        finally:
            for service in services:
                service.shutdown()
        self.assert_one_line_error(code, err, "-J: set_state refused; deleting 'f' failed too "
                                   "(delete refused): 'f' is still spawned", "fake_sim")
        self.assertEqual(deleted, ["f"])


if __name__ == "__main__":
    rostest.rosrun("flapsim", "spawn_creature", SpawnCreatureTool, sys.argv)
