//! The paper's Table I protocol (§V): 48 trials in the simulator against an in-process
//! registry, every one of them stored there. All 48 must come out right (the paper got 43).

mod support;

use pps_robot::cli::{flush_until_stored, render_table, run_trials};

#[tokio::test(flavor = "multi_thread")]
async fn table_one_protocol() {
    let dir = tempfile::tempdir().unwrap();
    let registry = support::Registry::start(dir.path()).await;
    let client = registry.client(dir.path());
    let rows = run_trials(&client, 0, None, false).await.unwrap();
    flush_until_stored(&client).await.unwrap();
    println!("{}", render_table(&rows, false));

    let trials: u32 = rows.iter().map(|r| r.trials).sum();
    assert_eq!(trials, 48);
    assert_eq!(registry.trials().await.len(), 48, "every trial is stored in the registry");
    let successes: u32 = rows.iter().map(|r| r.successes).sum();
    assert_eq!(successes, 48, "every trial right:\n{}", render_table(&rows, false));
}
