//! Trial pictures through HTTP: sent once by the robot that made the trial, read by whoever
//! may read the trial, bounded in size and kind, cached by ETag, and kept per tag.

use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, Response, StatusCode};
use serde_json::Value;

/// The start of a PNG of `width` × `height` (signature and header chunk), then `fill` bytes
/// of `seed`: what the registry reads of a picture, and different bytes for different seeds.
fn png(width: u32, height: u32, seed: u8, fill: usize) -> Vec<u8> {
    let mut bytes = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
    bytes.extend_from_slice(&width.to_be_bytes());
    bytes.extend_from_slice(&height.to_be_bytes());
    bytes.extend_from_slice(&[8, 2, 0, 0, 0, 0, 0, 0, 0]);
    bytes.extend(std::iter::repeat_n(seed, fill));
    bytes
}

async fn send_picture(
    server: &TestServer,
    trial: &str,
    token: &str,
    media_type: &str,
    bytes: Vec<u8>,
) -> Response {
    server
        .request(Method::PUT, &format!("/api/v1/trials/{trial}/picture"), Some(token))
        .header("content-type", media_type)
        .body(bytes)
        .send()
        .await
        .unwrap()
}

/// GET `path` as a browser that holds the picture under `etag` asks for it again.
async fn get_if_none_match(server: &TestServer, path: &str, token: &str, etag: &str) -> Response {
    server
        .request(Method::GET, path, Some(token))
        .header("if-none-match", etag)
        .send()
        .await
        .unwrap()
}

/// Records a trial of `el-e-1` on `epc`; returns its id.
async fn record_trial(server: &TestServer, robot: &str, epc: &str) -> String {
    let id = uuid();
    let body = trial(&id, epc, "el-e-1", "on", "push_top", "success");
    let response = server.put(&format!("/api/v1/trials/{id}"), robot, &body, None).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    id
}

#[tokio::test]
async fn the_robot_that_made_a_trial_sends_its_picture_once_and_readers_see_it() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let other_robot = server.token(Role::Robot, "el-e-2").await;
    let caretaker = server.token(Role::Caretaker, "nurse").await;
    let id = record_trial(&server, &robot, ADA_SWITCH).await;
    let path = format!("/api/v1/trials/{id}/picture");
    assert_eq!(server.get_json(&format!("/api/v1/trials/{id}")).await["picture"], Value::Null);
    problem(server.get(&path, &caretaker).await, StatusCode::NOT_FOUND).await;

    let picture = png(240, 180, 7, 2000);
    for stranger in [&other_robot, &caretaker, &server.admin] {
        let refused = send_picture(&server, &id, stranger, "image/png", picture.clone()).await;
        problem(refused, StatusCode::FORBIDDEN).await;
    }
    problem(server.get(&path, &caretaker).await, StatusCode::NOT_FOUND).await;

    let stored = send_picture(&server, &id, &robot, "image/png", picture.clone()).await;
    assert_eq!(stored.status(), StatusCode::CREATED);
    let stored: Value = stored.json().await.unwrap();
    assert_eq!(stored["picture"], path.as_str());
    assert_eq!(server.get_json(&format!("/api/v1/trials/{id}")).await["picture"], path.as_str());
    let listed = server.get_json(&format!("/api/v1/trials?epc={ADA_SWITCH}")).await;
    assert_eq!(listed["items"][0]["picture"], path.as_str());

    let again = send_picture(&server, &id, &robot, "image/png", picture.clone()).await;
    assert_eq!(again.status(), StatusCode::OK, "the outbox's retry is a no-op");
    let other = send_picture(&server, &id, &robot, "image/png", png(240, 180, 8, 2000)).await;
    problem(other, StatusCode::CONFLICT).await;

    let read = server.get(&path, &caretaker).await;
    assert_eq!(read.status(), StatusCode::OK);
    assert_eq!(read.headers()["content-type"], "image/png");
    assert_eq!(read.headers()["x-content-type-options"], "nosniff");
    assert!(read.headers()["cache-control"].to_str().unwrap().starts_with("private, max-age="));
    let etag = read.headers()["etag"].to_str().unwrap().to_owned();
    assert_eq!(read.bytes().await.unwrap().as_ref(), picture.as_slice(), "the bytes as sent");
    let own = server.get(&path, &robot).await;
    assert_eq!(own.status(), StatusCode::OK);
    problem(server.get(&path, &other_robot).await, StatusCode::FORBIDDEN).await;

    let cached = get_if_none_match(&server, &path, &caretaker, &etag).await;
    assert_eq!(cached.status(), StatusCode::NOT_MODIFIED);
    assert_eq!(cached.headers()["etag"], etag.as_str());
    assert!(cached.bytes().await.unwrap().is_empty());

    let unknown = uuid();
    let missing = send_picture(&server, &unknown, &robot, "image/png", picture).await;
    problem(missing, StatusCode::NOT_FOUND).await;
}

