"""The approach's perception chain in OpenCV and Open3D: the peer `pps-scenes bench` is compared
with. Each step does what the Rust step of the same name does, with the same parameters, through
the libraries' own calls wherever they have one (colour conversion, morphology, voxel grid,
DBSCAN for 3D components, RANSAC plane segmentation); the rest is NumPy.

    python chain.py [--window] SCENE_DIR [SCENE_DIR ...]

reads each directory `pps-scenes write` made (image.png, cloud.ply, camera.json, truth.json,
scene.json, and depth.png for an RGB-D scene, whose cloud it then makes from the depth with
Open3D, smooths along the rays around the target as the Rust chain does, and judges with
tolerances from the sensor's noise model in scene.json) and prints
the median and p95 of every step in milliseconds, then the whole chain's, and each scene's whole
chain by its directory's name, as JSON.

With --window, an RGB-D frame is read as the Rust chain's organised path reads it: only the
pixels whose rays can meet the box around the target (and, for the collision check, the box
around the robot at the waypoint) become points, the rest of the depth image zeroed before
Open3D makes the cloud.
"""

import json
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import open3d as o3d

# The Rust defaults (perception/tag.rs, navigation/approach.rs, navigation/ransac.rs).
HUE_DEG = (340.0, 20.0)
SATURATION_MIN = 0.6
VALUE_MIN = 0.15
CLOSE_RADIUS_PX = 2
OPEN_RADIUS_PX = 1
OCCLUSION_CELL_RAD = 0.008
OCCLUSION_TOLERANCE_M = 0.03
VOXEL_M = 0.01
MIN_TAG_POINTS = 10
VOI_RADIUS_M = 0.5
VOI_HALF_HEIGHT_M = 0.5
INLIER_M = 0.015
MAX_ITERATIONS = 400
CONFIDENCE = 0.995
MAX_PLANES = 12
MIN_PLANE_POINTS = 300
STANDOFF_M = 0.5
BASE_HALF = (0.25, 0.25)
BODY_HEIGHT_M = 1.6
FLOOR_CLEARANCE_M = 0.04
# The tag's reach around the target (perception/tag.rs: max_distance + fragment_gap).
TAG_REACH_M = 0.53
# Ray smoothing (perception/ray_smoothing.rs, depth_noise.rs).
SMOOTHED_SIGMA_M = 0.01
MAX_SMOOTHING_WINDOW = 24
MIN_BLOCK_POINTS = 6
SURFACE_SIGMAS = 3.0


class Timings:
    def __init__(self):
        self.steps = {}

    def time(self, name, f):
        start = time.perf_counter()
        result = f()
        self.steps[name] = (time.perf_counter() - start) * 1000.0
        return result


def read_ply(path):
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    if not any(line.startswith("format binary_little_endian") for line in header):
        raise SystemExit(f"{path}: only binary little-endian PLY is read here")
    return np.frombuffer(data, dtype="<f4", count=count * 3, offset=end).reshape(count, 3)


def quaternion_matrix(x, y, z, w):
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def segment(bgr):
    # OpenCV's full-range hue: 0..255 for 0..360°.
    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV_FULL)
    lo, hi = (round(h / 360.0 * 255.0) for h in HUE_DEG)
    s, v = round(SATURATION_MIN * 255), round(VALUE_MIN * 255)
    upper = cv2.inRange(hsv, (lo, s, v), (255, 255, 255))
    lower = cv2.inRange(hsv, (0, s, v), (hi, 255, 255))
    return cv2.bitwise_or(upper, lower)


def morphology(mask):
    # Hole filling: flood the background from the border; what it cannot reach is a hole.
    padded = cv2.copyMakeBorder(mask, 1, 1, 1, 1, cv2.BORDER_CONSTANT, value=0)
    flood = padded.copy()
    cv2.floodFill(flood, None, (0, 0), 255)
    filled = cv2.bitwise_or(padded, cv2.bitwise_not(flood))[1:-1, 1:-1]
    disc = lambda r: cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    closed = cv2.morphologyEx(filled, cv2.MORPH_CLOSE, disc(CLOSE_RADIUS_PX))
    return cv2.morphologyEx(closed, cv2.MORPH_OPEN, disc(OPEN_RADIUS_PX))


