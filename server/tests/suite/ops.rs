//! Operating the registry with the `pps-server` binary: a backup taken while robots write,
//! restored and served; trials exported with the API's filters; old force samples thinned
//! without losing a trial or breaking a robot's retry.
//!
//! Long because each test drives the binary end to end, with robots writing while it runs;
//! one file keeps the helpers they share (running the binary, paging, writing trials) with them.

use std::collections::{HashMap, HashSet};
use std::process::{Command, Output};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use time::OffsetDateTime;
use time::format_description::well_known::Rfc3339;

use pps_server::identity::Role;
use pps_server::trial_history::export::CSV_COLUMNS;
use pps_server::trial_history::retention::{Age, THINNED_KEY};
use pps_server::{AppState, Db, ServeOptions};
use pps_test_kit::{ADA_SWITCH, DRAWER, TestServer, register_robot, trial, wait_until};
use reqwest::StatusCode;
use serde_json::{Value, json};
use sqlx::{Connection, SqliteConnection};
use tokio::sync::watch;
use uuid::Uuid;

const BIN: &str = env!("CARGO_BIN_EXE_pps-server");

/// Runs the binary on `db` without blocking the runtime the in-process server runs on.
async fn cli(db: &str, args: &[&str]) -> Output {
    let (db, args): (String, Vec<String>) =
        (db.to_owned(), args.iter().map(|a| a.to_string()).collect());
    tokio::task::spawn_blocking(move || {
        Command::new(BIN).args(&args).arg("--db").arg(&db).output().unwrap()
    })
    .await
    .unwrap()
}

fn succeeded(output: &Output) -> (String, String) {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{stderr}");
    (String::from_utf8(output.stdout.clone()).unwrap(), stderr)
}

/// Every item of a listing, following `next_cursor`.
async fn all_items(server: &TestServer, url: &str, path_and_query: &str) -> Vec<Value> {
    let mut items = Vec::new();
    let separator = if path_and_query.contains('?') { '&' } else { '?' };
    let mut cursor: Option<String> = None;
    loop {
        // Cursors are URL-safe, so they go into the query as they are.
        let after = cursor.as_deref().map(|c| format!("&cursor={c}")).unwrap_or_default();
        let page_url = format!("{url}{path_and_query}{separator}limit=500{after}");
        let response = server.client.get(page_url).bearer_auth(&server.admin).send().await.unwrap();
        assert_eq!(response.status(), StatusCode::OK, "{path_and_query}");
        let page: Value = response.json().await.unwrap();
        items.extend(page["items"].as_array().unwrap().iter().cloned());
        match page["next_cursor"].as_str() {
            Some(next) => cursor = Some(next.to_owned()),
            None => return items,
        }
    }
}

/// Trials acknowledged by the registry, in order, with a count to wait on.
#[derive(Clone)]
struct Acknowledged {
    trials: Arc<Mutex<Vec<(String, Value)>>>,
    count: watch::Sender<usize>,
}

impl Acknowledged {
    fn ids(&self) -> HashSet<String> {
        self.trials.lock().unwrap().iter().map(|(id, _)| id.clone()).collect()
    }

    async fn reach(&self, n: usize) {
        let mut count = self.count.subscribe();
        tokio::time::timeout(Duration::from_secs(60), count.wait_for(|c| *c >= n))
            .await
            .expect("the robots kept writing")
            .unwrap();
    }
}

