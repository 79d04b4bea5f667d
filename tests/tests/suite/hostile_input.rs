//! Input a robot or caretaker on the LAN may send, well-formed JSON all of it, that must
//! neither fail anyone else's request nor teach the registry nonsense nor grow it without
//! bound: integers where learning expects decimals, learned values past the safe bounds,
//! overrides past the base schema, megabyte trials listed by the hundred, floods of unknown
//! EPCs.

use pps_test_kit::Registry;
use pps_test_kit::fixtures::{self, ADA_SWITCH, DRAWER, put_trial};
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

#[tokio::test]
async fn a_malformed_trial_fails_no_other_robots_trial() {
    let registry = Registry::start();
    let careless = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let careful = fixtures::robot(&registry, "el-e-2", "el-e").await;
    // 20 pulls measured as the integer 1 (as JavaScript writes 1.0), 60 valid trials of
    // another robot, all at once so they share commits.
    let mut sent = Vec::new();
    for n in 0..80 {
        let (token, trial) = if n % 4 == 0 {
            (careless.clone(), fixtures::pull_trial("el-e-1", json!(1)))
        } else {
            (careful.clone(), fixtures::switch_trial("el-e-2"))
        };
        let path = format!("/api/v1/trials/{}", trial["id"].as_str().unwrap());
        let request = registry.request(Method::PUT, &path, &token).json(&trial);
        sent.push(tokio::spawn(
            async move { (n % 4 == 0, request.send().await.unwrap().status()) },
        ));
    }
    let (mut valid_stored, mut integer_answers) = (0, Vec::new());
    for answer in sent {
        match answer.await.unwrap() {
            (false, status) => {
                assert_eq!(status, StatusCode::CREATED, "a valid trial of another robot");
                valid_stored += 1;
            }
            (true, status) => integer_answers.push(status),
        }
    }
    eprintln!("60 valid trials: {valid_stored} stored; integer displacements: {integer_answers:?}");
    assert_eq!(valid_stored, 60);
    assert!(integer_answers.iter().all(|s| *s == StatusCode::CREATED), "{integer_answers:?}");
    // 1 is a number like 1.0: it is learned from.
    let effective = registry.get(&format!("/api/v1/robots/el-e-2/tags/{DRAWER}")).await;
    assert_eq!(effective["entry"]["behaviors"]["pull_open"]["pull_distance"], 1.0);
    assert_eq!(effective["provenance"]["/behaviors/pull_open/pull_distance"], "learned");
}

#[tokio::test]
async fn learned_values_stay_within_the_safe_bounds() {
    let registry = Registry::start();
    let reporter = fixtures::robot(&registry, "el-e-1", "el-e").await;
    fixtures::robot(&registry, "el-e-2", "el-e").await;
    for displacement in [50.0, -5.0] {
        for _ in 0..2 {
            let (status, body) = put_trial(
                &registry,
                &reporter,
                &fixtures::pull_trial("el-e-1", json!(displacement)),
            )
            .await;
            assert_eq!(status, StatusCode::CREATED, "{body}");
        }
        let effective = registry.get(&format!("/api/v1/robots/el-e-2/tags/{DRAWER}")).await;
        let learned = &effective["entry"]["behaviors"]["pull_open"]["pull_distance"];
        eprintln!("after pulls of {displacement} m another robot pulls {learned} m");
        assert_eq!(*learned, 0.3, "the base value, not {displacement}");
        assert_eq!(effective["provenance"]["/behaviors/pull_open/pull_distance"], "base");
    }
}

#[tokio::test]
async fn property_overrides_meet_the_base_schema() {
    let registry = Registry::start();
    let path = format!("/api/v1/tags/{ADA_SWITCH}");
    let current = registry.request(Method::GET, &path, &registry.admin_token).send().await.unwrap();
    let etag = current.headers()["etag"].to_str().unwrap().to_owned();
    let mut entry: Value = current.json().await.unwrap();
    entry["properties"]["robots"]["el-e"]["height"] = json!(-1e308);
    let (status, body) = registry
        .call(Method::PUT, &path, &registry.admin_token, Some(&entry), &[("if-match", &etag)])
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");
    let pointers: Vec<&str> =
        body["errors"].as_array().unwrap().iter().map(|e| e["pointer"].as_str().unwrap()).collect();
    assert!(pointers.contains(&"/properties/robots/el-e/height"), "{body}");
    entry["properties"]["robots"]["el-e"]["height"] = json!(1.1);
    let (status, body) = registry
        .call(Method::PUT, &path, &registry.admin_token, Some(&entry), &[("if-match", &etag)])
        .await;
    assert_eq!(status, StatusCode::OK, "an override within bounds is stored: {body}");
}

