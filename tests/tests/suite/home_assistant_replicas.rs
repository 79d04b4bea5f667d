//! Two replicas on one PostgreSQL database with `--mqtt`: exactly one runs the Home Assistant
//! bridge (the broker sees one client besides the test's), a press is one task, and when the
//! holder stops the other takes over and announces. Needs the cluster the test command starts
//! (`PPS_TEST_POSTGRES`), as the server's replica tests do.

use std::time::{Duration, Instant};

use pps_server::store::db::Location;
use pps_test_kit::{ADA_SWITCH, Registry, wait};
use pps_tests::{Mosquitto, MqttWatch};

/// Which of the replicas says it runs the bridge.
fn runners(replicas: &[&Registry]) -> Vec<usize> {
    (0..replicas.len())
        .filter(|&i| replicas[i].logged("running the Home Assistant bridge"))
        .collect()
}

async fn tasks_on(registry: &Registry, epc: &str) -> usize {
    let page = registry.get(&format!("/api/v1/tasks?epc={epc}")).await;
    page["items"].as_array().map_or(0, Vec::len)
}

#[tokio::test]
async fn one_replica_runs_the_bridge_and_the_other_takes_over() {
    let Location::Postgres(database) = pps_test_kit::postgres::fresh_database().await else {
        unreachable!("a PostgreSQL database")
    };
    let broker = Mosquitto::start().await;
    let mqtt = ["--mqtt", &broker.url()];
    let first = Registry::on_postgres(&database, &mqtt);
    let second = first.another_replica(&mqtt);
    let watch = MqttWatch::connect(
        broker.port,
        "watch-replicas",
        &["homeassistant/#", "pps/#", "$SYS/broker/clients/connected"],
    )
    .await;
    wait::until("the tags announced", || async {
        (watch.topics(|t| t.ends_with("/task/config")).len() == 5).then_some(())
    })
    .await;
    wait::until("one replica to stand by", || async {
        [&first, &second].iter().any(|r| r.logged("standing by")).then_some(())
    })
    .await;
    assert_eq!(runners(&[&first, &second]).len(), 1, "exactly one replica runs the bridge");
    // The test's client and one bridge.
    watch.until_text("$SYS/broker/clients/connected", "2").await;

    let ada = format!("pps_{}", ADA_SWITCH.to_ascii_lowercase());
    watch.publish(&format!("pps/{ada}/press/off"), "PRESS").await;
    wait::until("the press to become a task", || async {
        (tasks_on(&first, ADA_SWITCH).await == 1).then_some(())
    })
    .await;

    // The holder stops; the other replica takes the bridge over and says so.
    let (holder, standby) =
        if runners(&[&first, &second]) == [0] { (first, second) } else { (second, first) };
    let stopping = Instant::now();
    let status = std::process::Command::new("kill")
        .args(["-TERM", &holder.pid().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
    watch.until_text("pps/bridge/availability", "offline").await;
    wait::wait_until(Duration::from_secs(30), "the other replica to take over", || async {
        standby.logged("running the Home Assistant bridge").then_some(())
    })
    .await;
    watch.until_text("pps/bridge/availability", "online").await;
    eprintln!("takeover after the holder stopped: {} ms", stopping.elapsed().as_millis());

    watch.publish(&format!("pps/{ada}/press/on"), "PRESS").await;
    wait::until("the second press to become a task", || async {
        (tasks_on(&standby, ADA_SWITCH).await == 2).then_some(())
    })
    .await;
}
