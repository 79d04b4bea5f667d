"""The ROS 2 messages pps-ros2 speaks, declared for Cyclone DDS's Python binding as ROS 2's
rosidl generates them for DDS: type `<pkg>::msg::dds_::<Type>_`, fields in `.msg` order.
Layouts of ROS 2 Jazzy (visualization_msgs/Marker with its texture and mesh-file fields);
Humble's Marker is HumbleMarker at the end."""

from dataclasses import dataclass, field

from cyclonedds.idl import IdlStruct, types


def ros_type(package, name):
    return f"{package}::msg::dds_::{name}_"


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: types.int32 = 0
    nanosec: types.uint32 = 0


@dataclass
class Duration(IdlStruct, typename="builtin_interfaces::msg::dds_::Duration_"):
    sec: types.int32 = 0
    nanosec: types.uint32 = 0


@dataclass
class Header(IdlStruct, typename=ros_type("std_msgs", "Header")):
    stamp: Time = field(default_factory=Time)
    frame_id: str = ""


@dataclass
class ColorRGBA(IdlStruct, typename=ros_type("std_msgs", "ColorRGBA")):
    r: types.float32 = 0.0
    g: types.float32 = 0.0
    b: types.float32 = 0.0
    a: types.float32 = 0.0


@dataclass
class Point(IdlStruct, typename=ros_type("geometry_msgs", "Point")):
    x: types.float64 = 0.0
    y: types.float64 = 0.0
    z: types.float64 = 0.0


@dataclass
class Vector3(IdlStruct, typename=ros_type("geometry_msgs", "Vector3")):
    x: types.float64 = 0.0
    y: types.float64 = 0.0
    z: types.float64 = 0.0


@dataclass
class Quaternion(IdlStruct, typename=ros_type("geometry_msgs", "Quaternion")):
    x: types.float64 = 0.0
    y: types.float64 = 0.0
    z: types.float64 = 0.0
    w: types.float64 = 1.0


@dataclass
class Pose(IdlStruct, typename=ros_type("geometry_msgs", "Pose")):
    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)


@dataclass
class PoseStamped(IdlStruct, typename=ros_type("geometry_msgs", "PoseStamped")):
    header: Header = field(default_factory=Header)
    pose: Pose = field(default_factory=Pose)


@dataclass
class PointStamped(IdlStruct, typename=ros_type("geometry_msgs", "PointStamped")):
    header: Header = field(default_factory=Header)
    point: Point = field(default_factory=Point)


@dataclass
class Transform(IdlStruct, typename=ros_type("geometry_msgs", "Transform")):
    translation: Vector3 = field(default_factory=Vector3)
    rotation: Quaternion = field(default_factory=Quaternion)


@dataclass
class TransformStamped(IdlStruct, typename=ros_type("geometry_msgs", "TransformStamped")):
    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    transform: Transform = field(default_factory=Transform)


@dataclass
class TFMessage(IdlStruct, typename=ros_type("tf2_msgs", "TFMessage")):
    transforms: types.sequence[TransformStamped] = field(default_factory=list)


@dataclass
class Image(IdlStruct, typename=ros_type("sensor_msgs", "Image")):
    header: Header = field(default_factory=Header)
    height: types.uint32 = 0
    width: types.uint32 = 0
    encoding: str = ""
    is_bigendian: types.uint8 = 0
    step: types.uint32 = 0
    data: types.sequence[types.uint8] = field(default_factory=bytes)


@dataclass
class RegionOfInterest(IdlStruct, typename=ros_type("sensor_msgs", "RegionOfInterest")):
    x_offset: types.uint32 = 0
    y_offset: types.uint32 = 0
    height: types.uint32 = 0
    width: types.uint32 = 0
    do_rectify: bool = False


@dataclass
class CameraInfo(IdlStruct, typename=ros_type("sensor_msgs", "CameraInfo")):
    header: Header = field(default_factory=Header)
    height: types.uint32 = 0
    width: types.uint32 = 0
    distortion_model: str = ""
    d: types.sequence[types.float64] = field(default_factory=list)
    k: types.array[types.float64, 9] = field(default_factory=lambda: [0.0] * 9)
    r: types.array[types.float64, 9] = field(default_factory=lambda: [0.0] * 9)
    p: types.array[types.float64, 12] = field(default_factory=lambda: [0.0] * 12)
    binning_x: types.uint32 = 0
    binning_y: types.uint32 = 0
    roi: RegionOfInterest = field(default_factory=RegionOfInterest)


