//! Task benchmark: robots long-polling for tasks over HTTP against the registry, in-process.
//!
//! ```sh
//! cargo bench -p pps-server --bench tasks                     # 64 robots, 300 tasks, 2000 claims
//! cargo bench -p pps-server --bench tasks -- --robots 16 --asks 100 --claims 500
//! ```
//!
//! Two phases. **Claim to answer**: every robot waits in a long poll (`wait=30`); a caretaker
//! asks for one task at a time, and the time from sending the ask to the waiting robot holding
//! the task is measured (the ask's own round trip included), once all robots wait again.
//! **Contention**: many tasks are queued, then every robot claims without waiting as fast as it
//! can until the queue is empty: claims per second, and each claim's p50 and p99. The robots and
//! the registry share the machine's cores; compare figures measured on one machine.

use std::time::{Duration, Instant};

use pps_server::identity::Role;
use pps_server::store::{robots, tokens};
use pps_server::{AppState, Db, tags::seed};
use serde_json::{Value, json};

const ADA_SWITCH: &str = "355AB1C60000002000000001";

struct Options {
    robots: usize,
    asks: usize,
    claims: usize,
}

fn options() -> Options {
    let mut options = Options { robots: 64, asks: 300, claims: 2000 };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--robots" => options.robots = value.parse().expect("--robots N"),
            "--asks" => options.asks = value.parse().expect("--asks N"),
            "--claims" => options.claims = value.parse().expect("--claims N"),
            // `cargo bench` passes --bench; other flags are not ours.
            _ => {
                i += 1;
                continue;
            }
        }
        i += 2;
    }
    options
}

fn percentile(sorted: &[Duration], p: f64) -> f64 {
    let index = ((sorted.len().saturating_sub(1)) as f64 * p).round() as usize;
    sorted.get(index).map_or(f64::NAN, |d| d.as_secs_f64() * 1000.0)
}

fn main() -> anyhow::Result<()> {
    let options = options();
    tokio::runtime::Builder::new_multi_thread().enable_all().build()?.block_on(run(&options))
}

async fn run(options: &Options) -> anyhow::Result<()> {
    let dir = tempfile::tempdir()?;
    let db = Db::open_file(&dir.path().join("pps.db")).await?;
    seed::seed_if_empty(&db).await?;
    let admin = tokens::create(&db, Role::Admin, "bench", None).await?.token;
    let mut fleet = Vec::new();
    for n in 0..options.robots {
        let id = format!("robot-{n}");
        let class = if n % 2 == 0 { "el-e" } else { "stretch" };
        let document = json!({ "id": id, "class": class, "name": id,
            "capabilities": ["light_switch", "pull_back", "push", "pull_lamp", "drop"],
            "limits": { "max_force": 40.0 } });
        robots::put(&db, &pps_schema::RobotId::parse(&id)?, &document, "bench").await?;
        fleet.push((id.clone(), tokens::create(&db, Role::Robot, &id, None).await?.token));
    }
    // The contention phase measures claims alone: its robots never finish what they hold.
    let state = AppState::new(db).with_max_tasks_per_robot(usize::MAX);
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await?;
    let url = format!("http://{}", listener.local_addr()?);
    tokio::spawn(pps_server::serve(listener, state.clone(), std::future::pending()));
    let client = reqwest::Client::builder().pool_max_idle_per_host(options.robots + 8).build()?;
    println!(
        "{} robots, {} asks one at a time, {} claims under contention",
        options.robots, options.asks, options.claims
    );
    claim_to_answer(&state, &client, &url, &admin, &fleet, options.asks).await?;
    contention(&client, &url, &admin, &fleet, options.claims).await
}

async fn ask(client: &reqwest::Client, url: &str, admin: &str) -> anyhow::Result<String> {
    let body = json!({ "epc": ADA_SWITCH, "action": "off" });
    let response =
        client.post(format!("{url}/api/v1/tasks")).bearer_auth(admin).json(&body).send().await?;
    anyhow::ensure!(response.status() == 201, "ask: {}", response.status());
    Ok(response.json::<Value>().await?["id"].as_str().unwrap_or_default().to_owned())
}