#[tokio::test]
async fn pictures_are_small_and_what_they_say_they_are() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let id = record_trial(&server, &robot, ADA_SWITCH).await;
    let cap = pps_server::trials::picture::MAX_PICTURE_BYTES;

    let header = png(10, 10, 0, 0).len();
    let too_big = send_picture(&server, &id, &robot, "image/png", png(10, 10, 1, cap - header + 1));
    let too_big = problem(too_big.await, StatusCode::PAYLOAD_TOO_LARGE).await;
    assert!(too_big["detail"].as_str().unwrap().contains("262144"), "{too_big}");
    let jpeg_bytes = vec![0xFF, 0xD8, 0xFF, 0xE0, 0, 4, 0, 0, 0xFF, 0xC0, 0, 11, 8, 0, 10, 0, 10];
    let disguised = send_picture(&server, &id, &robot, "image/png", jpeg_bytes).await;
    problem(disguised, StatusCode::UNSUPPORTED_MEDIA_TYPE).await;
    let svg = send_picture(&server, &id, &robot, "image/jpeg", b"<svg onload=x>".to_vec()).await;
    problem(svg, StatusCode::UNSUPPORTED_MEDIA_TYPE).await;
    let gif = send_picture(&server, &id, &robot, "image/gif", png(10, 10, 1, 10)).await;
    problem(gif, StatusCode::UNSUPPORTED_MEDIA_TYPE).await;
    let huge = send_picture(&server, &id, &robot, "image/png", png(8000, 10, 1, 10)).await;
    problem(huge, StatusCode::UNPROCESSABLE_ENTITY).await;

    let path = format!("/api/v1/trials/{id}/picture");
    problem(server.get(&path, &server.admin).await, StatusCode::NOT_FOUND).await;
    let at_cap = send_picture(&server, &id, &robot, "image/png", png(10, 10, 1, cap - header));
    assert_eq!(at_cap.await.status(), StatusCode::CREATED, "a picture of exactly the cap is fine");
}

#[tokio::test]
async fn a_tag_keeps_its_newest_pictures_and_every_trial() {
    let server = TestServer::start_keeping_pictures(2).await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let mut trials = Vec::new();
    for seed in 1..=3 {
        let id = record_trial(&server, &robot, ADA_SWITCH).await;
        let sent = send_picture(&server, &id, &robot, "image/png", png(20, 20, seed, 100)).await;
        assert_eq!(sent.status(), StatusCode::CREATED);
        trials.push(id);
    }
    let drawer = record_trial(&server, &robot, DRAWER).await;
    let sent = send_picture(&server, &drawer, &robot, "image/png", png(20, 20, 9, 100)).await;
    assert_eq!(sent.status(), StatusCode::CREATED);

    let picture_of = |id: &str| format!("/api/v1/trials/{id}/picture");
    let removed =
        problem(server.get(&picture_of(&trials[0]), &server.admin).await, StatusCode::NOT_FOUND);
    assert!(removed.await["detail"].as_str().unwrap().contains("newest 2 pictures"));
    let oldest = server.get_json(&format!("/api/v1/trials/{}", trials[0])).await;
    assert_eq!(oldest["picture"], Value::Null, "the trial stays, without its picture");
    for id in [&trials[1], &trials[2], &drawer] {
        assert_eq!(server.get(&picture_of(id), &server.admin).await.status(), StatusCode::OK);
    }

    // The outbox resending the removed picture is a retry; it does not come back.
    let resent = send_picture(&server, &trials[0], &robot, "image/png", png(20, 20, 1, 100)).await;
    assert_eq!(resent.status(), StatusCode::OK);
    let still_removed = server.get(&picture_of(&trials[0]), &server.admin).await;
    assert_eq!(still_removed.status(), StatusCode::NOT_FOUND);
    let other = send_picture(&server, &trials[0], &robot, "image/png", png(20, 20, 5, 100)).await;
    problem(other, StatusCode::CONFLICT).await;

    // A lower limit, as after a restart with fewer pictures per tag, is applied by the pass.
    assert_eq!(
        pps_server::trial_history::retention::keep_newest_pictures(&server.db, 1, server.now())
            .await
            .unwrap(),
        1
    );
    let second = server.get(&picture_of(&trials[1]), &server.admin).await;
    assert_eq!(second.status(), StatusCode::NOT_FOUND);
    assert_eq!(server.get(&picture_of(&trials[2]), &server.admin).await.status(), StatusCode::OK);
    assert_eq!(server.get(&picture_of(&drawer), &server.admin).await.status(), StatusCode::OK);
    let listed = server.get_json(&format!("/api/v1/trials?epc={ADA_SWITCH}")).await;
    assert_eq!(listed["items"].as_array().unwrap().len(), 3, "every trial stays");
}