#[tokio::test]
async fn listing_megabyte_trials_stays_small() {
    let registry = Registry::start();
    let robot = fixtures::robot(&registry, "el-e-1", "el-e").await;
    for _ in 0..20 {
        let mut trial = fixtures::switch_trial("el-e-1");
        let forces: Vec<Value> = (0..5000)
            .map(|i| json!({ "t": f64::from(i) * 0.001, "finger": "left", "force": [0.123456, 0.234567, 3.456789] }))
            .collect();
        trial["forces"] = Value::from(forces);
        trial["measurements"] = json!({ "note": "x".repeat(600_000) });
        let (status, body) = put_trial(&registry, &robot, &trial).await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
    }
    let baseline = registry.memory_kib("VmHWM");
    let list = registry.request(Method::GET, "/api/v1/trials?limit=500", &registry.admin_token);
    let answer = list.send().await.unwrap().bytes().await.unwrap();
    let page: Value = serde_json::from_slice(&answer).unwrap();
    let items = page["items"].as_array().unwrap();
    let with_forces = registry
        .request(Method::GET, "/api/v1/trials?limit=500&include=forces", &registry.admin_token)
        .send()
        .await
        .unwrap()
        .bytes()
        .await
        .unwrap();
    let forced: Value = serde_json::from_slice(&with_forces).unwrap();
    let peak = registry.memory_kib("VmHWM");
    eprintln!(
        "20 trials of ~0.9 MB: a page of {} bytes ({} items), with forces {} bytes ({} items); \
         peak RSS {baseline} -> {peak} KiB",
        answer.len(),
        items.len(),
        with_forces.len(),
        forced["items"].as_array().unwrap().len()
    );
    assert!(items.iter().all(|t| t.get("forces").is_none()), "forces only when asked");
    assert!(answer.len() < 5 << 20, "a page holds at most 4 MiB of trials: {}", answer.len());
    assert!(page["next_cursor"].is_string(), "a page cut short says where to go on");
    assert!(forced["items"][0]["forces"].as_array().is_some_and(|f| f.len() == 5000));
    assert!(with_forces.len() < 5 << 20);
    assert!(peak.saturating_sub(baseline) < 150 * 1024, "peak RSS {baseline} -> {peak} KiB");

    // Paging on reaches every trial once.
    let (mut seen, mut cursor) = (0, None::<String>);
    loop {
        let path = match &cursor {
            Some(c) => format!("/api/v1/trials?limit=500&cursor={c}"),
            None => "/api/v1/trials?limit=500".into(),
        };
        let page = registry.get(&path).await;
        seen += page["items"].as_array().unwrap().len();
        match page["next_cursor"].as_str() {
            Some(next) => cursor = Some(next.to_owned()),
            None => break,
        }
    }
    assert_eq!(seen, 20);
}

#[tokio::test]
async fn a_flood_of_unknown_epcs_keeps_the_inbox_and_the_feed_bounded() {
    let registry = Registry::start();
    let robot = fixtures::robot(&registry, "el-e-1", "el-e").await;
    let events_before = count_rows(&registry, "events").await;
    let reads = (0..16).map(|worker| {
        let (client, base, token) = (reqwest::Client::new(), registry.url.clone(), robot.clone());
        tokio::spawn(async move {
            for n in 0..750 {
                let epc = format!("E2{worker:02X}{n:020X}");
                let url = format!("{base}/api/v1/robots/el-e-1/tags/{epc}");
                let status = client.get(url).bearer_auth(&token).send().await.unwrap().status();
                assert_eq!(status, StatusCode::NOT_FOUND);
            }
        })
    });
    for worker in reads.collect::<Vec<_>>() {
        worker.await.unwrap();
    }
    // The last sightings reach the database within a second.
    let inbox = pps_test_kit::wait::until("the inbox to settle", || async {
        let rows = count_rows(&registry, "inbox").await;
        (rows >= 10_000).then_some(rows)
    })
    .await;
    let events = count_rows(&registry, "events").await - events_before;
    eprintln!("12,000 distinct unknown EPCs: {inbox} inbox rows, {events} events");
    assert_eq!(inbox, 10_000, "the newest 10,000 EPCs are kept");
    assert!(events < 100, "one inbox event per flush, not per EPC: {events}");
}

/// Rows in a table of the server's database, read as a second process would.
async fn count_rows(registry: &Registry, table: &str) -> i64 {
    let options =
        sqlx::sqlite::SqliteConnectOptions::new().filename(registry.db_path()).read_only(true);
    let mut conn =
        <sqlx::SqliteConnection as sqlx::Connection>::connect_with(&options).await.unwrap();
    let sql = match table {
        "events" => "select count(*) from events",
        _ => "select count(*) from inbox",
    };
    sqlx::query_scalar(sql).fetch_one(&mut conn).await.unwrap()
}
