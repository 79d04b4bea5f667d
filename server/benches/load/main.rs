//! Load benchmark: simulated robots over HTTP against the real `pps-server` release binary.
//!
//! ```sh
//! cargo bench -p pps-server --bench load                      # 10 s per phase, 64 connections
//! cargo bench -p pps-server --bench load -- --seconds 5 --connections 32 --tags 10,100000
//! cargo bench -p pps-server --bench load -- --postgres postgres://pps@127.0.0.1:5432/postgres
//! ```
//!
//! For each registry size it measures effective-entry reads (plain and revalidated with
//! `If-None-Match`, answered 304) and durable trial writes, and prints req/s, p50 and p99 per
//! operation and the server's resident memory. With `--postgres CLUSTER` (or
//! `PPS_TEST_POSTGRES`, as the test command sets it), each size runs again on a new database in
//! that PostgreSQL cluster, served by two replicas the connections are spread over. When `nginx`
//! is installed, the same generator also fetches the same JSON as a static file from nginx, and
//! with `wrk` installed too, `wrk -t2 -c64` compares the two on equal terms (`nginx.rs`), so
//! the two are compared in one run.
//! The generator shares the machine's cores with the server, as a robot fleet's LAN would not;
//! compare ratios measured in one run, not absolute figures across machines.
//!
//! Long because the fleet of simulated robots, the phases and the report share their types;
//! the comparison with nginx is `nginx.rs`.

use std::net::TcpListener;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Context;
use pps_server::identity::Role;
use pps_server::store::db::Location;
use pps_server::store::{robots, tokens};
use pps_server::{Db, tags::seed};
use pps_test_kit::process::memory_kib;
use pps_test_kit::wait::try_wait_until;
use serde_json::{Value, json};

mod nginx;

const BIN: &str = env!("CARGO_BIN_EXE_pps-server");

/// Robots per class writing trials and reading entries; tokens are bound to them.
const ROBOTS: [(&str, &str); 4] =
    [("el-e-1", "el-e"), ("el-e-2", "el-e"), ("pr2-1", "pr2"), ("pr2-2", "pr2")];
/// Tags the robots read during a phase (a working set, as robots at work read a few tags).
const WORKING_SET: usize = 2_000;

struct Options {
    seconds: u64,
    connections: usize,
    tag_counts: Vec<usize>,
    /// A PostgreSQL cluster to run every size on as well.
    postgres: Option<String>,
}

