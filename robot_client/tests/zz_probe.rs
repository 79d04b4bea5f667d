use pps_robot::hal::*;
use pps_robot::sim::*;
#[test]
fn probe() {
    let t = std::time::Instant::now();
    let room = Room::paper();
    println!("room {:?}", t.elapsed());
    let s = CaptureSettings::small();
    let pose = start_pose(room.device(DeviceKind::Drawer), StartDirection::Left, 1.5);
    let robot = SimRobot::with_geometry(
        room,
        pose,
        BodyGeometry { camera: s.camera, laser: s.laser, ..BodyGeometry::default() },
        1,
    );
    let t = std::time::Instant::now();
    let _ = robot.capture(true).unwrap();
    println!("image {:?}", t.elapsed());
    let t = std::time::Instant::now();
    let c = robot.scan(&s.sweep).unwrap();
    println!("scan {:?} {}", t.elapsed(), c.len());
}
