//! `pps-robot scene` and `pps-robot perceive` as a user runs them.

use std::path::Path;
use std::process::{Command, Output};

fn pps_robot(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pps-robot")).args(args).output().expect("the binary runs")
}

fn export_scene(dir: &Path, device: &str) -> serde_json::Value {
    let out = dir.to_str().expect("a UTF-8 temp path");
    let exported = pps_robot(&[
        "scene", "--device", device, "--from", "left", "--seed", "3", "--small", "--out", out,
    ]);
    assert!(exported.status.success(), "{}", String::from_utf8_lossy(&exported.stderr));
    serde_json::from_slice(&std::fs::read(dir.join("scene.json")).expect("scene.json written"))
        .expect("scene.json is JSON")
}

fn perceive(dir: &Path, target: &str, extra: &[&str]) -> Output {
    let file = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let (image, cloud, camera) = (file("image.png"), file("cloud.ply"), file("camera.json"));
    let mut args = vec![
        "perceive", "--image", &image, "--cloud", &cloud, "--camera", &camera, "--target", target,
    ];
    args.extend_from_slice(extra);
    pps_robot(&args)
}

fn target_of(scene: &serde_json::Value) -> String {
    let t = scene["target"].as_array().expect("target");
    t.iter().map(|v| v.as_f64().expect("number").to_string()).collect::<Vec<_>>().join(",")
}

#[test]
fn perceive_json_has_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let scene = export_scene(dir.path(), "drawer");
    let output = perceive(dir.path(), &target_of(&scene), &["--json"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    // One JSON document and nothing else on stdout.
    let report: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("stdout is one JSON document");
    let truth: Vec<f64> =
        scene["tag_truth"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let centroid: Vec<f64> =
        report["tag"]["centroid"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let error = centroid.iter().zip(&truth).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
    assert!(error < 0.02, "tag {centroid:?} vs truth {truth:?}");
    assert!(report["tag"]["points"].as_u64().unwrap() > 10);
    let normal = report["backing_plane"]["normal"].as_array().unwrap();
    assert_eq!(normal.len(), 3);
    // The normal points toward the robot, whose base is at the origin in front of the drawer.
    assert!(normal[0].as_f64().unwrap() < -0.8, "{normal:?}");
    assert!(
        report["backing_plane"]["offset"].is_number()
            && report["backing_plane"]["points"].as_u64().unwrap() >= 100
    );
    assert_eq!(report["waypoint"]["position"].as_array().unwrap().len(), 3);
    assert!(report["waypoint"]["yaw"].is_number());
    assert!(report["load_ms"].as_f64().unwrap() >= 0.0);
    let timings = report["timings_ms"].as_object().unwrap();
    for step in [
        "segment",
        "morphology",
        "project",
        "occupancy_grid",
        "components",
        "volume_of_interest",
        "ransac",
    ] {
        assert!(timings[step].as_f64().unwrap() >= 0.0, "{step}");
    }
    assert!(!timings.contains_key("load"), "loading is load_ms, not a compute step");
}

#[test]
fn perceive_reports_null_when_no_tag_is_near_the_target_and_prints_a_summary_without_json() {
    let dir = tempfile::tempdir().unwrap();
    export_scene(dir.path(), "trash-can");
    // A target up in the air, far from everything red.
    let output = perceive(dir.path(), "0.5,-1.0,2.0", &["--json"]);
    assert!(output.status.success());
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert!(
        report["tag"].is_null()
            && report["backing_plane"].is_null()
            && report["waypoint"].is_null()
    );
    let summary = perceive(dir.path(), "0.5,-1.0,2.0", &[]);
    let text = String::from_utf8(summary.stdout).unwrap();
    assert!(text.contains("tag: none found"), "{text}");
}

#[test]
fn bad_input_is_a_clear_error_and_a_failing_exit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = export_scene(dir.path(), "lamp");
    let target = target_of(&scene);
    let fails_saying = |output: Output, expected: &str| {
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(!output.status.success(), "should fail: {stderr}");
        assert!(stderr.contains(expected), "stderr {stderr:?} should say {expected:?}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(output.stdout.is_empty(), "nothing on stdout");
    };
    fails_saying(perceive(dir.path(), &target, &["--hsv", "340,20,0.6,1.0,0.15"]), "--hsv takes 6");
    fails_saying(
        perceive(dir.path(), &target, &["--hsv", "340,20,157,255,34,255"]),
        "fractions 0..1",
    );
    fails_saying(perceive(dir.path(), "1.0,2.0", &[]), "--target takes 3");

    // The files are read image, cloud, camera: break them last to first.
    std::fs::write(dir.path().join("camera.json"), "{\"width\": 320}").unwrap();
    fails_saying(perceive(dir.path(), &target, &["--json"]), "camera.json");
    std::fs::write(dir.path().join("cloud.ply"), "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n").unwrap();
    fails_saying(perceive(dir.path(), &target, &["--json"]), "ends at vertex 1");
    std::fs::remove_file(dir.path().join("image.png")).unwrap();
    fails_saying(perceive(dir.path(), &target, &["--json"]), "image.png");
}

#[test]
fn an_image_of_another_size_than_the_calibration_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = export_scene(dir.path(), "drawer");
    let camera = dir.path().join("camera.json");
    let text =
        std::fs::read_to_string(&camera).unwrap().replace("\"width\": 320", "\"width\": 640");
    std::fs::write(&camera, text).unwrap();
    let output = perceive(dir.path(), &target_of(&scene), &["--json"]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("calibration is for (640, 240)"));
}