async fn claim(
    client: &reqwest::Client,
    url: &str,
    (robot, token): &(String, String),
    wait: u32,
) -> anyhow::Result<Option<String>> {
    let path = format!("{url}/api/v1/robots/{robot}/tasks/claim?wait={wait}");
    let response = client.post(path).bearer_auth(token).send().await?;
    match response.status().as_u16() {
        204 => Ok(None),
        200 => Ok(Some(response.json::<Value>().await?["id"].as_str().unwrap_or_default().into())),
        other => anyhow::bail!("claim: {other}"),
    }
}

/// A new task's way to one of many waiting robots.
async fn claim_to_answer(
    state: &AppState,
    client: &reqwest::Client,
    url: &str,
    admin: &str,
    fleet: &[(String, String)],
    asks: usize,
) -> anyhow::Result<()> {
    let (got, mut arrivals) = tokio::sync::mpsc::unbounded_channel::<(String, Instant)>();
    let waiting: Vec<_> = fleet
        .iter()
        .cloned()
        .map(|robot| {
            let (client, url, got) = (client.clone(), url.to_owned(), got.clone());
            tokio::spawn(async move {
                loop {
                    match claim(&client, &url, &robot, 30).await {
                        Ok(Some(task)) => {
                            let _ = got.send((task, Instant::now()));
                        }
                        Ok(None) => {}
                        Err(error) => return eprintln!("{}: {error}", robot.0),
                    }
                }
            })
        })
        .collect();
    let mut latencies = Vec::with_capacity(asks);
    for _ in 0..asks {
        let everyone_waits = Instant::now() + Duration::from_secs(10);
        while state.tasks.waiting() < fleet.len() {
            anyhow::ensure!(Instant::now() < everyone_waits, "the robots stopped waiting");
            tokio::task::yield_now().await;
        }
        let sent = Instant::now();
        let id = ask(client, url, admin).await?;
        let (claimed, at) = arrivals.recv().await.ok_or_else(|| anyhow::anyhow!("no robot"))?;
        anyhow::ensure!(claimed == id, "a robot got {claimed}, not the task just asked for");
        latencies.push(at - sent);
    }
    for robot in waiting {
        robot.abort();
    }
    latencies.sort();
    println!(
        "claim to answer, {} robots waiting: p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms ({} asks)",
        fleet.len(),
        percentile(&latencies, 0.5),
        percentile(&latencies, 0.99),
        percentile(&latencies, 1.0),
        latencies.len()
    );
    Ok(())
}

/// Every robot claiming as fast as it can from one queue.
async fn contention(
    client: &reqwest::Client,
    url: &str,
    admin: &str,
    fleet: &[(String, String)],
    claims: usize,
) -> anyhow::Result<()> {
    for _ in 0..claims {
        ask(client, url, admin).await?;
    }
    let started = Instant::now();
    let claimers: Vec<_> = fleet
        .iter()
        .cloned()
        .map(|robot| {
            let (client, url) = (client.clone(), url.to_owned());
            tokio::spawn(async move {
                let mut took = Vec::new();
                loop {
                    let sent = Instant::now();
                    match claim(&client, &url, &robot, 0).await? {
                        Some(_) => took.push(sent.elapsed()),
                        None => return anyhow::Ok(took),
                    }
                }
            })
        })
        .collect();
    let mut latencies = Vec::new();
    for claimer in claimers {
        latencies.extend(claimer.await??);
    }
    let elapsed = started.elapsed();
    anyhow::ensure!(latencies.len() == claims, "{} of {claims} tasks claimed", latencies.len());
    latencies.sort();
    println!(
        "contention, {} robots claiming {claims} tasks: {:.0} claims/s, p50 {:.2} ms, p99 {:.2} ms",
        fleet.len(),
        claims as f64 / elapsed.as_secs_f64(),
        percentile(&latencies, 0.5),
        percentile(&latencies, 0.99)
    );
    Ok(())
}
