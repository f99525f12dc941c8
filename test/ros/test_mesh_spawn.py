#!/usr/bin/python3
"""Robots with meshes through the node (mesh_spawn.test, a paused empty world):

- test/ros/cad_mesh_unit.urdf, written the way CAD exports do (a massless base_link carrying
  the body's OBJ mesh, a full inertia tensor, STL wings, package:// URIs), spawned with
  `rosrun flapsim spawn_creature -file`, settles on the ground and, flapping, climbs: the air
  acts on its mesh wings (nothing else can lift it);
- test/meshes/flap_unit_mesh.urdf (urdf/flap_unit.urdf with every box a 12-triangle mesh)
  climbs within 2 % of the box unit in 6 s of sim time, both spawned by the flapsim/spawn
  service and flown by flapsim/step with the demo's strokes (60/10 rad/s, amplitude 0.8)."""
import os
import subprocess
import unittest

import rospkg
import rospy
import rostest
from geometry_msgs.msg import Pose
from flapsim.msg import WingCommand
from flapsim.srv import GetState, SpawnCreature, Step

PKG = rospkg.RosPack().get_path("flapsim")


def stroke(down, up, amplitude):
    c = WingCommand()
    c.downstroke_rate = [down, down]
    c.upstroke_rate = [up, up]
    c.amplitude = [amplitude, amplitude]
    return c


class MeshSpawn(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_mesh_spawn")
        for s in ("/flapsim/spawn", "/flapsim/step", "/flapsim/get_state"):
            rospy.wait_for_service(s, timeout=60)
        cls.spawn = rospy.ServiceProxy("/flapsim/spawn", SpawnCreature)
        cls.step = rospy.ServiceProxy("/flapsim/step", Step)
        cls.get_state = rospy.ServiceProxy("/flapsim/get_state", GetState)

    def state(self, name):
        s = self.get_state(name=name)
        self.assertTrue(s.success, s.status_message)
        return s

    def fly(self, names, command, steps):
        r = self.step(steps=steps, creatures=names, wing_commands=[command] * len(names))
        self.assertTrue(r.success, r.status_message)

    def test_a_cad_mesh_robot_rests_on_the_ground_and_climbs_when_it_flaps(self):
        result = subprocess.run(
            ["/usr/bin/python3", os.path.join(PKG, "scripts", "spawn_creature"), "-file",
             os.path.join(PKG, "test", "ros", "cad_mesh_unit.urdf"), "-model", "cad", "-x", "-5",
             "-z", "0.05"], capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.fly([], WingCommand(), 1000)  # 1 s without a command: it falls and settles
        rest = self.state("cad")
        speed = (rest.twist.linear.x ** 2 + rest.twist.linear.y ** 2 +
                 rest.twist.linear.z ** 2) ** 0.5
        self.assertLess(speed, 0.01)
        # The body's frame half its mesh's 0.03 m height up, plus the hull's 1 mm margin.
        self.assertAlmostEqual(rest.pose.position.z, 0.016, delta=1e-3)
        self.fly(["cad"], stroke(60.0, 10.0, 0.8), 1000)
        flown = self.state("cad")
        rospy.loginfo("cad at rest: z %.4f m, speed %.2e m/s; after 1 s of flapping %.4f m",
                      rest.pose.position.z, speed, flown.pose.position.z)
        self.assertGreater(flown.pose.position.z - rest.pose.position.z, 1.0)  # measured 1.42

    def test_b_a_meshed_flap_unit_climbs_as_the_box_one_does(self):
        start = {}
        for name, path, x in (("box", "urdf/flap_unit.urdf", 5.0),
                              ("meshed", "test/meshes/flap_unit_mesh.urdf", 15.0)):
            pose = Pose()
            pose.position.x, pose.position.z, pose.orientation.w = x, 1.0, 1.0
            r = self.spawn(name=name, urdf_file=os.path.join(PKG, path), initial_pose=pose)
            self.assertTrue(r.success, r.status_message)
            start[name] = self.state(name).pose.position.z
        self.fly(["box", "meshed"], stroke(60.0, 10.0, 0.8), 6000)
        climb = {n: self.state(n).pose.position.z - start[n] for n in start}
        rospy.loginfo("6 s climbs: box %.4f m, meshed %.4f m", climb["box"], climb["meshed"])
        self.assertGreater(climb["box"], 3.0)
        self.assertLess(abs(climb["meshed"] - climb["box"]), 0.02 * climb["box"])


if __name__ == "__main__":
    rostest.rosrun("flapsim", "mesh_spawn", MeshSpawn)
