//! What a robot's trial upload must look like.

use pps_schema::{MAX_FORCE_SAMPLES, Outcome, Purpose, Trial, ValidationErrors, validate_trial};
use serde_json::{Value, json};

fn trial() -> Value {
    json!({
        "id": "67e55044-10b1-426f-9247-bb680e5fe0c8",
        "epc": "355AB1C60000002000000001",
        "robot": "el-e-1",
        "action": "on",
        "behavior": "push_top",
        "started_at": "2024-05-01T12:00:00Z",
        "finished_at": "2024-05-01T12:00:41.5+00:00",
        "outcome": "success",
        "confirmed": null,
        "detector": {"brightness_before": 0.21, "brightness_after": 0.43},
        "forces": [
            {"t": 0.0, "finger": "left", "force": [0.1, 0.0, 2.1]},
            {"t": 0.02, "finger": "right", "force": [0.0, 0.1, 2.0], "torque": [0.0, 0.01, 0.0]}
        ],
        "measurements": {"carriage_travel": 0.02},
        "start_pose": {"x": 1.5, "y": -0.2, "yaw": 3.1}
    })
}

fn rejected(trial: &Value) -> ValidationErrors {
    validate_trial(trial).expect_err("the trial must be rejected")
}

fn pointers(errors: &ValidationErrors) -> Vec<&str> {
    errors.errors().iter().map(|e| e.pointer.as_str()).collect()
}

#[test]
fn a_complete_trial_validates_and_reads() {
    validate_trial(&trial()).unwrap();
    let typed: Trial = serde_json::from_value(trial()).unwrap();
    assert_eq!(typed.outcome, Outcome::Success);
    assert_eq!(typed.confirmed, None);
    assert_eq!((typed.finished_at - typed.started_at).as_seconds_f64(), 41.5);
    let back = serde_json::to_value(&typed).unwrap();
    validate_trial(&back).unwrap();
    assert_eq!(serde_json::from_value::<Trial>(back).unwrap(), typed);
}

#[test]
fn optional_parts_may_be_left_out() {
    let mut minimal = trial();
    for field in ["confirmed", "detector", "forces", "measurements", "start_pose"] {
        minimal.as_object_mut().unwrap().remove(field);
    }
    validate_trial(&minimal).unwrap();
    let typed: Trial = serde_json::from_value(minimal).unwrap();
    assert!(typed.forces.is_empty() && typed.start_pose.is_none());
}

#[test]
fn a_trial_cannot_finish_before_it_starts() {
    let mut early = trial();
    early["finished_at"] = json!("2024-05-01T11:59:59Z");
    let errors = rejected(&early);
    assert_eq!(pointers(&errors), ["/finished_at"]);
    assert!(errors.errors()[0].message.contains("before started_at"), "{errors}");

    let mut same = trial();
    same["finished_at"] = same["started_at"].clone();
    validate_trial(&same).unwrap();
}

#[test]
fn every_problem_is_reported_at_once() {
    let mut bad = trial();
    bad["id"] = json!("trial-1");
    bad["robot"] = json!("EL-E");
    bad["outcome"] = json!("ok");
    bad["confirmed"] = json!("yes");
    bad["started_at"] = json!("yesterday");
    bad["forces"] = json!([{"t": -1, "finger": "thumb", "force": [1, 2]}]);
    bad["start_pose"] = json!({"x": 0, "y": 0, "yaw": 7});
    bad["weather"] = json!("rain");
    let errors = rejected(&bad);
    assert_eq!(
        pointers(&errors),
        [
            "/confirmed",
            "/forces/0/finger",
            "/forces/0/force",
            "/forces/0/t",
            "/id",
            "/outcome",
            "/robot",
            "/start_pose/yaw",
            "/started_at",
            "/weather",
        ],
        "{errors}"
    );
    let started = errors.at("/started_at").next().unwrap();
    assert!(started.message.contains("RFC 3339"), "{started}");
}

#[test]
fn force_samples_are_capped() {
    let sample = json!({"t": 0.0, "finger": "left", "force": [0.0, 0.0, 0.0]});
    let mut full = trial();
    full["forces"] = Value::Array(vec![sample.clone(); MAX_FORCE_SAMPLES]);
    validate_trial(&full).unwrap();
    full["forces"].as_array_mut().unwrap().push(sample);
    let errors = rejected(&full);
    assert_eq!(pointers(&errors), ["/forces"]);
    assert!(errors.errors()[0].message.contains("5000"), "{errors}");
}

#[test]
fn the_registrys_fields_are_allowed_on_output() {
    let mut stored = trial();
    stored["received_at"] = json!("2024-05-01T12:00:42Z");
    stored["seq"] = json!(17);
    validate_trial(&stored).unwrap();
    let typed: Trial = serde_json::from_value(stored.clone()).unwrap();
    assert_eq!(typed.seq, Some(17));
    pps_schema::strip_fields(&mut stored, pps_schema::READ_ONLY_TRIAL_FIELDS);
    assert_eq!(stored, trial());
}

#[test]
fn the_cap_is_the_schemas() {
    let schema = pps_schema::schema_document("trial").unwrap();
    assert_eq!(schema["properties"]["forces"]["maxItems"], json!(MAX_FORCE_SAMPLES));
}

#[test]
fn a_trial_says_why_it_was_made_and_real_use_goes_without_saying() {
    let typed: Trial = serde_json::from_value(trial()).unwrap();
    assert_eq!(typed.purpose, Purpose::Use);
    assert!(serde_json::to_value(&typed).unwrap().get("purpose").is_none());

    let mut experiment = trial();
    experiment["purpose"] = json!("experiment");
    validate_trial(&experiment).unwrap();
    let typed: Trial = serde_json::from_value(experiment.clone()).unwrap();
    assert_eq!(typed.purpose, Purpose::Experiment);
    assert_eq!(serde_json::to_value(&typed).unwrap()["purpose"], "experiment");

    experiment["purpose"] = json!("demo");
    let errors = rejected(&experiment);
    assert_eq!(pointers(&errors), ["/purpose"]);
    assert_eq!(
        errors.errors()[0].message,
        "purpose is \"demo\"; it must be one of \"use\", \"experiment\", \"test\"."
    );
}
