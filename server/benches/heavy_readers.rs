//! Heavy readers that never read: how long a third host waits while two hosts each hold many
//! connections that pipeline requests for 4 MiB trial pages and never take the answers.
//!
//! ```sh
//! cargo bench -p pps-server --bench heavy_readers
//! cargo bench -p pps-server --bench heavy_readers -- --hosts 3 --connections 32 --seconds 20
//! cargo bench -p pps-server --bench heavy_readers -- --server path/to/older/pps-server
//! cargo bench -p pps-server --bench heavy_readers -- --serve "--max-connections 64"
//! ```
//!
//! It prepares a registry whose robot has trials with many force samples, so that one page of
//! `GET /api/v1/trials?limit=500&include=forces` is about 4 MiB, and first measures where one
//! such page's time goes: the query, turning the stored rows into the answer, and the whole
//! request over HTTP. Then `--hosts` addresses (127.0.0.8 and up) each open `--connections`
//! connections with a small receive buffer that ask for that page `--pipelined` times in one
//! go and never read. Meanwhile 127.0.0.100 asks for `/healthz` and, as an admin, for the tag
//! list, one after the other, for `--seconds`; the report gives their waits, the server's CPU
//! time and its memory. The generator shares the machine's cores with the server.

use std::net::{IpAddr, SocketAddr};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use futures_util::StreamExt;
use pps_server::answers::trials::StoredTrialAnswer;
use pps_server::identity::Role;
use pps_server::store::db::Location;
use pps_server::store::trials::{self, Window};
use pps_server::store::{robots, tokens};
use pps_server::trials::filter::TrialFilter;
use pps_server::{Db, tags::seed};
use pps_test_kit::process::memory_kib;
use pps_test_kit::wait::try_wait_until;
use serde_json::{Value, json};
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpSocket, TcpStream};

const BIN: &str = env!("CARGO_BIN_EXE_pps-server");
const ROBOT: &str = "el-e-1";
const HEAVY_PAGE: &str = "/api/v1/trials?limit=500&include=forces";

struct Options {
    hosts: u8,
    connections: usize,
    pipelined: usize,
    seconds: u64,
    trials: usize,
    samples: usize,
    /// Extra flags for `serve`.
    serve_flags: Vec<String>,
    /// Another build of the server to measure (an older one, say).
    server: String,
}

