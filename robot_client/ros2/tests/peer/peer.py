"""A ROS 2 robot and its operator played by Cyclone DDS (PyPI `cyclonedds`), for pps-ros2's
interop tests: it streams a recorded scene's camera and cloud, latches the camera's static
transform, clicks, sends inventory rounds and trials, and reports what the node answers.

Driven by one JSON command a line on stdin, one JSON answer a line on stdout:
  {"scene": DIR}          stream DIR's image.rgb, cloud.xyz and scene.json (see below)
  {"wait_matched": S}     until every topic here is matched with the node, S seconds at most
  {"click": [x, y, z], "timeout": S}   click (again every 3 s) until /pps/tag_pose and
                          /goal_pose answer
  {"rfid": [[epc, rssi_dbm, antenna], ...], "timeout": S}   one round (again every 3 s until
                                                              answered), the /pps/entry answer
  {"trial": JSON}         publish a pps_msgs/Trial
Images go out as bgr8 with padded rows, clouds with the fields in the order z, x, y,
intensity and 16 bytes a point: layouts the node must read as well as the plain ones.
"""

import json
import sys
import threading
import time
from array import array

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

import ros_types as t

CDR = Policy.DataRepresentation(use_cdrv0_representation=True)
RELIABLE = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(10), CDR)
LATCHED = Qos(
    Policy.Reliability.Reliable(duration(seconds=1)),
    Policy.Durability.TransientLocal,
    Policy.History.KeepLast(1),
    CDR,
)
SENSOR = Qos(Policy.Reliability.BestEffort, Policy.History.KeepLast(1), CDR)