def packed(cells):
    """Integer cells (rows of 2 or 3, |c| < 2**20) as one int64 each, for fast 1-D set operations."""
    key = np.zeros(len(cells), dtype=np.int64)
    for column in range(cells.shape[1]):
        key = (key << 21) | (cells[:, column] + (1 << 20))
    return key


def project(points, mask, camera, occlusion_tolerance=OCCLUSION_TOLERANCE_M):
    t = np.array(camera["base_from_camera"]["translation"])
    r = quaternion_matrix(*camera["base_from_camera"]["rotation_xyzw"])
    in_camera = (points - t) @ r
    z = in_camera[:, 2]
    ahead = z > 1e-3
    u = camera["fx"] * in_camera[:, 0] / np.where(ahead, z, 1) + camera["cx"]
    v = camera["fy"] * in_camera[:, 1] / np.where(ahead, z, 1) + camera["cy"]
    inside = ahead & (u >= 0) & (u < camera["width"]) & (v >= 0) & (v < camera["height"])
    # Occlusion: a point counts only if it is near the nearest depth of its angular cell.
    depth = np.linalg.norm(in_camera, axis=1)
    idx = np.flatnonzero(inside)
    cells = np.stack(
        [
            np.floor(np.arctan2(in_camera[idx, 0], z[idx]) / OCCLUSION_CELL_RAD),
            np.floor(np.arctan2(in_camera[idx, 1], z[idx]) / OCCLUSION_CELL_RAD),
        ],
        axis=1,
    ).astype(np.int64)
    _, cell_of = np.unique(packed(cells), return_inverse=True)
    cell_of = cell_of.ravel()
    nearest = np.full(cell_of.max() + 1 if len(cell_of) else 0, np.inf)
    np.minimum.at(nearest, cell_of, depth[idx])
    seen = depth[idx] <= nearest[cell_of] + occlusion_tolerance
    idx = idx[seen]
    on_red = mask[v[idx].astype(np.int64), u[idx].astype(np.int64)] > 0
    return points[idx[on_red]]


def components(red_points, target):
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(red_points.astype(np.float64)))
    # Two points are neighbours when their voxels touch (26-connectivity of 1 cm voxels).
    labels = np.asarray(cloud.cluster_dbscan(eps=VOXEL_M * np.sqrt(3.0), min_points=1))
    best, best_distance = None, np.inf
    for label in range(labels.max() + 1 if len(labels) else 0):
        members = red_points[labels == label]
        if len(members) < MIN_TAG_POINTS:
            continue
        distance = np.linalg.norm(members.mean(axis=0) - target)
        if distance < best_distance:
            best, best_distance = members, distance
    return best


def volume_of_interest(points, target, tag):
    d = points - target
    inside = (np.hypot(d[:, 0], d[:, 1]) <= VOI_RADIUS_M) & (np.abs(d[:, 2]) <= VOI_HALF_HEIGHT_M)
    voi = points[inside]
    if tag is None:
        return voi
    own = packed(np.floor(tag / VOXEL_M).astype(np.int64))
    keys = packed(np.floor(voi / VOXEL_M).astype(np.int64))
    return voi[~np.isin(keys, own)]


def planes(surface, inlier=INLIER_M):
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(surface.astype(np.float64)))
    found = []
    while len(found) < MAX_PLANES and len(cloud.points) >= MIN_PLANE_POINTS:
        model, inliers = cloud.segment_plane(
            distance_threshold=inlier,
            ransac_n=3,
            num_iterations=MAX_ITERATIONS,
            probability=CONFIDENCE,
        )
        if len(inliers) < MIN_PLANE_POINTS:
            break
        found.append((np.array(model), np.asarray(cloud.select_by_index(inliers).points)))
        cloud = cloud.select_by_index(inliers, invert=True)
    return found


