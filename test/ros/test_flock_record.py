#!/usr/bin/python3
"""A lockstep flock recorded at rtf 0 (flock_record.test): once the controller has flown its
10 s and the recorder has closed the bag, the bag holds every stamp, 0 to 10 s at the 100 Hz
publish rate, of each creature's odom, imu and joint_states. rosbag record lost messages here
(its subscriptions queue 100 and drop the oldest; 1 bag of 8 lost 38 odometry messages):
record.launch runs flapsim_record."""
import os
import time
import unittest
import xmlrpc.client

import rosbag
import rosnode
import rospy
import rostest
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger

DURATION = 10.0


def sent_to(node, peer):
    """Messages `node` (roscpp) has sent per topic on its connections to `peer`."""
    master = xmlrpc.client.ServerProxy(os.environ["ROS_MASTER_URI"])
    _, _, uri = master.lookupNode("/flock_record_test", node)
    api = xmlrpc.client.ServerProxy(uri)
    peer_of = {c[0]: c[1] for c in api.getBusInfo("/flock_record_test")[2]}
    sent = {}
    # roscpp: [publications, subscriptions], each [topic, [[id, bytes, bytes, messages, _]]]
    for topic, conns in api.getBusStats("/flock_record_test")[0]:
        for conn in conns:
            if peer_of.get(conn[0]) == peer:
                sent[topic] = sent.get(topic, 0) + conn[3]
    return sent
RATE = 100.0


class FlockRecord(unittest.TestCase):
    def test_the_bag_has_every_stamp_of_every_creature(self):
        rospy.init_node("flock_record_test", anonymous=True)
        bag = rospy.get_param("~bag")
        # The controller flies DURATION of sim time, then the simulator stays paused there
        # (waits bounded in wall time: the condition, not the time, ends them).
        reached = []
        sub = rospy.Subscriber("/clock", Clock,
                               lambda m: reached.append(m.clock.to_sec() >= DURATION - 1e-9))
        end = time.monotonic() + 180.0
        while not (reached and reached[-1]) and time.monotonic() < end:
            time.sleep(0.05)
        sub.unregister()
        self.assertTrue(reached and reached[-1], "sim time never reached 10 s")
        # Every message the simulator sent the recorder on these topics is written (the
        # simulator's count of its connection to /record against the recorder's ~written),
        # then the recorder is shut down, closing the bag.
        topics = [f"/afc{c}/{t}" for c in range(4) for t in ("odom", "imu", "joint_states")]
        written = rospy.ServiceProxy("/record/written", Trigger)
        rospy.wait_for_service("/record/written", timeout=60)
        end = time.monotonic() + 60.0
        while True:
            counts = dict(line.split() for line in written().message.splitlines())
            sent = sent_to("/flapsim", "/record")
            if all(int(counts[t]) == sent.get(t, -1) for t in topics):
                break
            self.assertLess(time.monotonic(), end, f"written {counts}, sent {sent}")
            time.sleep(0.05)
        rosnode.kill_nodes(["/record"])
        end = time.monotonic() + 60.0
        while "/record" in rosnode.get_node_names() and time.monotonic() < end:
            time.sleep(0.1)
        self.assertTrue(os.path.exists(bag), bag)
        last = round(DURATION * RATE)
        with rosbag.Bag(bag) as b:
            for c in range(4):
                for topic in (f"/afc{c}/odom", f"/afc{c}/imu", f"/afc{c}/joint_states"):
                    stamps = sorted({round(m.header.stamp.to_sec() * RATE)
                                     for _, m, _ in b.read_messages(topics=[topic])})
                    missing = sorted(set(range(0, last + 1)) - set(stamps))
                    self.assertEqual(missing, [], f"{topic}: {len(stamps)} distinct stamps of "
                                     f"{last + 1}, missing (x 10 ms) {missing[:20]}")


if __name__ == "__main__":
    rostest.rosrun("flapsim", "flock_record", FlockRecord)