class Peer:
    def __init__(self):
        self.dp = DomainParticipant(0)
        topic = lambda name, kind: Topic(self.dp, "rt" + name, kind)
        self.image = DataWriter(self.dp, topic("/camera/image_raw", t.Image), qos=SENSOR)
        self.info = DataWriter(self.dp, topic("/camera/camera_info", t.CameraInfo), qos=SENSOR)
        self.points = DataWriter(self.dp, topic("/points", t.PointCloud2), qos=SENSOR)
        self.tf_static = DataWriter(self.dp, topic("/tf_static", t.TFMessage), qos=LATCHED)
        self.click_writer = DataWriter(self.dp, topic("/clicked_point", t.PointStamped), qos=RELIABLE)
        self.rfid = DataWriter(self.dp, topic("/pps/rfid", t.TagReads), qos=RELIABLE)
        self.trial = DataWriter(self.dp, topic("/pps/trial", t.Trial), qos=RELIABLE)
        self.tag_pose = DataReader(self.dp, topic("/pps/tag_pose", t.PoseStamped), qos=RELIABLE)
        self.goal_pose = DataReader(self.dp, topic("/goal_pose", t.PoseStamped), qos=RELIABLE)
        self.markers = DataReader(self.dp, topic("/pps/markers", t.MarkerArray), qos=RELIABLE)
        self.entry = DataReader(self.dp, topic("/pps/entry", t.TagEntry), qos=RELIABLE)
        self.stream = None

    def scene(self, directory):
        with open(f"{directory}/scene.json") as f:
            scene = json.load(f)
        width, height = scene["width"], scene["height"]
        rgb = open(f"{directory}/image.rgb", "rb").read()
        bgr = bytearray(rgb)
        bgr[0::3], bgr[2::3] = rgb[2::3], rgb[0::3]
        step = width * 3 + 4
        padded = bytearray(step * height)
        for row in range(height):
            padded[row * step : row * step + width * 3] = bgr[row * width * 3 : (row + 1) * width * 3]
        camera_frame = "camera_optical"
        image = t.Image(
            header=t.Header(frame_id=camera_frame), height=height, width=width,
            encoding="bgr8", step=step, data=bytes(padded),
        )
        fx, fy, cx, cy = scene["fx"], scene["fy"], scene["cx"], scene["cy"]
        info = t.CameraInfo(
            header=t.Header(frame_id=camera_frame), height=height, width=width,
            distortion_model="plumb_bob", d=[0.0] * 5,
            k=[fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0],
            r=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            p=[fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0],
        )
        xyz = array("f")
        xyz.frombytes(open(f"{directory}/cloud.xyz", "rb").read())
        n = len(xyz) // 3
        packed = array("f", bytes(16 * n))
        packed[0::4], packed[1::4], packed[2::4] = xyz[2::3], xyz[0::3], xyz[1::3]
        field = lambda name, offset: t.PointField(name=name, offset=offset, datatype=7, count=1)
        cloud = t.PointCloud2(
            header=t.Header(frame_id="base_link"), height=1, width=n,
            fields=[field("z", 0), field("x", 4), field("y", 8), field("intensity", 12)],
            point_step=16, row_step=16 * n, data=packed.tobytes(), is_dense=True,
        )
        (x, y, z), (qx, qy, qz, qw) = scene["translation"], scene["rotation_xyzw"]
        self.tf_static.write(t.TFMessage(transforms=[t.TransformStamped(
            header=t.Header(frame_id="base_link"), child_frame_id=camera_frame,
            transform=t.Transform(
                translation=t.Vector3(x, y, z), rotation=t.Quaternion(qx, qy, qz, qw)),
        )]))
        # A camera and a laser stream: a best-effort sample lost now comes again soon.
        def stream():
            while True:
                self.info.write(info)
                self.image.write(image)
                self.points.write(cloud)
                time.sleep(0.5)
        self.stream = threading.Thread(target=stream, daemon=True)
        self.stream.start()
        return {"streaming": {"image": [width, height], "points": n}}

    def wait_matched(self, seconds):
        deadline = time.monotonic() + seconds
        writers = [self.image, self.info, self.points, self.tf_static, self.click_writer,
                   self.rfid, self.trial]
        readers = [self.tag_pose, self.goal_pose, self.markers, self.entry]
        while time.monotonic() < deadline:
            unmatched = [w for w in writers if w.get_publication_matched_status().current_count == 0]
            unmatched += [r for r in readers if r.get_subscription_matched_status().current_count == 0]
            if not unmatched:
                return {"matched": True}
            time.sleep(0.05)
        return {"matched": False, "unmatched": [e.topic.name for e in unmatched]}

    def click(self, point, timeout):
        deadline = time.monotonic() + timeout
        tag = goal = None
        markers = 0
        while time.monotonic() < deadline and (tag is None or goal is None):
            self.click_writer.write(t.PointStamped(
                header=t.Header(frame_id="base_link"), point=t.Point(*point)))
            again = min(deadline, time.monotonic() + 3.0)
            while time.monotonic() < again and (tag is None or goal is None):
                for sample in self.tag_pose.take(10):
                    tag = sample
                for sample in self.goal_pose.take(10):
                    goal = sample
                for sample in self.markers.take(10):
                    markers = len(sample.markers)
                time.sleep(0.01)
        pose = lambda p: None if p is None else {
            "frame": p.header.frame_id,
            "position": [p.pose.position.x, p.pose.position.y, p.pose.position.z],
            "orientation_xyzw": [p.pose.orientation.x, p.pose.orientation.y,
                                 p.pose.orientation.z, p.pose.orientation.w],
        }
        return {"tag_pose": pose(tag), "goal_pose": pose(goal), "markers": markers}

    def round(self, reads, timeout):
        # Like a click, the round is written again every 3 s until the node answers: a sample
        # written while the two sides' discovery is still settling may reach no reader, and a
        # round no answer came back to is one the node never saw.
        self.entry.take(100)
        message = t.TagReads(reads=[t.TagRead(epc=e, rssi_dbm=r, antenna=a) for e, r, a in reads])
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.rfid.write(message)
            again = min(deadline, time.monotonic() + 3.0)
            while time.monotonic() < again:
                for sample in self.entry.take(1):
                    return {"entry": {
                        "epc": sample.epc, "ambiguous": sample.ambiguous,
                        "revision": sample.revision, "entry_json": sample.entry_json,
                        "unavailable_actions": list(sample.unavailable_actions),
                        "error": sample.error,
                    }}
                time.sleep(0.01)
        return {"entry": None}


def main():
    peer = Peer()
    print(json.dumps({"ready": True}), flush=True)
    for line in sys.stdin:
        command = json.loads(line)
        if "scene" in command:
            answer = peer.scene(command["scene"])
        elif "wait_matched" in command:
            answer = peer.wait_matched(command["wait_matched"])
        elif "click" in command:
            answer = peer.click(command["click"], command.get("timeout", 60))
        elif "rfid" in command:
            answer = peer.round(command["rfid"], command.get("timeout", 20))
        elif "trial" in command:
            peer.trial.write(t.Trial(trial_json=json.dumps(command["trial"])))
            answer = {"sent": True}
        else:
            answer = {"error": f"unknown command {line.strip()}"}
        print(json.dumps(answer), flush=True)


if __name__ == "__main__":
    main()