@dataclass
class CompressedImage(IdlStruct, typename=ros_type("sensor_msgs", "CompressedImage")):
    header: Header = field(default_factory=Header)
    format: str = ""
    data: types.sequence[types.uint8] = field(default_factory=bytes)


@dataclass
class PointField(IdlStruct, typename=ros_type("sensor_msgs", "PointField")):
    name: str = ""
    offset: types.uint32 = 0
    datatype: types.uint8 = 0
    count: types.uint32 = 0


@dataclass
class PointCloud2(IdlStruct, typename=ros_type("sensor_msgs", "PointCloud2")):
    header: Header = field(default_factory=Header)
    height: types.uint32 = 0
    width: types.uint32 = 0
    fields: types.sequence[PointField] = field(default_factory=list)
    is_bigendian: bool = False
    point_step: types.uint32 = 0
    row_step: types.uint32 = 0
    data: types.sequence[types.uint8] = field(default_factory=bytes)
    is_dense: bool = False


@dataclass
class UVCoordinate(IdlStruct, typename=ros_type("visualization_msgs", "UVCoordinate")):
    u: types.float32 = 0.0
    v: types.float32 = 0.0


@dataclass
class MeshFile(IdlStruct, typename=ros_type("visualization_msgs", "MeshFile")):
    filename: str = ""
    data: types.sequence[types.uint8] = field(default_factory=bytes)


@dataclass
class Marker(IdlStruct, typename=ros_type("visualization_msgs", "Marker")):
    header: Header = field(default_factory=Header)
    ns: str = ""
    id: types.int32 = 0
    type: types.int32 = 0
    action: types.int32 = 0
    pose: Pose = field(default_factory=Pose)
    scale: Vector3 = field(default_factory=Vector3)
    color: ColorRGBA = field(default_factory=ColorRGBA)
    lifetime: Duration = field(default_factory=Duration)
    frame_locked: bool = False
    points: types.sequence[Point] = field(default_factory=list)
    colors: types.sequence[ColorRGBA] = field(default_factory=list)
    texture_resource: str = ""
    texture: CompressedImage = field(default_factory=CompressedImage)
    uv_coordinates: types.sequence[UVCoordinate] = field(default_factory=list)
    text: str = ""
    mesh_resource: str = ""
    mesh_file: MeshFile = field(default_factory=MeshFile)
    mesh_use_embedded_materials: bool = False


@dataclass
class MarkerArray(IdlStruct, typename=ros_type("visualization_msgs", "MarkerArray")):
    markers: types.sequence[Marker] = field(default_factory=list)


@dataclass
class TagRead(IdlStruct, typename=ros_type("pps_msgs", "TagRead")):
    epc: str = ""
    rssi_dbm: types.float64 = 0.0
    antenna: types.uint8 = 0


@dataclass
class TagReads(IdlStruct, typename=ros_type("pps_msgs", "TagReads")):
    stamp: Time = field(default_factory=Time)
    reads: types.sequence[TagRead] = field(default_factory=list)


@dataclass
class TagEntry(IdlStruct, typename=ros_type("pps_msgs", "TagEntry")):
    stamp: Time = field(default_factory=Time)
    epc: str = ""
    ambiguous: bool = False
    revision: str = ""
    entry_json: str = ""
    unavailable_actions: types.sequence[str] = field(default_factory=list)
    error: str = ""


@dataclass
class Trial(IdlStruct, typename=ros_type("pps_msgs", "Trial")):
    trial_json: str = ""


@dataclass
class HumbleMarker(IdlStruct, typename=ros_type("visualization_msgs", "Marker")):
    """Marker as ROS 2 Humble lays it out: no texture, UV coordinates or mesh file."""
    header: Header = field(default_factory=Header)
    ns: str = ""
    id: types.int32 = 0
    type: types.int32 = 0
    action: types.int32 = 0
    pose: Pose = field(default_factory=Pose)
    scale: Vector3 = field(default_factory=Vector3)
    color: ColorRGBA = field(default_factory=ColorRGBA)
    lifetime: Duration = field(default_factory=Duration)
    frame_locked: bool = False
    points: types.sequence[Point] = field(default_factory=list)
    colors: types.sequence[ColorRGBA] = field(default_factory=list)
    text: str = ""
    mesh_resource: str = ""
    mesh_use_embedded_materials: bool = False


@dataclass
class HumbleMarkerArray(IdlStruct, typename=ros_type("visualization_msgs", "MarkerArray")):
    markers: types.sequence[HumbleMarker] = field(default_factory=list)
