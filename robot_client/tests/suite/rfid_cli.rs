//! `pps-robot rfid` as a person or a script runs it, against llrpkit's LLRP reader emulator.

use std::net::TcpListener;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use crate::llrpkit::{Emulator, tag};
use pps_test_kit::ADA_SWITCH;
use serde_json::Value;

const LAMP: &str = "355AB1C60000003000000001";
const UNREGISTERED: &str = "E2801160600002084D2AB5C71E0F0A11";

fn pps_robot(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pps-robot")).args(args).output().expect("the binary runs")
}

fn json_of(output: &Output) -> Value {
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    serde_json::from_slice(&output.stdout).expect("stdout is one JSON document")
}

#[test]
fn json_names_the_reads_the_tags_strongest_first_and_the_choice_and_a_second_run_follows_at_once() {
    let emulator =
        Emulator::start(vec![tag(LAMP, &[2], -57.0), tag(ADA_SWITCH, &[1], -44.0)], 400.0);
    let address = emulator.address();
    let args = ["rfid", "--llrp", &address, "--antennas", "1,2", "--rounds", "2", "--json"];
    let doc = json_of(&pps_robot(&args));
    let keys: Vec<&str> = doc.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(keys, ["ambiguous", "chosen", "reads", "tags"]);
    assert_eq!(doc["chosen"], ADA_SWITCH);
    assert_eq!(doc["ambiguous"], false);
    let tags = doc["tags"].as_array().unwrap();
    assert_eq!((tags[0]["epc"].as_str(), tags[1]["epc"].as_str()), (Some(ADA_SWITCH), Some(LAMP)));
    let reads = doc["reads"].as_array().unwrap();
    let counted: u64 = tags.iter().map(|t| t["reads"].as_u64().unwrap()).sum();
    assert_eq!(counted, reads.len() as u64);
    assert!(reads.iter().all(|r| (r["epc"] == LAMP) == (r["antenna"] == 2)), "{reads:?}");

    // The emulator takes one client at a time: the first run must have closed its connection.
    let started = Instant::now();
    let again = json_of(&pps_robot(&args));
    assert_eq!(again["chosen"], ADA_SWITCH);
    assert!(started.elapsed() < Duration::from_secs(3), "{:?}", started.elapsed());

    let text = pps_robot(&["rfid", "--llrp", &address, "--antennas", "1,2", "--rounds", "1"]);
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains(&format!("chosen: {ADA_SWITCH}\n")), "{text}");
}

#[test]
fn an_unreachable_reader_is_a_sentence_and_a_failure_within_seconds() {
    let started = Instant::now();
    let refused = pps_robot(&["rfid", "--llrp", "127.0.0.1:1"]);
    assert!(!refused.status.success());
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(stderr.contains("cannot connect to 127.0.0.1:1"), "{stderr}");
    assert!(refused.stdout.is_empty());

    // Something listens but is no LLRP reader: it never sends the connection event.
    let silent = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = silent.local_addr().unwrap().to_string();
    let mute = pps_robot(&["rfid", "--llrp", &address, "--json"]);
    assert!(!mute.status.success());
    let stderr = String::from_utf8_lossy(&mute.stderr);
    assert!(stderr.contains("sent no LLRP connection event"), "{stderr}");
    assert!(mute.stdout.is_empty(), "--json prints nothing when there is no document");
    assert!(started.elapsed() < Duration::from_secs(8), "{:?}", started.elapsed());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_a_registry_the_chosen_tags_actions_are_printed() {
    let dir = tempfile::tempdir().unwrap();
    let registry = pps_test_kit::RobotRegistry::start().await;
    let emulator = Emulator::start(vec![tag(ADA_SWITCH, &[1], -44.0)], 400.0);
    let state = dir.path().join("robot-state").to_string_lossy().into_owned();
    let run = |address: String, json: bool| {
        let (url, token, state) =
            (registry.url.clone(), registry.robot_token.clone(), state.clone());
        tokio::task::spawn_blocking(move || {
            let mut args = vec!["rfid", "--llrp", &address, "--rounds", "1", "--registry", &url];
            args.extend(["--token", &token, "--robot", "el-e-1", "--state", &state]);
            if json {
                args.push("--json");
            }
            pps_robot(&args)
        })
    };
    let doc = json_of(&run(emulator.address(), true).await.unwrap());
    assert_eq!(
        doc["registry"]["actions"],
        serde_json::json!({"on": "push_top", "off": "push_bottom"})
    );
    assert_eq!(doc["registry"]["unavailable_actions"], serde_json::json!([]));
    let text = run(emulator.address(), false).await.unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("  on: push_top\n") && text.contains("  off: push_bottom\n"), "{text}");
    drop(emulator);

    let stranger = Emulator::start(vec![tag(UNREGISTERED, &[1], -44.0)], 400.0);
    let doc = json_of(&run(stranger.address(), true).await.unwrap());
    assert_eq!(doc["chosen"], UNREGISTERED);
    let error = doc["registry"]["error"].as_str().expect("an unknown tag is a sentence");
    assert!(error.starts_with("the registry refused") && error.contains("404"), "{error}");
}

#[test]
fn durations_out_of_range_are_refused_with_their_range() {
    for (args, said) in [
        (&["rfid", "--llrp", "127.0.0.1:9", "--round-ms", "0"][..], "10 to 60000 milliseconds"),
        (
            &["rfid", "--llrp", "127.0.0.1:9", "--round-ms", "18446744073709551615"][..],
            "10 to 60000",
        ),
        (&["bench-llrp", "--seconds=-1"][..], "0.1 to 3600 seconds"),
        (&["bench-llrp", "--seconds", "1e300"][..], "0.1 to 3600 seconds"),
        (&["bench-llrp", "--seconds", "NaN"][..], "0.1 to 3600 seconds"),
    ] {
        let output = pps_robot(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?}: {stderr}");
        assert!(stderr.contains(said), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}
