#!/usr/bin/python3
"""A subscriber of /fu/odom and /fu/imu that reads nothing while the node publishes 10 s of sim
time (1,000 messages each at 100 Hz; its socket's receive buffer is 4 KiB, so the node's queue
holds what the kernel does not), then reads: every stamp from 0 to 10 s is there, in order
(lagging_subscriber.test). With the former 10-message queues a recorder lost messages at
rtf 0 in lockstep; here such a subscriber got 259 of the 1,001 odometry messages."""
import os
import socket
import struct
import unittest
import xmlrpc.client

import rospy
import rostest
from flapsim.srv import Step
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

SECONDS = 10.0  # kPublishQueueSeconds
RATE = 100.0    # config/flapsim.yaml publish_rate


def recv_exact(sock, n):
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise ConnectionError(f"closed after {len(data)} of {n} bytes")
        data += chunk
    return data


class StalledSubscriber:
    """A TCPROS subscriber connected to the node's publisher of `topic` that reads only when
    asked (rospy and roscpp subscribers read their sockets at once)."""

    def __init__(self, topic, msg_type):
        master = xmlrpc.client.ServerProxy(os.environ["ROS_MASTER_URI"])
        _, _, uri = master.lookupNode("/lagging_subscriber_test", "/flapsim")
        _, _, proto = xmlrpc.client.ServerProxy(uri).requestTopic(
            "/lagging_subscriber_test", topic, [["TCPROS"]])
        self.sock = socket.socket()
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        self.sock.settimeout(20.0)
        self.sock.connect((proto[1], proto[2]))
        fields = {"callerid": "/lagging_subscriber_test", "topic": topic, "md5sum": "*",
                  "type": msg_type._type, "tcp_nodelay": "1"}
        header = b"".join(struct.pack("<I", len(f"{k}={v}")) + f"{k}={v}".encode()
                          for k, v in fields.items())
        self.sock.sendall(struct.pack("<I", len(header)) + header)
        recv_exact(self.sock, struct.unpack("<I", recv_exact(self.sock, 4))[0])
        self.msg_type = msg_type

    def read_until(self, last_stamp):
        stamps = []
        while not stamps or stamps[-1] < last_stamp:
            size = struct.unpack("<I", recv_exact(self.sock, 4))[0]
            msg = self.msg_type().deserialize(recv_exact(self.sock, size))
            stamps.append(round(msg.header.stamp.to_sec() * RATE))
        return stamps


class LaggingSubscriber(unittest.TestCase):
    def test_a_subscriber_ten_sim_seconds_behind_loses_no_message(self):
        rospy.init_node("lagging_subscriber_test", anonymous=True)
        rospy.wait_for_service("/flapsim/step", timeout=60)
        subs = [StalledSubscriber("/fu/odom", Odometry), StalledSubscriber("/fu/imu", Imu)]
        step = rospy.ServiceProxy("/flapsim/step", Step)
        # Connected: each gets the current (t = 0) message at once; then 10 s at 1 ms steps.
        for _ in range(10):
            self.assertTrue(step(steps=1000).success)
        last = round(SECONDS * RATE)
        for sub in subs:
            stamps = sub.read_until(last)
            self.assertEqual(stamps, list(range(0, last + 1)),
                             f"{sub.msg_type._type}: {len(stamps)} stamps")


if __name__ == "__main__":
    rostest.rosrun("flapsim", "lagging_subscriber", LaggingSubscriber)