def backing_plane(found, tag, robot):
    centre = tag.mean(axis=0)
    best, best_fit = None, np.inf
    for model, inliers in found:
        normal, offset = model[:3], model[3]
        if normal @ robot + offset < 0:
            normal, offset = -normal, -offset
        if abs(normal[2]) > 0.5:  # a floor or a table top, not a front
            continue
        height = normal @ centre + offset
        spread = np.ptp(tag @ normal)
        fit = max(height, 0.0) + spread
        if fit < best_fit:
            best, best_fit = (normal, offset), fit
    return best


def waypoint(tag, plane):
    normal, _ = plane
    horizontal = np.array([normal[0], normal[1], 0.0])
    horizontal /= np.linalg.norm(horizontal)
    return tag.mean(axis=0) + STANDOFF_M * horizontal, -horizontal


def collision_check(points, position, heading):
    d = points[:, :2] - position[:2]
    along = d @ heading[:2]
    across = d @ np.array([-heading[1], heading[0]])
    body = (np.abs(along) <= BASE_HALF[0]) & (np.abs(across) <= BASE_HALF[1])
    tall = (points[:, 2] > FLOOR_CLEARANCE_M) & (points[:, 2] < BODY_HEIGHT_M)
    return int(np.count_nonzero(body & tall))


class DepthNoise:
    """σ(z) = floor + growth·z², the range sensor's model (perception/depth_noise.rs)."""

    def __init__(self, floor, growth):
        self.floor, self.growth = floor, growth

    def sigma_at(self, z):
        return self.floor + self.growth * z * z

    def smoothing_window(self, z):
        side = np.ceil(np.sqrt(3.0) * self.sigma_at(z) / SMOOTHED_SIGMA_M)
        return int(np.clip(side, 1, MAX_SMOOTHING_WINDOW))

    def smoothed_sigma_at(self, z):
        w = self.smoothing_window(z)
        sigma = self.sigma_at(z)
        return sigma if w == 1 else max(np.sqrt(3.0) * sigma / w, self.floor)