fn options() -> Options {
    let mut options = Options {
        hosts: 2,
        connections: 32,
        pipelined: 60,
        seconds: 15,
        trials: 500,
        samples: 500,
        serve_flags: Vec::new(),
        server: BIN.to_owned(),
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--hosts" => options.hosts = value.parse().expect("--hosts N"),
            "--connections" => options.connections = value.parse().expect("--connections N"),
            "--pipelined" => options.pipelined = value.parse().expect("--pipelined N"),
            "--seconds" => options.seconds = value.parse().expect("--seconds N"),
            "--trials" => options.trials = value.parse().expect("--trials N"),
            "--samples" => options.samples = value.parse().expect("--samples N"),
            "--server" => options.server = value,
            "--serve" => options.serve_flags = value.split_whitespace().map(String::from).collect(),
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

fn main() -> anyhow::Result<()> {
    let options = options();
    let runtime =
        tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    runtime.block_on(run(&options))
}

async fn run(options: &Options) -> anyhow::Result<()> {
    let dir = tempfile::tempdir()?;
    let location = Location::File(dir.path().join("bench.db"));
    let (epc, admin, robot) = prepare(&location).await?;
    let port = std::net::TcpListener::bind("127.0.0.1:0")?.local_addr()?.port();
    let url = format!("http://127.0.0.1:{port}");
    let mut server = Command::new(&options.server)
        .args(["serve", "--listen", &format!("127.0.0.1:{port}"), "--db"])
        .arg(location.as_db_arg())
        .args(&options.serve_flags)
        .env("RUST_LOG", "warn")
        .stderr(Stdio::null())
        .spawn()?;
    let client = reqwest::Client::builder().timeout(Duration::from_secs(60)).build()?;
    wait_until_up(&client, &url).await?;
    let seeded = Instant::now();
    record_trials(&client, &url, &robot, &epc, options).await?;
    println!(
        "{} trials of {} force samples recorded in {:.1} s",
        options.trials,
        options.samples,
        seeded.elapsed().as_secs_f64()
    );
    one_page(&location, &client, &url, &robot).await?;

    let cpu_before = cpu_seconds(&server);
    let attack = Instant::now();
    let mut hogs = Vec::new();
    for host in 0..options.hosts {
        let source = IpAddr::from([127, 0, 0, 8 + host]);
        for _ in 0..options.connections {
            if let Some(hog) = non_reader(port, source, &robot, options.pipelined).await {
                hogs.push(hog);
            }
        }
    }
    println!(
        "{} hosts opened {} non-reading connections in {:.2} s, each asking {} pages",
        options.hosts,
        hogs.len(),
        attack.elapsed().as_secs_f64(),
        options.pipelined
    );
    let third = reqwest::Client::builder()
        .local_address(IpAddr::from([127, 0, 0, 100]))
        .timeout(Duration::from_secs(60))
        .build()?;
    let (mut health, mut tags) = (Vec::new(), Vec::new());
    let until = attack + Duration::from_secs(options.seconds);
    while Instant::now() < until {
        health.push(timed(third.get(format!("{url}/healthz"))).await?);
        tags.push(timed(third.get(format!("{url}/api/v1/tags")).bearer_auth(&admin)).await?);
        #[allow(clippy::disallowed_methods, reason = "the probe asks ten times a second")]
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let cpu = cpu_seconds(&server) - cpu_before;
    println!(
        "during {:.1} s of it: server CPU {cpu:.1} s ({:.0} % of one core), {}",
        attack.elapsed().as_secs_f64(),
        100.0 * cpu / attack.elapsed().as_secs_f64(),
        memory(&server).unwrap_or_else(|| "memory unknown".into())
    );
    report("/healthz from a third host", &mut health);
    report("GET /api/v1/tags as admin from a third host", &mut tags);
    drop(hogs);
    let _ = Command::new("kill").arg("-TERM").arg(server.id().to_string()).status();
    let _ = server.wait();
    Ok(())
}

/// A database with one tag, the robot registered, an admin token and the robot's token.
async fn prepare(location: &Location) -> anyhow::Result<(String, String, String)> {
    let db = Db::open(location).await?;
    let mut entry = seed::seed_entries()?.remove(0);
    let epc = "E2BE00000000000000000001".to_owned();
    entry["epc"] = epc.clone().into();
    seed::import(&db, vec![entry], "bench").await?;
    let admin = tokens::create(&db, Role::Admin, "bench admin", None).await?.token;
    let robot = json!({ "id": ROBOT, "class": "el-e", "name": ROBOT, "capabilities": ["light_switch"], "limits": { "max_force": 40.0 } });
    robots::put(&db, &pps_schema::RobotId::parse(ROBOT)?, &robot, "bench").await?;
    let token = tokens::create(&db, Role::Robot, ROBOT, None).await?.token;
    db.close().await;
    Ok((epc, admin, token))
}

/// Trials with `samples` force samples each, as a gripper's sensor reports them.
async fn record_trials(
    client: &reqwest::Client,
    url: &str,
    token: &str,
    epc: &str,
    options: &Options,
) -> anyhow::Result<()> {
    let puts = (0..options.trials).map(|n| {
        let forces: Vec<Value> = (0..options.samples)
            .map(|s| {
                let x = (n * options.samples + s) as f64;
                json!({ "t": s as f64 * 0.01, "finger": if s % 2 == 0 { "left" } else { "right" },
                        "force": [(x * 0.37).sin() * 3.1, (x * 0.11).cos() * 1.7, 2.9 + (x * 0.05).sin()] })
            })
            .collect();
        let id = format!("00000000-0000-4000-8000-{n:012}");
        let trial = json!({
            "id": id, "epc": epc, "robot": ROBOT, "action": "on", "behavior": "push_top",
            "started_at": "2026-11-22T10:00:00Z", "finished_at": "2026-11-22T10:00:20Z",
            "outcome": "success", "detector": { "brightness_change": -0.21 },
            "forces": forces, "measurements": {}
        });
        let request =
            client.put(format!("{url}/api/v1/trials/{id}")).bearer_auth(token).json(&trial);
        async move {
            let response = request.send().await?;
            anyhow::ensure!(response.status().is_success(), "trial {n}: {}", response.status());
            Ok(())
        }
    });
    let results: Vec<anyhow::Result<()>> =
        futures_util::stream::iter(puts).buffer_unordered(8).collect().await;
    results.into_iter().collect()
}

/// Where one heavy page's time goes, each part alone, on a quiet server.
async fn one_page(
    location: &Location,
    client: &reqwest::Client,
    url: &str,
    token: &str,
) -> anyhow::Result<()> {
    let db = Db::open_existing(location).await?;
    let filter =
        TrialFilter { robot: Some(pps_schema::RobotId::parse(ROBOT)?), ..Default::default() };
    let window = Window { after: 0, limit: 501, max_bytes: 4 << 20, forces: true };
    let (mut query, mut values, mut written, mut http) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut shape = (0, 0);
    for _ in 0..7 {
        let started = Instant::now();
        let (rows, _) = trials::list(db.reader(), &filter, window).await?;
        query.push(started.elapsed());
        let started = Instant::now();
        // What answers cost before: each stored body decoded into values and printed again.
        let mut reprinted = 0;
        for row in &rows {
            let value: serde_json::Value = serde_json::from_str(&row.body)?;
            reprinted += value.to_string().len();
        }
        values.push(started.elapsed());
        let started = Instant::now();
        let mut text = Vec::new();
        for row in &rows {
            serde_json::to_writer(&mut text, &StoredTrialAnswer::from(row))?;
        }
        written.push(started.elapsed());
        anyhow::ensure!(text.len() >= reprinted, "the answers hold every stored value");
        let bytes = text.len();
        shape = (rows.len(), bytes);
        let started = Instant::now();
        let page = client
            .get(format!("{url}{HEAVY_PAGE}"))
            .bearer_auth(token)
            .send()
            .await?
            .error_for_status()?
            .bytes()
            .await?;
        http.push(started.elapsed());
        anyhow::ensure!(page.len() >= bytes, "the page has {} bytes", page.len());
    }
    db.close().await;
    println!("one page alone: {} trials, {:.2} MiB", shape.0, shape.1 as f64 / 1048576.0);
    for (part, times) in [
        ("query", &mut query),
        ("bodies decoded and printed again", &mut values),
        ("answers with stored values copied", &mut written),
        ("whole request over HTTP", &mut http),
    ] {
        times.sort_unstable();
        println!(
            "  {part:<24} median {:>7.1} ms, fastest {:>7.1} ms",
            times[times.len() / 2].as_secs_f64() * 1e3,
            times[0].as_secs_f64() * 1e3
        );
    }
    Ok(())
}

/// A connection from `source` asking for the heavy page `times` times and never reading;
/// `None` when the server closed it at once (beyond the host's share).
async fn non_reader(port: u16, source: IpAddr, token: &str, times: usize) -> Option<TcpStream> {
    let socket = TcpSocket::new_v4().ok()?;
    socket.set_recv_buffer_size(4096).ok()?;
    socket.bind(SocketAddr::new(source, 0)).ok()?;
    let mut stream = socket.connect(SocketAddr::from(([127, 0, 0, 1], port))).await.ok()?;
    let request = format!(
        "GET {HEAVY_PAGE} HTTP/1.1\r\nhost: registry\r\nauthorization: Bearer {token}\r\n\r\n"
    )
    .repeat(times);
    stream.write_all(request.as_bytes()).await.ok()?;
    Some(stream)
}

async fn timed(request: reqwest::RequestBuilder) -> anyhow::Result<Duration> {
    let started = Instant::now();
    let response = request.send().await?;
    anyhow::ensure!(response.status().is_success(), "{}", response.status());
    response.bytes().await?;
    Ok(started.elapsed())
}

fn report(what: &str, waits: &mut [Duration]) {
    waits.sort_unstable();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "{what}: {} answers, median {:.1} ms, p90 {:.1} ms, slowest {:.1} ms",
        waits.len(),
        ms(waits[waits.len() / 2]),
        ms(waits[waits.len() * 9 / 10]),
        ms(waits[waits.len() - 1])
    );
}

async fn wait_until_up(client: &reqwest::Client, url: &str) -> anyhow::Result<()> {
    let answers = || async { client.get(format!("{url}/healthz")).send().await.ok().map(drop) };
    try_wait_until(Duration::from_secs(10), answers)
        .await
        .ok_or_else(|| anyhow::anyhow!("the server did not come up"))
}

/// User and system CPU time of the server so far.
fn cpu_seconds(child: &Child) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{}/stat", child.id())).unwrap_or_default();
    // Fields after the command name, which is in parentheses and may hold spaces.
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map(|(_, rest)| rest.split_whitespace().collect())
        .unwrap_or_default();
    let ticks = |n: usize| fields.get(n).and_then(|f| f.parse::<f64>().ok()).unwrap_or(0.0);
    // utime and stime are the 14th and 15th fields; the rest starts at the 3rd.
    (ticks(11) + ticks(12)) / 100.0
}

/// Current and peak resident memory of the server process.
fn memory(child: &Child) -> Option<String> {
    let (now, peak) = (memory_kib(child.id(), "VmRSS")?, memory_kib(child.id(), "VmHWM")?);
    Some(format!("RSS {} MB now, {} MB peak", now / 1024, peak / 1024))
}