/// A robot writing one trial after another until `stop` is set.
async fn robot_writes(
    server: Arc<TestServer>,
    robot: String,
    token: String,
    acknowledged: Acknowledged,
    stop: watch::Receiver<bool>,
) {
    let mut n = 0;
    while !*stop.borrow() {
        let id = Uuid::new_v4().to_string();
        let outcome = ["success", "failure"][n % 2];
        let mut body = trial(&id, ADA_SWITCH, &robot, "on", "push_top", outcome);
        body["forces"] = json!([{ "t": 0.1, "finger": "left", "force": [1.0, 2.0, 2.0] }]);
        let response = server.put(&format!("/api/v1/trials/{id}"), &token, &body, None).await;
        assert_eq!(response.status(), StatusCode::CREATED);
        acknowledged.trials.lock().unwrap().push((id, body));
        acknowledged.count.send_modify(|count| *count += 1);
        n += 1;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_backup_taken_while_robots_write_holds_every_acknowledged_trial_and_restores() {
    let server = Arc::new(TestServer::start_sqlite().await);
    let acknowledged = Acknowledged { trials: Arc::default(), count: watch::Sender::new(0) };
    let (stop, stopping) = watch::channel(false);
    let mut robots = Vec::new();
    for n in 1..=4 {
        let robot = format!("el-e-{n}");
        register_robot(&server, &robot, "el-e", &["light_switch"], 15.0).await;
        let token = server.token(Role::Robot, &robot).await;
        robots.push(tokio::spawn(robot_writes(
            server.clone(),
            robot,
            token,
            acknowledged.clone(),
            stopping.clone(),
        )));
    }
    acknowledged.reach(200).await;

    let dir = tempfile::tempdir().unwrap();
    let backup = dir.path().join("pps-backup.db");
    let before = acknowledged.ids();
    let started = Instant::now();
    let output = cli(&server.db_arg(), &["backup", "--to", backup.to_str().unwrap()]).await;
    let took = started.elapsed();
    let (_, said) = succeeded(&output);
    let during = *acknowledged.count.borrow();
    acknowledged.reach(during + 100).await;
    stop.send_replace(true);
    for robot in robots {
        robot.await.unwrap();
    }
    let sent: HashMap<String, Value> =
        acknowledged.trials.lock().unwrap().iter().cloned().collect();

    // The copy is sound and holds exactly acknowledged trials, including all acknowledged
    // before it began.
    let mut copy =
        SqliteConnection::connect(&format!("sqlite:{}", backup.display())).await.unwrap();
    let integrity: String =
        sqlx::query_scalar("pragma integrity_check").fetch_one(&mut copy).await.unwrap();
    assert_eq!(integrity, "ok");
    let stored: Vec<(String, String)> =
        sqlx::query_as("select id, body from trials").fetch_all(&mut copy).await.unwrap();
    copy.close().await.unwrap();
    let in_backup: HashSet<String> = stored.iter().map(|(id, _)| id.clone()).collect();
    eprintln!(
        "backup took {took:.2?}: {} trials acknowledged before it began, {} in it, {} \
         acknowledged by its end, {} in all",
        before.len(),
        in_backup.len(),
        during,
        sent.len()
    );
    assert!(before.is_subset(&in_backup), "every trial acknowledged before the backup is in it");
    for (id, body) in &stored {
        let sent = sent.get(id).expect("nothing in the backup was never acknowledged");
        assert_eq!(&serde_json::from_str::<Value>(body).unwrap(), sent);
    }
    assert!(in_backup.len() < sent.len(), "the robots kept writing after the backup");
    assert!(said.contains(&format!("{} trials", in_backup.len())), "{said}");
    assert!(said.contains("5 tags"), "{said}");

    // Restore as the README says: the copy becomes pps.db of a stopped registry.
    let restored_dir = tempfile::tempdir().unwrap();
    let restored_path = restored_dir.path().join("pps.db");
    std::fs::copy(&backup, &restored_path).unwrap();
    let restored = Db::open_file(&restored_path).await.unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let restored_url = format!("http://{}", listener.local_addr().unwrap());
    tokio::spawn(pps_server::serve(listener, AppState::new(restored), std::future::pending()));

    let original_trials: HashMap<String, Value> = all_items(&server, &server.url, "/api/v1/trials")
        .await
        .into_iter()
        .map(|t| (t["id"].as_str().unwrap().to_owned(), t))
        .collect();
    let restored_trials = all_items(&server, &restored_url, "/api/v1/trials").await;
    assert_eq!(restored_trials.len(), in_backup.len());
    for trial in &restored_trials {
        let id = trial["id"].as_str().unwrap();
        assert!(in_backup.contains(id));
        assert_eq!(
            trial, &original_trials[id],
            "the restored registry answers as the original did"
        );
    }
    assert_eq!(
        all_items(&server, &restored_url, "/api/v1/tags").await,
        all_items(&server, &server.url, "/api/v1/tags").await
    );

    let again = cli(&server.db_arg(), &["backup", "--to", backup.to_str().unwrap()]).await;
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    succeeded(
        &cli(&server.db_arg(), &["backup", "--to", backup.to_str().unwrap(), "--force"]).await,
    );
    let live = server.db_path.to_str().unwrap();
    let onto_itself = cli(&server.db_arg(), &["backup", "--to", live, "--force"]).await;
    assert!(!onto_itself.status.success(), "a backup never overwrites the live database");
}

#[tokio::test]
async fn a_backup_never_replaces_the_live_databases_journals() {
    let server = TestServer::start_sqlite().await;
    let token = server.token(Role::Robot, "el-e-1").await;
    let id = Uuid::new_v4().to_string();
    let body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    let stored = server.put(&format!("/api/v1/trials/{id}"), &token, &body, None).await;
    assert_eq!(stored.status(), StatusCode::CREATED);

    let dir = server.db_path.parent().unwrap();
    let wal = dir.join("pps.db-wal");
    let inode = |path: &std::path::Path| {
        std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(path).unwrap())
    };
    let wal_before = inode(&wal);
    let linked = tempfile::tempdir().unwrap();
    let link = linked.path().join("innocent.db");
    std::os::unix::fs::symlink(&wal, &link).unwrap();
    let via_dotdot = dir.join("..").join(dir.file_name().unwrap()).join("pps.db-shm");
    let journal = dir.join("pps.db-journal");
    for (to, what) in [
        (wal.clone(), "write-ahead log"),
        (via_dotdot, "shared-memory index"),
        (journal.clone(), "rollback journal"),
        (link, "write-ahead log"),
    ] {
        let output =
            cli(&server.db_arg(), &["backup", "--to", to.to_str().unwrap(), "--force"]).await;
        let said = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{}: {said}", to.display());
        assert!(said.contains(&format!("is the live database's {what}")), "{said}");
    }
    assert!(!journal.exists(), "no journal was made");
    assert_eq!(inode(&wal), wal_before, "the server's WAL was not replaced");
    let read = server.get(&format!("/api/v1/trials/{id}"), &server.admin).await;
    assert_eq!(read.status(), StatusCode::OK);
}

/// Trials of two robots on two tags, over several days, with forces and awkward text.
async fn varied_trials(server: &TestServer) -> Vec<Value> {
    let mut written = Vec::new();
    let tokens = [
        ("el-e-1", server.token(Role::Robot, "el-e-1").await),
        ("el-e-2", server.token(Role::Robot, "el-e-2").await),
    ];
    register_robot(server, "el-e-1", "el-e", &["light_switch", "pull_back"], 15.0).await;
    for n in 0..12 {
        let (robot, token) = &tokens[n % 2];
        let (epc, action, behavior) =
            if n % 3 == 0 { (DRAWER, "open", "pull_open") } else { (ADA_SWITCH, "on", "push_top") };
        let outcome = ["success", "failure", "aborted"][n % 3];
        let id = Uuid::new_v4().to_string();
        let mut body = trial(&id, epc, robot, action, behavior, outcome);
        body["started_at"] = format!("2026-11-{:02}T10:00:00Z", 10 + n).into();
        body["finished_at"] = format!("2026-11-{:02}T10:00:30Z", 10 + n).into();
        body["forces"] = json!([
            { "t": 0.5, "finger": "left", "force": [3.0, 4.0, 0.0] },
            { "t": 1.5, "finger": "right", "force": [0.0, 0.0, 1.0] }
        ]);
        body["measurements"] =
            json!({ "note": format!("trial {n}, \"quoted\",\nsecond line"), "pulled_m": 0.25 });
        let response = server.put(&format!("/api/v1/trials/{id}"), token, &body, None).await;
        assert_eq!(response.status(), StatusCode::CREATED);
        written.push(response.json().await.unwrap());
    }
    written
}

/// Whether `trial` passes `filter`, judged from its own fields: `epc_uri` is the ADA switch's
/// EPC in its pure-identity spelling, and `since` compares the start as a time.
fn selected_by(trial: &Value, filter: &[(&str, &str)], epc_uri: &str) -> bool {
    let time = |text: &str| OffsetDateTime::parse(text, &Rfc3339).unwrap();
    filter.iter().all(|&(key, value)| match key {
        "robot" | "outcome" | "action" => trial[key] == value,
        "epc" => {
            let epc = if value == epc_uri { ADA_SWITCH } else { value };
            trial["epc"].as_str().unwrap().eq_ignore_ascii_case(epc)
        }
        "since" => time(trial["started_at"].as_str().unwrap()) >= time(value),
        _ => panic!("no such filter in this test: {key}"),
    })
}

#[tokio::test]
async fn export_trials_selects_by_each_trials_own_fields_in_json_lines_and_csv() {
    let server = TestServer::start().await;
    let written = varied_trials(&server).await;
    let epc_uri = "urn:epc:tag:gid-96:95100000.2.1"; // the ADA switch, in another accepted spelling
    let filters: [&[(&str, &str)]; 6] = [
        &[],
        &[("robot", "el-e-2")],
        &[("epc", epc_uri)],
        &[("outcome", "failure"), ("action", "on")],
        &[("since", "2026-11-15T00:00:00+00:00")],
        &[("epc", &DRAWER.to_lowercase()), ("robot", "el-e-1"), ("since", "2026-11-12T00:00:00Z")],
    ];
    for filter in filters {
        // Worked out here from what each trial says, not through the registry's own filter,
        // which the export shares.
        let expected: Vec<&Value> =
            written.iter().filter(|trial| selected_by(trial, filter, epc_uri)).collect();
        let mut args = vec!["export-trials".to_owned(), "--format".into(), "jsonl".into()];
        for (key, value) in filter {
            args.extend([format!("--{key}"), value.to_string()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (out, said) = succeeded(&cli(&server.db_arg(), &args).await);
        let exported: Vec<Value> = out.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
        let ids = |trials: &[&Value]| -> Vec<String> {
            trials.iter().map(|t| t["id"].as_str().unwrap().to_owned()).collect()
        };
        assert_eq!(
            ids(&exported.iter().collect::<Vec<_>>()),
            ids(&expected),
            "export-trials {filter:?}"
        );
        // Each trial whole, forces included, as the registry answers for it alone.
        for trial in &exported {
            let id = trial["id"].as_str().unwrap();
            let alone = server.get_json(&format!("/api/v1/trials/{id}")).await;
            assert_eq!(trial, &alone, "export-trials {filter:?}");
        }
        assert!(said.contains(&format!("exported {} trials", expected.len())), "{said}");
        let selective = !expected.is_empty() && expected.len() < written.len();
        assert!(filter.is_empty() || selective, "{filter:?} selects some trials, not all");
    }

    let file = server.db_path.with_file_name("trials.csv");
    let args =
        ["export-trials", "--format", "csv", "--robot", "el-e-1", "--out", file.to_str().unwrap()];
    succeeded(&cli(&server.db_arg(), &args).await);
    let mut csv = csv::Reader::from_path(&file).unwrap();
    assert_eq!(csv.headers().unwrap(), &csv::StringRecord::from(CSV_COLUMNS.to_vec()));
    let rows: Vec<HashMap<String, String>> = csv.deserialize().map(Result::unwrap).collect();
    let expected: Vec<&Value> = written.iter().filter(|t| t["robot"] == "el-e-1").collect();
    assert_eq!(rows.len(), expected.len());
    for (row, trial) in rows.iter().zip(expected) {
        assert_eq!(row["id"], trial["id"].as_str().unwrap());
        assert_eq!(row["behavior"], trial["behavior"].as_str().unwrap());
        assert_eq!(row["robot_class"], "el-e");
        assert_eq!(row["seq"], trial["seq"].to_string());
        assert_eq!(row["confirmed"], "");
        assert_eq!(row["duration_s"], "30");
        assert_eq!(row["force_samples"], "2");
        assert_eq!(row["peak_force_n"], "5");
        let measurements: Value = serde_json::from_str(&row["measurements"]).unwrap();
        assert_eq!(measurements, trial["measurements"], "quotes, commas and newlines survive");
    }

    let bad =
        cli(&server.db_arg(), &["export-trials", "--format", "csv", "--outcome", "maybe"]).await;
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("outcome is one of"));
}

#[tokio::test]
async fn export_trials_pages_through_more_trials_than_one_query_returns() {
    let server = Arc::new(TestServer::start().await);
    let token = server.token(Role::Robot, "el-e-1").await;
    let writers: Vec<_> = (0..8)
        .map(|_| {
            let (server, token) = (server.clone(), token.clone());
            tokio::spawn(async move {
                for _ in 0..70 {
                    let id = Uuid::new_v4().to_string();
                    let body = trial(&id, ADA_SWITCH, "el-e-1", "off", "push_bottom", "success");
                    let response =
                        server.put(&format!("/api/v1/trials/{id}"), &token, &body, None).await;
                    assert_eq!(response.status(), StatusCode::CREATED);
                }
            })
        })
        .collect();
    for writer in writers {
        writer.await.unwrap();
    }
    let (out, _) = succeeded(&cli(&server.db_arg(), &["export-trials", "--format", "jsonl"]).await);
    let seqs: Vec<i64> = out
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap()["seq"].as_i64().unwrap())
        .collect();
    assert_eq!(seqs.len(), 560);
    assert!(seqs.windows(2).all(|w| w[0] < w[1]), "oldest first, none twice");
}

/// Pretends trials arrived `days` ago.
async fn backdate(db: &Db, ids: &[&str], days: i64) {
    let then =
        pps_server::clock::format(time::OffsetDateTime::now_utc() - time::Duration::days(days));
    let mut tx = db.begin_write().await.unwrap();
    for id in ids {
        sqlx::query("update trials set received_at = $1 where id = $2")
            .bind(&then)
            .bind(id)
            .execute(&mut *tx)
            .await
            .unwrap();
    }
    tx.commit().await.unwrap();
}

#[tokio::test]
async fn thinning_keeps_every_trial_with_a_summary_and_old_trials_can_still_be_resent() {
    let server = TestServer::start().await;
    let token = server.token(Role::Robot, "el-e-1").await;
    let samples: Vec<Value> = (0..300)
        .map(|i| json!({ "t": f64::from(i) * 0.01, "finger": "left", "force": [0.0, 0.0, f64::from(i % 7)] }))
        .collect();
    let mut sent = Vec::new();
    for _ in 0..3 {
        let id = Uuid::new_v4().to_string();
        let mut body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
        body["forces"] = samples.clone().into();
        body["measurements"] = json!({ "switch_travel_m": 0.02 });
        let response = server.put(&format!("/api/v1/trials/{id}"), &token, &body, None).await;
        assert_eq!(response.status(), StatusCode::CREATED);
        sent.push((id, body));
    }
    let (old, recent) = (&sent[..2], &sent[2]);
    backdate(&server.db, &[&old[0].0, &old[1].0], 40).await;
    let recent_before = server.get_json(&format!("/api/v1/trials/{}", recent.0)).await;

    let (_, said) = succeeded(&cli(&server.db_arg(), &["thin-forces", "--older-than", "30"]).await);
    assert!(said.contains("thinned 2 trials") && said.contains("600 force samples"), "{said}");

    assert_eq!(
        all_items(&server, &server.url, "/api/v1/trials").await.len(),
        3,
        "no trial is lost"
    );
    for (id, body) in old {
        let thinned = server.get_json(&format!("/api/v1/trials/{id}")).await;
        assert_eq!(thinned["forces"], json!([]));
        let kept = &thinned["measurements"][THINNED_KEY];
        assert_eq!(kept["samples"], 300);
        assert_eq!(kept["peak_n"], 6.0);
        assert!(kept["thinned_at"].is_string());
        assert_eq!(thinned["measurements"]["switch_travel_m"], 0.02);
        for field in ["epc", "robot", "action", "behavior", "outcome", "started_at", "detector"] {
            assert_eq!(thinned[field], body[field], "{field} is kept");
        }
    }
    assert_eq!(server.get_json(&format!("/api/v1/trials/{}", recent.0)).await, recent_before);

    // A robot's outbox re-sends an old trial after a long outage: still the same trial.
    let (id, body) = &old[0];
    let resent = server.put(&format!("/api/v1/trials/{id}"), &token, body, None).await;
    assert_eq!(resent.status(), StatusCode::OK);
    let resent: Value = resent.json().await.unwrap();
    assert_eq!(
        resent["measurements"][THINNED_KEY]["samples"], 300,
        "the stored trial is unchanged"
    );
    let mut altered = body.clone();
    altered["forces"][10]["force"][2] = json!(99.0);
    let conflict = server.put(&format!("/api/v1/trials/{id}"), &token, &altered, None).await;
    assert_eq!(conflict.status(), StatusCode::CONFLICT, "a different trial under the same id");

    let (_, said) = succeeded(&cli(&server.db_arg(), &["thin-forces", "--older-than", "30"]).await);
    assert!(said.contains("thinned 0 trials"), "thinning twice changes nothing: {said}");
    let (csv, _) = succeeded(&cli(&server.db_arg(), &["export-trials", "--format", "csv"]).await);
    let mut rows = csv::Reader::from_reader(csv.as_bytes());
    let rows: Vec<HashMap<String, String>> = rows.deserialize().map(Result::unwrap).collect();
    assert!(rows.iter().all(|row| row["force_samples"] == "300" && row["peak_force_n"] == "6"));
}

#[tokio::test]
async fn a_server_with_thinning_on_thins_old_trials_when_it_starts() {
    let server = TestServer::start().await;
    let token = server.token(Role::Robot, "el-e-1").await;
    let id = Uuid::new_v4().to_string();
    let mut body = trial(&id, ADA_SWITCH, "el-e-1", "on", "push_top", "success");
    body["forces"] = json!([{ "t": 0.0, "finger": "right", "force": [0.0, 2.0, 0.0] }]);
    let response = server.put(&format!("/api/v1/trials/{id}"), &token, &body, None).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    backdate(&server.db, &[&id], 8).await;

    let db = Db::open(&server.location).await.unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let options =
        ServeOptions { thin_forces_after: Some(Age { days: 7 }), ..ServeOptions::default() };
    tokio::spawn(pps_server::serve_with(
        listener,
        AppState::new(db),
        options,
        std::future::pending(),
    ));
    let thinned = wait_until(Duration::from_secs(10), "the trial to be thinned", || async {
        let trial = server.get_json(&format!("/api/v1/trials/{id}")).await;
        (trial["forces"] == json!([])).then_some(trial)
    })
    .await;
    assert_eq!(thinned["measurements"][THINNED_KEY]["peak_n"], 2.0);
}