fn options() -> Options {
    let mut options = Options {
        seconds: 10,
        connections: 64,
        tag_counts: vec![10, 100_000],
        postgres: std::env::var("PPS_TEST_POSTGRES").ok(),
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--seconds" => options.seconds = value.parse().expect("--seconds N"),
            "--connections" => options.connections = value.parse().expect("--connections N"),
            "--postgres" => options.postgres = Some(value),
            "--tags" => {
                options.tag_counts =
                    value.split(',').map(|n| n.parse().expect("--tags N,M")).collect()
            }
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

/// One operation's results.
struct Measured {
    requests: usize,
    elapsed: Duration,
    latencies_us: Vec<u32>,
    failures: usize,
}

impl Measured {
    fn percentile(&self, p: f64) -> f64 {
        if self.latencies_us.is_empty() {
            return f64::NAN;
        }
        let index = ((self.latencies_us.len() - 1) as f64 * p).round() as usize;
        f64::from(self.latencies_us[index]) / 1000.0
    }

    fn print(&self, name: &str) {
        println!(
            "  {name:<34} {:>9.0} req/s   p50 {:>6.2} ms   p99 {:>6.2} ms   ({} requests, {} failed)",
            self.requests as f64 / self.elapsed.as_secs_f64(),
            self.percentile(0.5),
            self.percentile(0.99),
            self.requests,
            self.failures
        );
    }
}

/// What one simulated robot connection does once.
#[derive(Clone)]
enum Operation {
    Read { revalidate: bool },
    WriteTrial,
    Static { url: String },
}

/// The registry under load: one SQLite server, or replicas on one PostgreSQL database.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Store {
    Sqlite,
    Postgres,
}

/// Replicas served on PostgreSQL.
const REPLICAS: usize = 2;

struct Fleet {
    /// The replicas; connection `i` talks to `urls[i % urls.len()]`.
    urls: Vec<String>,
    tokens: Vec<(String, String)>,
    epcs: Vec<String>,
    etags: std::collections::HashMap<(String, String), String>,
}

fn main() -> anyhow::Result<()> {
    let options = options();
    let runtime =
        tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    println!(
        "PPS-tag registry load benchmark: {} connections, {} s per phase, server {}",
        options.connections, options.seconds, BIN
    );
    let mut stores = vec![Store::Sqlite];
    if options.postgres.is_some() {
        stores.push(Store::Postgres);
    }
    for &tags in &options.tag_counts {
        for &store in &stores {
            runtime.block_on(run(&options, tags, store))?;
        }
    }
    Ok(())
}

async fn run(options: &Options, tag_count: usize, store: Store) -> anyhow::Result<()> {
    let dir = tempfile::tempdir()?;
    let (location, replicas) = match (store, &options.postgres) {
        (Store::Postgres, Some(cluster)) => {
            (pps_test_kit::postgres::fresh_database_in(cluster).await?, REPLICAS)
        }
        _ => (Location::File(dir.path().join("bench.db")), 1),
    };
    let prepared = Instant::now();
    let (epcs, tokens) = prepare(&location, tag_count).await?;
    let client = client(options.connections)?;
    let mut servers = Vec::new();
    let mut urls = Vec::new();
    for _ in 0..replicas {
        let port = free_port()?;
        servers.push(
            Command::new(BIN)
                .args(["serve", "--listen", &format!("127.0.0.1:{port}"), "--db"])
                .arg(location.as_db_arg())
                .env("RUST_LOG", "warn")
                .stderr(Stdio::null())
                .spawn()?,
        );
        let url = format!("http://127.0.0.1:{port}");
        wait_until_up(&client, &url).await?;
        urls.push(url);
    }
    let engine = match store {
        Store::Sqlite => "SQLite, one server".to_owned(),
        Store::Postgres => format!("PostgreSQL, {replicas} replicas"),
    };
    println!(
        "\n{tag_count} tags on {engine} (prepared in {:.1} s)",
        prepared.elapsed().as_secs_f64()
    );

    let working: Vec<String> =
        epcs.iter().step_by((epcs.len() / WORKING_SET).max(1)).cloned().collect();
    let mut fleet = Fleet { urls: urls.clone(), tokens, epcs: working, etags: Default::default() };
    // Warm every replica's cache and learn each entry's ETag, as robots that read the tag
    // before would; the ETag is the content's hash, the same from every replica.
    for url in &urls {
        for (robot, token) in &fleet.tokens {
            for epc in &fleet.epcs {
                let response = client
                    .get(format!("{url}/api/v1/robots/{robot}/tags/{epc}"))
                    .bearer_auth(token)
                    .send()
                    .await?;
                let etag = response.headers()["etag"].to_str()?.to_owned();
                fleet.etags.insert((robot.clone(), epc.clone()), etag);
            }
        }
    }
    let fleet = Arc::new(fleet);
    let duration = Duration::from_secs(options.seconds);
    for (name, operation) in [
        ("effective entry, full read", Operation::Read { revalidate: false }),
        ("effective entry, If-None-Match 304", Operation::Read { revalidate: true }),
        ("trial write (durable)", Operation::WriteTrial),
    ] {
        let measured = measure(&client, &fleet, operation, options.connections, duration).await;
        measured.print(name);
    }
    for server in &servers {
        println!(
            "  server resident memory: {}",
            memory(server).unwrap_or_else(|| "unknown".into())
        );
    }
    if tag_count == *options.tag_counts.first().unwrap_or(&0) {
        nginx::compare(&client, &fleet, options, duration).await?;
    }
    for server in &mut servers {
        stop(server);
    }
    Ok(())
}

/// A database with `tag_count` tags, the robots registered and their tokens minted.
async fn prepare(
    location: &Location,
    tag_count: usize,
) -> anyhow::Result<(Vec<String>, Vec<(String, String)>)> {
    let db = Db::open(location).await?;
    let seeds = seed::seed_entries()?;
    let mut entries = Vec::with_capacity(tag_count);
    for n in 0..tag_count {
        let mut entry = seeds[n % seeds.len()].clone();
        entry["epc"] = format!("E2BE0000{n:016X}").into();
        entry["properties"]["name"] =
            format!("{} {n}", entry["properties"]["type"].as_str().unwrap_or("tag")).into();
        entries.push(entry);
    }
    let epcs = entries.iter().map(|e| e["epc"].as_str().unwrap_or_default().to_owned()).collect();
    seed::import(&db, entries, "bench").await?;
    tokens::create(&db, Role::Admin, "bench admin", None).await?;
    let mut minted = Vec::new();
    for (id, class) in ROBOTS {
        let robot = json!({ "id": id, "class": class, "name": id, "capabilities": ["light_switch", "pull_back", "push", "pull_lamp", "drop"], "limits": { "max_force": 40.0 } });
        robots::put(&db, &pps_schema::RobotId::parse(id)?, &robot, "bench").await?;
        minted.push((id.to_owned(), tokens::create(&db, Role::Robot, id, None).await?.token));
    }
    db.close().await;
    Ok((epcs, minted))
}

async fn measure(
    client: &reqwest::Client,
    fleet: &Arc<Fleet>,
    operation: Operation,
    connections: usize,
    duration: Duration,
) -> Measured {
    let started = Instant::now();
    let deadline = started + duration;
    let mut tasks = tokio::task::JoinSet::new();
    for connection in 0..connections {
        let (client, fleet, operation) = (client.clone(), fleet.clone(), operation.clone());
        tasks.spawn(async move {
            let (robot, token) = &fleet.tokens[connection % fleet.tokens.len()];
            let url = &fleet.urls[connection % fleet.urls.len()];
            let mut latencies = Vec::with_capacity(50_000);
            let mut failures = 0;
            let mut n = connection;
            while Instant::now() < deadline {
                n += connections;
                let epc = &fleet.epcs[n % fleet.epcs.len()];
                let sent = Instant::now();
                let ok = match &operation {
                    Operation::Read { revalidate } => {
                        let mut request = client
                            .get(format!("{url}/api/v1/robots/{robot}/tags/{epc}"))
                            .bearer_auth(token);
                        if *revalidate {
                            request = request.header(
                                "if-none-match",
                                &fleet.etags[&(robot.clone(), epc.clone())],
                            );
                        }
                        match request.send().await {
                            Ok(response) => {
                                let expected = if *revalidate { 304 } else { 200 };
                                response.status().as_u16() == expected
                                    && response.bytes().await.is_ok()
                            }
                            Err(_) => false,
                        }
                    }
                    Operation::WriteTrial => {
                        let id = uuid::Uuid::new_v4().to_string();
                        let body = trial(&id, epc, robot);
                        match client
                            .put(format!("{url}/api/v1/trials/{id}"))
                            .bearer_auth(token)
                            .json(&body)
                            .send()
                            .await
                        {
                            Ok(response) => {
                                response.status().as_u16() == 201 && response.bytes().await.is_ok()
                            }
                            Err(_) => false,
                        }
                    }
                    Operation::Static { url } => match client.get(url).send().await {
                        Ok(response) => {
                            response.status().is_success() && response.bytes().await.is_ok()
                        }
                        Err(_) => false,
                    },
                };
                latencies.push(sent.elapsed().as_micros().min(u128::from(u32::MAX)) as u32);
                failures += usize::from(!ok);
            }
            (latencies, failures)
        });
    }
    let mut measured =
        Measured { requests: 0, elapsed: Duration::ZERO, latencies_us: Vec::new(), failures: 0 };
    while let Some(Ok((latencies, failures))) = tasks.join_next().await {
        measured.requests += latencies.len();
        measured.latencies_us.extend(latencies);
        measured.failures += failures;
    }
    measured.elapsed = started.elapsed();
    measured.latencies_us.sort_unstable();
    measured
}

fn trial(id: &str, epc: &str, robot: &str) -> Value {
    json!({
        "id": id, "epc": epc, "robot": robot, "action": "on", "behavior": "push_top",
        "started_at": "2026-11-22T10:00:00Z", "finished_at": "2026-11-22T10:00:20Z",
        "outcome": "success", "confirmed": null, "detector": { "brightness_change": -0.21 },
        "forces": [ { "t": 0.5, "finger": "left", "force": [0.1, 0.2, 2.9] } ],
        "measurements": {}
    })
}

fn which(program: &str) -> std::io::Result<std::path::PathBuf> {
    std::env::var_os("PATH")
        .iter()
        .flat_map(std::env::split_paths)
        .chain(["/usr/sbin".into(), "/sbin".into()])
        .map(|dir| dir.join(program))
        .find(|path| path.is_file())
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, program.to_owned()))
}

fn client(connections: usize) -> reqwest::Result<reqwest::Client> {
    reqwest::Client::builder()
        .pool_max_idle_per_host(connections)
        .timeout(Duration::from_secs(30))
        .build()
}

async fn wait_until_up(client: &reqwest::Client, url: &str) -> anyhow::Result<()> {
    let answers = || async { client.get(format!("{url}/healthz")).send().await.ok().map(drop) };
    try_wait_until(Duration::from_secs(10), answers).await.context("the server did not come up")
}

fn free_port() -> std::io::Result<u16> {
    Ok(TcpListener::bind("127.0.0.1:0")?.local_addr()?.port())
}

/// Current and peak resident memory of the server process.
fn memory(child: &Child) -> Option<String> {
    let (now, peak) = (memory_kib(child.id(), "VmRSS")?, memory_kib(child.id(), "VmHWM")?);
    Some(format!("{} MB now, {} MB peak", now / 1024, peak / 1024))
}

fn stop(child: &mut Child) {
    let _ = Command::new("kill").arg("-TERM").arg(child.id().to_string()).status();
    let _ = child.wait();
}
