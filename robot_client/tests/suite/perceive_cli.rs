//! `pps-robot scene` and `pps-robot perceive` as a user runs them.

use std::path::Path;
use std::process::{Command, Output};

fn pps_robot(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pps-robot")).args(args).output().expect("the binary runs")
}

fn export_scene(dir: &Path, device: &str) -> serde_json::Value {
    export_scene_with(dir, device, &[])
}

fn export_scene_with(dir: &Path, device: &str, extra: &[&str]) -> serde_json::Value {
    let out = dir.to_str().expect("a UTF-8 temp path");
    let mut args =
        vec!["scene", "--device", device, "--from", "left", "--seed", "3", "--small", "--out", out];
    args.extend_from_slice(extra);
    let exported = pps_robot(&args);
    assert!(exported.status.success(), "{}", String::from_utf8_lossy(&exported.stderr));
    serde_json::from_slice(&std::fs::read(dir.join("scene.json")).expect("scene.json written"))
        .expect("scene.json is JSON")
}

fn perceive(dir: &Path, target: &str, extra: &[&str]) -> Output {
    perceive_from(dir, "--cloud", "cloud.ply", target, extra)
}

/// `perceive` on `dir`'s image.png and camera.json, with `range_flag` (`--cloud` or `--depth`)
/// naming `range_file` in `dir`.
fn perceive_from(
    dir: &Path,
    range_flag: &str,
    range_file: &str,
    target: &str,
    extra: &[&str],
) -> Output {
    let file = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let (image, range, camera) = (file("image.png"), file(range_file), file("camera.json"));
    let mut args = vec![
        "perceive", "--image", &image, range_flag, &range, "--camera", &camera, "--target", target,
    ];
    args.extend_from_slice(extra);
    pps_robot(&args)
}

fn fails_saying(output: Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "should fail: {stderr}");
    assert!(stderr.contains(expected), "stderr {stderr:?} should say {expected:?}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(output.stdout.is_empty(), "nothing on stdout");
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
    assert!(
        text.contains("what to do: nothing red near the target: check that --target"),
        "{text}"
    );
}

#[test]
fn bad_input_is_a_clear_error_and_a_failing_exit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = export_scene(dir.path(), "lamp");
    let target = target_of(&scene);
    fails_saying(perceive(dir.path(), &target, &["--hsv", "340,20,0.6,1.0,0.15"]), "--hsv takes 6");
    fails_saying(
        perceive(dir.path(), &target, &["--hsv", "340,20,157,255,34,255"]),
        "fractions 0..1",
    );
    fails_saying(perceive(dir.path(), "1.0,2.0", &[]), "--target takes 3");
    fails_saying(
        perceive(dir.path(), &target, &["--depth-noise-at-1m", "0.5"]),
        "not a depth camera's noise at 1 m",
    );
    fails_saying(
        perceive(dir.path(), &target, &["--largest-tag", "5,8"]),
        "not a tag's width and height",
    );
    // A negative number is a value the person gave, answered as one, not taken for a flag.
    fails_saying(
        perceive(dir.path(), &target, &["--largest-tag", "-0.05,0.08"]),
        "not a tag's width and height",
    );
    fails_saying(
        perceive(dir.path(), &target, &["--depth-noise-at-1m", "-0.002"]),
        "not a depth camera's noise at 1 m",
    );

    // The files are read camera, image, cloud: break them last to first.
    std::fs::write(dir.path().join("cloud.ply"), "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n").unwrap();
    fails_saying(perceive(dir.path(), &target, &["--json"]), "ends at vertex 1");
    std::fs::remove_file(dir.path().join("image.png")).unwrap();
    fails_saying(perceive(dir.path(), &target, &["--json"]), "image.png");
    std::fs::write(dir.path().join("camera.json"), "{\"width\": 320}").unwrap();
    fails_saying(perceive(dir.path(), &target, &["--json"]), "camera.json");
}

#[test]
fn a_towel_is_not_taken_for_a_tag_in_a_home_whose_largest_tag_is_a_patch() {
    let dir = tempfile::tempdir().unwrap();
    // The simulator's towel is 16 × 24 cm.
    let scene = export_scene(dir.path(), "drawer");
    let target = target_of(&scene);
    let towels = json_of(&perceive(dir.path(), &target, &["--json", "--largest-tag", "0.2,0.3"]));
    assert!(towels["tag"].is_object(), "{towels}");
    let patches =
        json_of(&perceive(dir.path(), &target, &["--json", "--largest-tag", "0.05,0.05"]));
    assert!(patches["tag"].is_null(), "{patches}");
    let notes = patches["tag_notes"].to_string();
    assert!(notes.contains("larger than any tag"), "{notes}");
    let said = perceive(dir.path(), &target, &["--largest-tag", "0.05,0.05"]);
    let text = String::from_utf8(said.stdout).unwrap();
    assert!(
        text.contains("what to do: the tag could not be told from the red thing nearest"),
        "{text}"
    );
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
    fails_saying(
        output,
        "image.png: the image is 320×240 pixels but the camera calibration is for 640×240",
    );
}

/// The `--json` document's numbers that say where the robot goes: the tag's centroid, the
/// backing plane's normal and offset, the waypoint and its yaw.
fn answer(report: &serde_json::Value) -> Vec<f64> {
    let numbers = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array().expect("an array").iter().map(|x| x.as_f64().expect("a number")).collect()
    };
    let mut out = numbers(&report["tag"]["centroid"]);
    out.extend(numbers(&report["backing_plane"]["normal"]));
    out.push(report["backing_plane"]["offset"].as_f64().expect("an offset"));
    out.extend(numbers(&report["waypoint"]["position"]));
    out.push(report["waypoint"]["yaw"].as_f64().expect("a yaw"));
    out
}

