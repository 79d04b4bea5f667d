//! The hot path against nginx serving the same JSON as a static file, in one run: first with
//! the benchmark's own generator, then, when `wrk` is installed, with `wrk -t2 -c64` on each
//! alternately.
//!
//! The generator of `main.rs` is reqwest in this very process, and it takes most of the two
//! cores, more of them against the server (whose answers it reads the same way) than against
//! nginx; wrk is lean C, so the two servers get the machine on equal terms. Only the ratio from
//! one run means anything.

use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context;
use pps_test_kit::wait::try_wait_until;

use super::{Fleet, Operation, Options, free_port, measure, stop, which};

/// wrk rounds (ours, then nginx) in the comparison.
const WRK_ROUNDS: usize = 3;

/// Serves one effective entry as a static file from nginx, if nginx is installed.
pub async fn compare(
    client: &reqwest::Client,
    fleet: &Arc<Fleet>,
    options: &Options,
    duration: Duration,
) -> anyhow::Result<()> {
    let Ok(nginx) = which("nginx") else {
        println!("  (nginx is not installed: no static-file comparison in this run)");
        return Ok(());
    };
    let dir = tempfile::tempdir()?;
    let (robot, token) = &fleet.tokens[0];
    let epc = &fleet.epcs[0];
    let body = client
        .get(format!("{}/api/v1/robots/{robot}/tags/{epc}", fleet.urls[0]))
        .bearer_auth(token)
        .send()
        .await?
        .bytes()
        .await?;
    std::fs::create_dir_all(dir.path().join("www"))?;
    std::fs::create_dir_all(dir.path().join("logs"))?;
    std::fs::write(dir.path().join("www/entry.json"), &body)?;
    let port = free_port()?;
    let config = format!(
        "worker_processes auto; error_log logs/error.log; pid logs/nginx.pid;\n\
         events {{ worker_connections 1024; }}\n\
         http {{ access_log off; server {{ listen 127.0.0.1:{port}; root {}; }} }}\n",
        dir.path().join("www").display()
    );
    std::fs::write(dir.path().join("nginx.conf"), config)?;
    let mut child = Command::new(nginx)
        .arg("-p")
        .arg(dir.path())
        .args(["-c", "nginx.conf", "-g", "daemon off;"])
        .stderr(Stdio::null())
        .spawn()?;
    let url = format!("http://127.0.0.1:{port}/entry.json");
    let answers = || async { client.get(&url).send().await.ok().map(drop) };
    try_wait_until(Duration::from_secs(5), answers).await.context("nginx did not come up")?;
    let measured = measure(
        client,
        fleet,
        Operation::Static { url: url.clone() },
        options.connections,
        duration,
    )
    .await;
    measured.print("nginx, same JSON as a static file");
    if which("wrk").is_ok() {
        let ours = format!("{}/api/v1/robots/{robot}/tags/{epc}", fleet.urls[0]);
        let (token, seconds) = (token.clone(), duration.as_secs().max(1));
        tokio::task::spawn_blocking(move || {
            compare_with_wrk(&ours, &token, &url, seconds, WRK_ROUNDS)
        })
        .await?;
    } else {
        println!("  (wrk is not installed: no wrk comparison in this run)");
    }
    stop(&mut child);
    Ok(())
}

/// One wrk run: requests per second and the 99th-percentile latency in milliseconds.
#[derive(Debug, Clone, Copy)]
struct Run {
    per_second: f64,
    p99_ms: f64,
}

/// Alternates `rounds` wrk runs of `seconds` each against ours (with the robot's token) and
/// nginx's, printing each pair and the median ratio.
fn compare_with_wrk(ours: &str, token: &str, nginx: &str, seconds: u64, rounds: usize) {
    let mut ratios = Vec::with_capacity(rounds);
    for round in 1..=rounds {
        let measured = run(ours, Some(token), seconds).zip(run(nginx, None, seconds));
        let Some((ours, nginx)) = measured else {
            println!("  (wrk did not run to the end: no comparison in this round)");
            continue;
        };
        let ratio = ours.per_second / nginx.per_second;
        ratios.push(ratio);
        println!(
            "  wrk round {round}: ours {:>6.0} req/s p99 {:.2} ms, nginx {:>6.0} req/s p99 {:.2} ms: \
             {ratio:.2}x",
            ours.per_second, ours.p99_ms, nginx.per_second, nginx.p99_ms
        );
    }
    ratios.sort_by(f64::total_cmp);
    if let Some(median) = ratios.get(ratios.len() / 2) {
        println!(
            "  wrk, median of {} rounds: {median:.2}x nginx's requests per second",
            ratios.len()
        );
    }
}

fn run(url: &str, token: Option<&str>, seconds: u64) -> Option<Run> {
    let mut wrk = Command::new("wrk");
    wrk.args(["-t2", "-c64", &format!("-d{seconds}s"), "--latency"]);
    if let Some(token) = token {
        wrk.args(["-H", &format!("Authorization: Bearer {token}")]);
    }
    let output = wrk.arg(url).output().ok()?;
    let text = String::from_utf8_lossy(&output.stdout);
    // A failed request is no request: wrk counts them apart, and any would spoil the figure.
    if text.contains("Non-2xx") || text.contains("Socket errors") {
        println!("  (wrk saw errors against {url}:\n{text})");
        return None;
    }
    parse(&text)
}

/// Reads `Requests/sec:` and the `99%` line of wrk's `--latency` report.
fn parse(report: &str) -> Option<Run> {
    let field = |label: &str| {
        report.lines().find_map(|line| {
            let mut words = line.split_whitespace();
            (words.next() == Some(label)).then(|| words.next()).flatten()
        })
    };
    let per_second = field("Requests/sec:")?.parse().ok()?;
    let p99 = field("99%")?;
    let (number, unit) = p99.split_at(p99.find(|c: char| c.is_ascii_alphabetic())?);
    let scale = match unit {
        "us" => 0.001,
        "ms" => 1.0,
        "s" => 1000.0,
        _ => return None,
    };
    Some(Run { per_second, p99_ms: number.parse::<f64>().ok()? * scale })
}