#[tokio::test]
async fn a_tag_shows_people_the_newest_picture_of_its_trials() {
    let server = TestServer::start().await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let caretaker = server.token(Role::Caretaker, "nurse").await;
    let path = format!("/api/v1/tags/{ADA_SWITCH}/picture");
    problem(server.get(&path, &caretaker).await, StatusCode::NOT_FOUND).await;
    for seed in 1..=2 {
        let id = record_trial(&server, &robot, ADA_SWITCH).await;
        let sent = send_picture(&server, &id, &robot, "image/png", png(64, 48, seed, 100)).await;
        assert_eq!(sent.status(), StatusCode::CREATED);
    }

    let newest = server.get(&path, &caretaker).await;
    assert_eq!(newest.status(), StatusCode::OK);
    assert_eq!(newest.headers()["content-type"], "image/png");
    assert_eq!(newest.headers()["cache-control"], "private, no-cache");
    let etag = newest.headers()["etag"].to_str().unwrap().to_owned();
    assert_eq!(newest.bytes().await.unwrap().as_ref(), png(64, 48, 2, 100).as_slice());
    let cached = get_if_none_match(&server, &path, &caretaker, &etag).await;
    assert_eq!(cached.status(), StatusCode::NOT_MODIFIED);
    problem(server.get(&path, &robot).await, StatusCode::FORBIDDEN).await;
    let never_seen = format!("/api/v1/tags/{DRAWER}/picture");
    problem(server.get(&never_seen, &caretaker).await, StatusCode::NOT_FOUND).await;
}

/// Runs `pps-server export-trials` on the test's database without blocking its runtime.
async fn export_trials(server: &TestServer, args: &[&str]) -> std::process::Output {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_pps-server"));
    command.args(["export-trials", "--db", &server.db_arg()]).args(args);
    tokio::task::spawn_blocking(move || command.output().unwrap()).await.unwrap()
}

#[tokio::test]
async fn an_export_with_pictures_carries_each_trials_picture_beside_its_lines() {
    let server = TestServer::start_keeping_pictures(2).await;
    register_robot(&server, "el-e-1", "el-e", ALL, 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let jpeg = vec![0xFF, 0xD8, 0xFF, 0xE0, 0, 4, 0, 0, 0xFF, 0xC0, 0, 11, 8, 0, 10, 0, 10];
    // The first picture is removed by retention when the third arrives; one trial has none.
    let mut trials = Vec::new();
    for (seed, kind) in [(1, "image/png"), (2, "image/png"), (3, "image/jpeg")] {
        let id = record_trial(&server, &robot, ADA_SWITCH).await;
        let bytes = if kind == "image/jpeg" { jpeg.clone() } else { png(30, 20, seed, 50) };
        let sent = send_picture(&server, &id, &robot, kind, bytes).await;
        assert_eq!(sent.status(), StatusCode::CREATED);
        trials.push(id);
    }
    let without = record_trial(&server, &robot, DRAWER).await;

    let dir = tempfile::tempdir().unwrap();
    let pictures = dir.path().join("export/pictures");
    let lines = dir.path().join("trials.jsonl");
    let output = export_trials(
        &server,
        &[
            "--format",
            "jsonl",
            "--out",
            lines.to_str().unwrap(),
            "--pictures",
            pictures.to_str().unwrap(),
        ],
    )
    .await;
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{said}");
    // The summary is the last line; PostgreSQL may log a notice of its own before it.
    assert_eq!(
        said.trim().lines().last().unwrap_or_default(),
        format!(
            "exported 4 trials to {}, and 2 pictures to {}",
            lines.display(),
            pictures.display()
        )
    );
    let exported: Vec<Value> = std::fs::read_to_string(&lines)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    let file_of =
        |id: &str| exported.iter().find(|t| t["id"] == id).unwrap()["picture_file"].clone();
    assert_eq!(file_of(&trials[0]), Value::Null, "retention removed it before the export");
    assert_eq!(file_of(&without), Value::Null);
    let png_file = pictures.join(format!("{}.png", trials[1]));
    let jpeg_file = pictures.join(format!("{}.jpg", trials[2]));
    assert_eq!(file_of(&trials[1]), png_file.display().to_string());
    assert_eq!(file_of(&trials[2]), jpeg_file.display().to_string());
    assert_eq!(std::fs::read(&png_file).unwrap(), png(30, 20, 2, 50));
    assert_eq!(std::fs::read(&jpeg_file).unwrap(), jpeg);
    assert_eq!(std::fs::read_dir(&pictures).unwrap().count(), 2, "nothing else is written");

    // CSV names the same files; without --pictures the column is empty and nothing is written.
    let csv =
        export_trials(&server, &["--format", "csv", "--pictures", pictures.to_str().unwrap()])
            .await;
    let mut reader = csv::Reader::from_reader(csv.stdout.as_slice());
    let rows: Vec<std::collections::HashMap<String, String>> =
        reader.deserialize().map(Result::unwrap).collect();
    let files: Vec<&str> = rows.iter().map(|r| r["picture_file"].as_str()).collect();
    let (png_name, jpeg_name) = (png_file.display().to_string(), jpeg_file.display().to_string());
    assert_eq!(files, ["", png_name.as_str(), jpeg_name.as_str(), ""]);
    let plain = export_trials(&server, &["--format", "jsonl"]).await;
    let first: Value =
        serde_json::from_slice(plain.stdout.split(|b| *b == b'\n').next().unwrap()).unwrap();
    assert!(first.get("picture_file").is_none(), "the lines are the API's unless asked");
}