def smooth_along_rays(points, raw_mask, camera, target, window, noise):
    """Each point within the tag's reach of the target moved along its camera ray onto the plane
    in inverse depth (1/z affine in the pixel) that its window × window pixel block shows, the
    tag-coloured points (`raw_mask`) and the rest fitted apart; points beyond three σ of the fit
    keep their depth. The Rust step's algorithm, in NumPy: every block fitted at once from
    per-block sums (np.bincount), not a loop over blocks."""
    out = points.copy()
    inside = np.all(np.abs(points - target) <= TAG_REACH_M, axis=1)
    t = np.array(camera["base_from_camera"]["translation"])
    r = quaternion_matrix(*camera["base_from_camera"]["rotation_xyzw"])
    idx = np.flatnonzero(inside)
    q = (points[idx].astype(np.float64) - t) @ r
    ahead = q[:, 2] > 1e-6
    idx, q = idx[ahead], q[ahead]
    z = q[:, 2]
    u = camera["fx"] * q[:, 0] / z + camera["cx"]
    v = camera["fy"] * q[:, 1] / z + camera["cy"]
    in_image = (u >= 0) & (v >= 0) & (u < camera["width"]) & (v < camera["height"])
    tag = np.zeros(len(idx), dtype=bool)
    tag[in_image] = raw_mask[v[in_image].astype(np.int64), u[in_image].astype(np.int64)] > 0
    cells = np.stack([np.floor(u / window), np.floor(v / window), tag], axis=1).astype(np.int64)
    _, block = np.unique(packed(cells), return_inverse=True)
    block = block.ravel()
    blocks = block.max() + 1 if len(block) else 0
    count = np.bincount(block, minlength=blocks)
    # The median depth of each block: sorted by block, then depth; the upper middle one.
    order = np.lexsort((z, block))
    starts = np.concatenate([[0], np.cumsum(count)[:-1]])
    median = z[order[np.minimum(starts + count // 2, len(z) - 1)]] if len(z) else z
    on = np.abs(z - median[block]) <= SURFACE_SIGMAS * noise.sigma_at(median[block])
    sigma = SURFACE_SIGMAS * noise.sigma_at(z)
    fitted = count >= MIN_BLOCK_POINTS
    inverse = np.zeros(len(z))
    for _ in range(3):
        w = on.astype(np.float64)
        n = np.bincount(block, w, blocks)
        fitted &= n >= MIN_BLOCK_POINTS
        safe = np.where(n > 0, n, 1.0)
        mu, mv = np.bincount(block, w * u, blocks) / safe, np.bincount(block, w * v, blocks) / safe
        du, dv, iz = u - mu[block], v - mv[block], 1.0 / z
        s = lambda x: np.bincount(block, w * x, blocks)
        normal = np.empty((blocks, 3, 3))
        normal[:, 0, 0], normal[:, 1, 1], normal[:, 2, 2] = n, s(du * du), s(dv * dv)
        normal[:, 0, 1] = normal[:, 1, 0] = s(du)
        normal[:, 0, 2] = normal[:, 2, 0] = s(dv)
        normal[:, 1, 2] = normal[:, 2, 1] = s(du * dv)
        right = np.stack([s(iz), s(du * iz), s(dv * iz)], axis=1)
        fitted &= np.abs(np.linalg.det(normal)) > 1e-12
        normal[~fitted] = np.eye(3)
        c = np.linalg.solve(normal, right[:, :, None])[:, :, 0]
        inverse = c[block, 0] + c[block, 1] * du + c[block, 2] * dv
        with np.errstate(divide="ignore"):
            on = (inverse > 0) & (np.abs(z - 1.0 / inverse) <= sigma)
    move = fitted[block] & on
    moved = q[move] * (1.0 / inverse[move] / z[move])[:, None]
    out[idx[move]] = (moved @ r.T + t).astype(points.dtype)
    return out


def depth_to_cloud(depth, camera):
    """An RGB-D frame's aligned 16-bit depth (millimetres) as a base-frame cloud, through
    Open3D's own back-projection."""
    intrinsic = o3d.camera.PinholeCameraIntrinsic(
        camera["width"], camera["height"], camera["fx"], camera["fy"], camera["cx"], camera["cy"]
    )
    base_from_camera = np.eye(4)
    base_from_camera[:3, :3] = quaternion_matrix(*camera["base_from_camera"]["rotation_xyzw"])
    base_from_camera[:3, 3] = camera["base_from_camera"]["translation"]
    cloud = o3d.geometry.PointCloud.create_from_depth_image(
        o3d.geometry.Image(depth),
        intrinsic,
        extrinsic=np.linalg.inv(base_from_camera),
        depth_scale=1000.0,
        depth_trunc=10.0,
    )
    return np.asarray(cloud.points, dtype=np.float32)


def pixel_window(camera, lo, hi, pad):
    """The rows and columns of the pixels whose rays can meet the box from `lo` to `hi` (base
    frame), `pad` pixels wider; the whole image when a corner is not before the camera."""
    t = np.array(camera["base_from_camera"]["translation"])
    r = quaternion_matrix(*camera["base_from_camera"]["rotation_xyzw"])
    corners = np.array([[(lo, hi)[(c >> a) & 1][a] for a in range(3)] for c in range(8)])
    q = (corners - t) @ r
    w, h = camera["width"], camera["height"]
    if np.any(q[:, 2] <= 1e-3):
        return slice(0, h), slice(0, w)
    u = camera["fx"] * q[:, 0] / q[:, 2] + camera["cx"] - 0.5
    v = camera["fy"] * q[:, 1] / q[:, 2] + camera["cy"] - 0.5
    bound = lambda x, n: int(np.clip(x, 0, n))
    columns = slice(bound(np.floor(u.min()) - pad, w), bound(np.ceil(u.max()) + 1 + pad, w))
    rows = slice(bound(np.floor(v.min()) - pad, h), bound(np.ceil(v.max()) + 1 + pad, h))
    return rows, columns


def window_of(depth, window):
    cropped = np.zeros_like(depth)
    cropped[window] = depth[window]
    return cropped


def chain(scene, windowed=False):
    bgr = cv2.imread(str(scene / "image.png"), cv2.IMREAD_COLOR)
    camera = json.loads((scene / "camera.json").read_text())
    target = np.array(json.loads((scene / "truth.json").read_text())["target"])
    robot = np.array(camera["base_from_camera"]["translation"])
    described = json.loads((scene / "scene.json").read_text()).get("depth_noise")
    noise = DepthNoise(**described) if described else DepthNoise(0.004, 0.0)
    range_m = np.linalg.norm(target - robot)
    t = Timings()
    depth = None
    if (scene / "depth.png").exists():
        depth = cv2.imread(str(scene / "depth.png"), cv2.IMREAD_UNCHANGED)
        if windowed:
            pad = int(np.ceil(OCCLUSION_CELL_RAD * max(camera["fx"], camera["fy"]))) + 2
            box = pixel_window(camera, target - TAG_REACH_M, target + TAG_REACH_M, pad)
            points = t.time(
                "depth_to_cloud", lambda: depth_to_cloud(window_of(depth, box), camera)
            )
        else:
            points = t.time("depth_to_cloud", lambda: depth_to_cloud(depth, camera))
    else:
        points = read_ply(scene / "cloud.ply")
    raw = t.time("segment", lambda: segment(bgr))
    window = noise.smoothing_window(range_m)
    if window > 1:
        points = t.time(
            "ray_smoothing",
            lambda: smooth_along_rays(points, raw, camera, target, window, noise),
        )
    # The tolerances the Rust chain sizes by the noise left after smoothing.
    sigma = noise.smoothed_sigma_at(range_m)
    occlusion, inlier = max(OCCLUSION_TOLERANCE_M, 5 * sigma), max(INLIER_M, 2.5 * sigma)
    red = t.time("morphology", lambda: morphology(raw))
    red_points = t.time("project", lambda: project(points, red, camera, occlusion))
    t.time("occupancy_grid", lambda: o3d.geometry.VoxelGrid.create_from_point_cloud(
        o3d.geometry.PointCloud(o3d.utility.Vector3dVector(red_points.astype(np.float64))),
        VOXEL_M,
    ))
    tag = t.time("components", lambda: components(red_points, target))
    surface = t.time("volume_of_interest", lambda: volume_of_interest(points, target, tag))
    found = t.time("ransac", lambda: planes(surface, inlier))
    plane = t.time("backing_plane", lambda: None if tag is None else backing_plane(found, tag, robot))
    goal = t.time("waypoint", lambda: None if plane is None else waypoint(tag, plane))
    if goal is not None and windowed and depth is not None:
        def around_robot():
            reach = np.hypot(*BASE_HALF) + 0.01
            (x, y, _), _ = goal
            lo = np.array([x - reach, y - reach, FLOOR_CLEARANCE_M])
            hi = np.array([x + reach, y + reach, BODY_HEIGHT_M])
            near = depth_to_cloud(window_of(depth, pixel_window(camera, lo, hi, 1)), camera)
            return collision_check(near, *goal)

        t.time("collision_check", around_robot)
    elif goal is not None:
        t.time("collision_check", lambda: collision_check(points, *goal))
    return t.steps, goal is not None


def main(args):
    windowed = args[:1] == ["--window"]
    dirs = args[1:] if windowed else args
    steps, totals, planned, per_scene = {}, [], 0, {}
    for scene in map(Path, dirs):
        timed, ok = chain(scene, windowed)
        planned += ok
        for name, ms in timed.items():
            steps.setdefault(name, []).append(ms)
        totals.append(sum(timed.values()))
        per_scene[scene.name] = totals[-1]
    summary = {
        name: {"median": float(np.median(v)), "p95": float(np.percentile(v, 95, method="nearest"))}
        for name, v in [*steps.items(), ("whole chain", totals)]
    }
    print(json.dumps(
        {"scenes": len(dirs), "planned": planned, "steps": summary, "per_scene": per_scene},
        indent=2,
    ))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    main(sys.argv[1:])