fn json_of(output: &Output) -> serde_json::Value {
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    serde_json::from_slice(&output.stdout).expect("stdout is one JSON document")
}

#[test]
fn depth_as_png_or_pfm_gives_the_answer_of_the_same_frame_as_a_cloud() {
    for device in ["drawer", "light-switch"] {
        let dir = tempfile::tempdir().unwrap();
        let scene = export_scene_with(dir.path(), device, &["--depth"]);
        let target = target_of(&scene);
        // The same frame's points as a cloud, with the noise model `--depth` takes by default.
        let d435 = ["--json", "--depth-noise-at-1m", "0.0036"];
        let from_cloud =
            json_of(&perceive_from(dir.path(), "--cloud", "depth.ply", &target, &d435));
        let expected = answer(&from_cloud);
        for depth in ["depth.png", "depth.pfm"] {
            let report =
                json_of(&perceive_from(dir.path(), "--depth", depth, &target, &["--json"]));
            let got = answer(&report);
            let worst = got.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            // Millimetres, unit normals and radians alike: 1 mm, or a thousandth.
            assert!(worst < 1e-3, "{device} from {depth}: {got:?} against {expected:?}");
            let points = |r: &serde_json::Value| r["tag"]["points"].as_u64().unwrap();
            assert_eq!(points(&report), points(&from_cloud), "{device} from {depth}");
            assert!(report["timings_ms"]["depth_to_cloud"].as_f64().unwrap() >= 0.0);
        }
    }
}

#[test]
fn cloud_and_depth_together_or_neither_is_one_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let scene = export_scene_with(dir.path(), "lamp", &["--depth"]);
    let target = target_of(&scene);
    let depth = dir.path().join("depth.png").to_string_lossy().into_owned();
    let both = perceive(dir.path(), &target, &["--depth", &depth]);
    fails_saying(both, "cannot be used with");
    let file = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let (image, camera) = (file("image.png"), file("camera.json"));
    let neither =
        pps_robot(&["perceive", "--image", &image, "--camera", &camera, "--target", &target]);
    fails_saying(neither, "--cloud <CLOUD>|--depth <DEPTH>");
    // A colour PNG given as depth, and a depth of another size, say what is wrong.
    fails_saying(
        perceive_from(dir.path(), "--depth", "image.png", &target, &[]),
        "8-bit Rgb; depth in millimetres takes 16-bit greyscale",
    );
    let mut small = b"Pf\n2 2\n-1\n".to_vec();
    small.extend_from_slice(&[0; 16]);
    std::fs::write(dir.path().join("small.pfm"), small).unwrap();
    fails_saying(
        perceive_from(dir.path(), "--depth", "small.pfm", &target, &[]),
        "small.pfm: the image is 2×2 pixels but the camera calibration is for 320×240",
    );
}

/// A PNG of a few hundred bytes whose header declares `width`×`height` grey pixels: the data
/// holds one pixel, so only a reader that decodes before it checks would ever allocate the
/// rest.
fn png_declaring(path: &Path, width: u32, height: u32) {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
    encoder.set_color(png::ColorType::Grayscale);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&[0]).unwrap();
    writer.finish().unwrap();
    // IHDR's data follows the 8-byte signature, its length and its type; its CRC covers type
    // and data.
    bytes[16..20].copy_from_slice(&width.to_be_bytes());
    bytes[20..24].copy_from_slice(&height.to_be_bytes());
    let crc = crc32(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(path, bytes).unwrap();
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

#[test]
fn an_image_declaring_30000_by_30000_pixels_is_refused_before_it_is_decoded() {
    let dir = tempfile::tempdir().unwrap();
    let scene = export_scene_with(dir.path(), "drawer", &["--depth"]);
    let target = target_of(&scene);
    let image = dir.path().join("image.png");
    let colour = std::fs::read(&image).unwrap();
    png_declaring(&image, 30000, 30000);
    // Against the scene's 320×240 calibration: refused as another camera's.
    fails_saying(
        perceive(dir.path(), &target, &[]),
        "image.png: the image is 30000×30000 pixels but the camera calibration is for 320×240",
    );
    // With a calibration that matches it: refused by the cap.
    let camera_json = dir.path().join("camera.json");
    let text = std::fs::read_to_string(&camera_json).unwrap();
    let huge = text
        .replace("\"width\": 320", "\"width\": 30000")
        .replace("\"height\": 240", "\"height\": 30000");
    std::fs::write(&camera_json, huge).unwrap();
    fails_saying(
        perceive(dir.path(), &target, &[]),
        "image.png: it declares 30000×30000 pixels, more than the 16777216 (4096×4096) an image may have",
    );
    // The same for the depth image, the colour image being of a size the cap allows.
    std::fs::write(&camera_json, text).unwrap();
    std::fs::write(&image, colour).unwrap();
    png_declaring(&dir.path().join("depth.png"), 30000, 30000);
    fails_saying(
        perceive_from(dir.path(), "--depth", "depth.png", &target, &[]),
        "depth.png: the image is 30000×30000 pixels but the camera calibration is for 320×240",
    );
}
