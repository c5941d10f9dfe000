#!/usr/bin/python3
"""The Segmentation nodelet learning online in the running system (vision_online.test): its
diagnostics show the learned state once Identification's confirmed markers arrive, and
~reset_online_calibration returns to the calibrated table."""
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from std_srvs.srv import Trigger

SEGMENTATION = "/camera_0/segmentation"


class OnlineCalibrationLive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("online_calibration_live")
        cls.lock = threading.Lock()
        cls.latest = {}  # key -> value of the segmentation nodelet's last status

        def keep(msg):
            for status in msg.status:
                if status.name.startswith(SEGMENTATION.lstrip("/")) or SEGMENTATION in status.name:
                    with cls.lock:
                        cls.latest = {kv.key: kv.value for kv in status.values}

        rospy.Subscriber("/diagnostics", DiagnosticArray, keep, queue_size=20)

    def status_when(self, condition, timeout):
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            with self.lock:
                latest = dict(self.latest)
            if latest and condition(latest):
                return latest
            time.sleep(0.2)
        with self.lock:
            return dict(self.latest)

    def test_learns_and_resets(self):
        def updates(s):
            return int(s.get("online: updates", "0"))

        # The table is calibrated at start-up; then at least two updates of 1 s each.
        learned = self.status_when(lambda s: updates(s) >= 2, 60)
        self.assertEqual(learned.get("online calibration"), "on", learned)
        self.assertGreaterEqual(updates(learned), 2, learned)
        frames, markers = (int(v) for v in learned["online: frames / confirmed markers learned from"].split(" / "))
        self.assertGreater(frames, 60, learned)
        self.assertGreater(markers, frames, learned)  # robots of 2 markers each in view
        self.assertEqual(learned.get("online: errors"), "0", learned)
        # The confirmed markers meet their frame: at most a tenth arrive after it left the buffer.
        late = int(learned["online: confirmed markers too late (frame no longer kept)"])
        self.assertLess(late, frames // 10, learned)
        print("online calibration live: %s" % learned, flush=True)

        rospy.wait_for_service(SEGMENTATION + "/reset_online_calibration", timeout=10)
        reply = rospy.ServiceProxy(SEGMENTATION + "/reset_online_calibration", Trigger)()
        self.assertTrue(reply.success, reply.message)
        self.assertIn("back to the calibrated table", reply.message)
        # Counters start again from zero after the reset.
        after = self.status_when(lambda s: int(s["online: frames / confirmed markers learned from"].split(" / ")[0])
                                 < frames, 10)
        self.assertLess(int(after["online: frames / confirmed markers learned from"].split(" / ")[0]), frames, after)


if __name__ == "__main__":
    rostest.rosrun("soccer_vision", "online_calibration_live", OnlineCalibrationLive)
