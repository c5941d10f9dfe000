#!/usr/bin/python3
"""N cameras in one running system (vision_four_cameras.test: demo.launch on Division A with
its four cameras): every camera's pipeline runs, each camera's frame is tracked with the robots
its ground truth shows, and no output ever reports a robot twice, however many cameras see it.
The cameras capture at the same instants: tf carries each frame once per stamp (tf2 refuses a
transform repeated at its stamp, and every listener warns of it)."""
import collections
import threading
import time
import unittest

import rospy
import rostest
from soccer_vision.msg import CameraDetections, RobotPoseArray
from tf2_msgs.msg import TFMessage


def key(pose):
    return (pose.team, pose.id)


class CamerasLive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("cameras_live")
        cls.cameras = rospy.get_param("~cameras", 4)
        cls.duration = rospy.get_param("~duration", 20.0)
        cls.lock = threading.Lock()
        cls.truth = {}  # stamp -> (camera, visible (team, id) -> (x, y))
        cls.outputs = {}  # stamp -> RobotPoseArray
        cls.detections = collections.Counter()  # camera -> frames identified
        for i in range(cls.cameras):
            rospy.Subscriber("/camera_%d/ground_truth/robots" % i, RobotPoseArray,
                             lambda m, i=i: cls.keep_truth(i, m), queue_size=50)
            rospy.Subscriber("/camera_%d/detections" % i, CameraDetections,
                             lambda m, i=i: cls.count_detections(i, m), queue_size=50)
        rospy.Subscriber("/vision/robots", RobotPoseArray, cls.keep_output, queue_size=200)
        cls.tf_seen = collections.Counter()  # (child frame, stamp) -> transforms published
        rospy.Subscriber("/tf", TFMessage, cls.count_tf, queue_size=200)

    @classmethod
    def keep_truth(cls, camera, msg):
        with cls.lock:
            cls.truth[msg.header.stamp.to_sec()] = (camera, {key(r): (r.x, r.y) for r in msg.robots if r.visible})

    @classmethod
    def count_detections(cls, camera, msg):
        with cls.lock:
            cls.detections[camera] += 1

    @classmethod
    def count_tf(cls, msg):
        with cls.lock:
            for t in msg.transforms:
                cls.tf_seen[(t.child_frame_id, t.header.stamp)] += 1

    @classmethod
    def keep_output(cls, msg):
        with cls.lock:
            cls.outputs[msg.header.stamp.to_sec()] = msg

    def test_every_camera_tracks_its_robots_and_none_twice(self):
        deadline = time.time() + 120
        while time.time() < deadline and not rospy.is_shutdown():
            with self.lock:
                if len(self.detections) == self.cameras and min(self.detections.values()) > 0:
                    break
            time.sleep(0.5)
        with self.lock:
            self.detections.clear()
            self.outputs.clear()
            self.tf_seen.clear()
        time.sleep(self.duration)
        with self.lock:
            detections = dict(self.detections)
            outputs = dict(self.outputs)
            truth = dict(self.truth)
            tf_seen = dict(self.tf_seen)

        print("frames identified per camera in %.0f s: %s" % (self.duration, detections))
        self.assertEqual(sorted(detections), list(range(self.cameras)), "a camera's pipeline is not running")
        self.assertGreater(min(detections.values()), 3 * self.duration, detections)

        twice = [stamp for stamp, msg in outputs.items() if len({key(r) for r in msg.robots}) < len(msg.robots)]
        self.assertEqual(twice, [], "outputs with a robot reported twice")
        tf_stamps = {stamp for _, stamp in tf_seen}
        tf_repeated = sorted((n, frame, stamp.to_sec()) for (frame, stamp), n in tf_seen.items() if n > 1)
        print("tf: %d transforms at %d stamps, %d repeated" % (len(tf_seen), len(tf_stamps), len(tf_repeated)))
        self.assertGreater(len(tf_stamps), 3 * self.duration, "tf is published")
        self.assertEqual(tf_repeated[:5], [], "a frame's transform repeated at its stamp")
        seen = {key(r) for msg in outputs.values() for r in msg.robots if r.visible}

        # Each output is the tracker after one camera's frame: the robots that camera shows
        # are measured in it, within 3 cm of the truth.
        per_camera = collections.defaultdict(lambda: [0, 0])
        for stamp, msg in outputs.items():
            if stamp not in truth:
                continue
            camera, shown = truth[stamp]
            measured = {key(r): (r.x, r.y) for r in msg.robots if r.visible}
            for robot, (x, y) in shown.items():
                per_camera[camera][1] += 1
                m = measured.get(robot)
                per_camera[camera][0] += m is not None and (m[0] - x) ** 2 + (m[1] - y) ** 2 < 0.03 ** 2
        print("robots measured of those in view, per camera: %s; %d distinct robots measured" % (
            {c: "%d/%d" % tuple(v) for c, v in sorted(per_camera.items())}, len(seen)))
        self.assertEqual(sorted(per_camera), list(range(self.cameras)), "outputs of every camera's frames")
        for camera, (found, shown) in per_camera.items():
            self.assertGreater(shown, 0)
            self.assertGreaterEqual(found / shown, 0.97, "camera %d: %d of %d" % (camera, found, shown))
        self.assertEqual(len(seen), rospy.get_param("~robots", 22), sorted(seen))


if __name__ == "__main__":
    rostest.rosrun("soccer_vision", "test_cameras_live", CamerasLive)
