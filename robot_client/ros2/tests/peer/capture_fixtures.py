"""Writes tests/fixtures/*.cdr: one message of each type pps-ros2 speaks, serialized by Cyclone
DDS's Python binding as its writers put them on the wire (plain CDR, little-endian). The Rust
side (tests/cdr_fixtures.rs) builds the same messages and must produce and read these bytes.

Run with the Python that has cyclonedds (tests/cyclonedds/install makes one):
    target/cyclonedds-venv/bin/python robot_client/ros2/tests/peer/capture_fixtures.py
The values are odd on purpose: strings of every length mod 4, a byte before every wider field,
so any misplaced alignment shows."""

import pathlib

import ros_types as t

STAMP = t.Time(sec=1764583200, nanosec=123456789)


def header(frame):
    return t.Header(stamp=STAMP, frame_id=frame)


def messages():
    yield "image", t.Image(
        header=header("camera_optical"), height=2, width=3, encoding="bgr8", is_bigendian=0,
        step=10, data=bytes(range(20)),
    )
    yield "camera_info", t.CameraInfo(
        header=header("cam"), height=960, width=1280, distortion_model="plumb_bob",
        d=[0.1, -0.25, 0.001, 0.002, 0.0],
        k=[1000.5, 0.0, 640.25, 0.0, 1001.5, 480.75, 0.0, 0.0, 1.0],
        r=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        p=[1000.5, 0.0, 640.25, 0.0, 0.0, 1001.5, 480.75, 0.0, 0.0, 0.0, 1.0, 0.0],
        binning_x=1, binning_y=2,
        roi=t.RegionOfInterest(x_offset=3, y_offset=4, height=5, width=6, do_rectify=True),
    )
    yield "point_cloud2", t.PointCloud2(
        header=header("base_link"), height=1, width=2,
        fields=[
            t.PointField(name="z", offset=0, datatype=7, count=1),
            t.PointField(name="x", offset=4, datatype=7, count=1),
            t.PointField(name="y", offset=8, datatype=7, count=1),
            t.PointField(name="intensity", offset=12, datatype=2, count=1),
        ],
        is_bigendian=False, point_step=13, row_step=26, data=bytes(range(100, 126)), is_dense=True,
    )
    yield "tf_message", t.TFMessage(transforms=[
        t.TransformStamped(
            header=header("base_link"), child_frame_id="head",
            transform=t.Transform(t.Vector3(0.1, -0.2, 1.3), t.Quaternion(0.0, 0.0, 0.38268343, 0.92387953)),
        ),
        t.TransformStamped(
            header=header("head"), child_frame_id="camera_optical",
            transform=t.Transform(t.Vector3(0.05, 0.0, 0.0), t.Quaternion(-0.5, 0.5, -0.5, 0.5)),
        ),
    ])
    yield "point_stamped", t.PointStamped(header=header("base_link"), point=t.Point(1.25, -0.5, 0.875))
    yield "pose_stamped", t.PoseStamped(
        header=header("map"),
        pose=t.Pose(t.Point(2.0, 3.5, 0.0), t.Quaternion(0.0, 0.0, 0.6, 0.8)),
    )
    yield "marker_array", t.MarkerArray(markers=[
        t.Marker(header=header("base_link"), ns="pps", id=0, type=0, action=3),
        t.Marker(
            header=header("base_link"), ns="pps", id=4, type=8, action=0,
            pose=t.Pose(t.Point(0.5, 0.25, 1.0), t.Quaternion(0.0, 0.0, 0.0, 1.0)),
            scale=t.Vector3(0.008, 0.008, 0.008), color=t.ColorRGBA(1.0, 0.125, 0.125, 1.0),
            lifetime=t.Duration(sec=2, nanosec=500000000), frame_locked=True,
            points=[t.Point(1.0, 2.0, 3.0), t.Point(-1.0, 0.5, 0.25)],
            colors=[t.ColorRGBA(0.0, 0.5, 1.0, 0.75)],
            texture_resource="embedded://tex",
            texture=t.CompressedImage(header=header("t"), format="png", data=bytes([137, 80, 78])),
            uv_coordinates=[t.UVCoordinate(0.25, 0.75)],
            text="tag", mesh_resource="package://pps/mesh.dae",
            mesh_file=t.MeshFile(filename="m.stl", data=bytes([1, 2, 3, 4, 5])),
            mesh_use_embedded_materials=True,
        ),
    ])
    yield "marker_array_humble", t.HumbleMarkerArray(markers=[
        t.HumbleMarker(
            header=header("base_link"), ns="pps", id=4, type=8, action=0,
            pose=t.Pose(t.Point(0.5, 0.25, 1.0), t.Quaternion(0.0, 0.0, 0.0, 1.0)),
            scale=t.Vector3(0.008, 0.008, 0.008), color=t.ColorRGBA(1.0, 0.125, 0.125, 1.0),
            lifetime=t.Duration(sec=2, nanosec=500000000), frame_locked=True,
            points=[t.Point(1.0, 2.0, 3.0), t.Point(-1.0, 0.5, 0.25)],
            colors=[t.ColorRGBA(0.0, 0.5, 1.0, 0.75)],
            text="tag", mesh_resource="package://pps/mesh.dae", mesh_use_embedded_materials=True,
        ),
    ])
    yield "tag_reads", t.TagReads(stamp=STAMP, reads=[
        t.TagRead(epc="E20034120000000000001001", rssi_dbm=-47.5, antenna=1),
        t.TagRead(epc="355AB1C6", rssi_dbm=-61.25, antenna=3),
    ])
    yield "tag_entry", t.TagEntry(
        stamp=STAMP, epc="E20034120000000000001001", ambiguous=True, revision="r3",
        entry_json='{"epc":"E20034120000000000001001"}', unavailable_actions=["on", "off"],
        error="",
    )
    yield "trial", t.Trial(trial_json='{"id":"7d1f2b9e-4c3a-4e55-9a41-0c2d9b6e8f10"}')


def main():
    out = pathlib.Path(__file__).resolve().parent.parent / "fixtures"
    out.mkdir(exist_ok=True)
    for name, message in messages():
        (out / f"{name}.cdr").write_bytes(message.serialize(use_version_2=False))
        print(f"{name}.cdr: {type(message).__idl_annotations__.get('typename', type(message).__name__)}")


if __name__ == "__main__":
    main()
