//! What a registry's metrics say, read as a monitoring system would (no token), and the robots
//! waiting in line for a task that tests wait for before they ask for one.

use std::time::Duration;

use crate::in_process::TestServer;
use crate::process::Registry;
use crate::wait::wait_until;

/// A registry a test can reach: in-process, a process, or a replica by its URL.
pub trait Served {
    /// The base URL, without a trailing slash.
    fn base_url(&self) -> &str;
}

impl Served for TestServer {
    fn base_url(&self) -> &str {
        &self.url
    }
}

impl Served for Registry {
    fn base_url(&self) -> &str {
        &self.url
    }
}

impl Served for str {
    fn base_url(&self) -> &str {
        self
    }
}

impl Served for String {
    fn base_url(&self) -> &str {
        self
    }
}

/// The metric `name` of the registry, or `None` when it has none or cannot be reached.
pub async fn metric(registry: &(impl Served + ?Sized), name: &str) -> Option<u64> {
    let url = format!("{}/metrics", registry.base_url());
    let text = reqwest::get(url).await.ok()?.text().await.ok()?;
    let value = text.lines().find_map(|l| l.strip_prefix(name)?.strip_prefix(' '))?;
    value.parse().ok()
}

/// Waits until `n` robots wait in line for a task at the registry, as its metrics say, so a
/// task asked for next goes to a robot already waiting.
pub async fn robots_waiting(registry: &(impl Served + ?Sized), n: u64) {
    let reason = format!("{n} robot(s) to wait for a task");
    wait_until(Duration::from_secs(10), &reason, || async {
        (metric(registry, "pps_robots_waiting_for_tasks").await? == n).then_some(())
    })
    .await
}
