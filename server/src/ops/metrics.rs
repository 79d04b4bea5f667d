//! Prometheus metrics: requests by route and status, a latency histogram per route, trials
//! recorded and SSE clients, served as text at `GET /metrics`.
//!
//! Counting is a read lock and a few atomic increments, cheap enough for the hot path.

use std::collections::HashMap;
use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, RwLock};

use axum::http::Method;

/// Upper bounds of the latency buckets, in seconds.
const BUCKETS: [f64; 12] =
    [0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5];

/// One route's counters, looked up once per request and counted into when it is answered.
#[derive(Debug)]
pub struct RouteMetrics {
    /// Responses by status code, indexed by `status - 100`.
    statuses: Vec<AtomicU64>,
    buckets: [AtomicU64; BUCKETS.len()],
    count: AtomicU64,
    sum_micros: AtomicU64,
}

impl RouteMetrics {
    /// Counts one response.
    pub fn observe(&self, status: u16, seconds: f64) {
        if let Some(counter) = self.statuses.get(usize::from(status).saturating_sub(100)) {
            counter.fetch_add(1, Ordering::Relaxed);
        }
        if let Some(bucket) = BUCKETS.iter().position(|bound| seconds <= *bound) {
            self.buckets[bucket].fetch_add(1, Ordering::Relaxed);
        }
        self.count.fetch_add(1, Ordering::Relaxed);
        self.sum_micros.fetch_add((seconds * 1e6) as u64, Ordering::Relaxed);
    }
}

impl Default for RouteMetrics {
    fn default() -> Self {
        Self {
            statuses: (100..600).map(|_| AtomicU64::new(0)).collect(),
            buckets: Default::default(),
            count: AtomicU64::new(0),
            sum_micros: AtomicU64::new(0),
        }
    }
}

#[derive(Debug, Default)]
pub struct Metrics {
    /// By route, then method: a standard method's name or `other`, so made-up methods sent by
    /// anyone cannot add series (and memory) without bound.
    routes: RwLock<HashMap<String, HashMap<&'static str, Arc<RouteMetrics>>>>,
    trials_recorded: AtomicU64,
}

impl Metrics {
    pub fn trial_recorded(&self) {
        self.trials_recorded.fetch_add(1, Ordering::Relaxed);
    }

    /// The counters of a matched route (or `unmatched`) and method.
    pub fn route(&self, route: &str, method: &Method) -> Arc<RouteMetrics> {
        let method = method_label(method);
        if let Some(found) = self
            .routes
            .read()
            .unwrap_or_else(|e| e.into_inner())
            .get(route)
            .and_then(|m| m.get(method))
        {
            return found.clone();
        }
        let mut routes = self.routes.write().unwrap_or_else(|e| e.into_inner());
        routes.entry(route.to_owned()).or_default().entry(method).or_default().clone()
    }

    /// The Prometheus text exposition.
    pub fn render(&self, sse_clients: usize) -> String {
        let mut out = String::new();
        let routes = self.routes.read().unwrap_or_else(|e| e.into_inner());
        let mut sorted: Vec<(&String, &&str, &Arc<RouteMetrics>)> = routes
            .iter()
            .flat_map(|(route, methods)| methods.iter().map(move |(m, r)| (route, m, r)))
            .collect();
        sorted.sort_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)));
        out.push_str(
            "# HELP pps_http_requests_total HTTP responses by matched route, method and status.\n",
        );
        out.push_str("# TYPE pps_http_requests_total counter\n");
        for (route, method, metrics) in &sorted {
            for (offset, counter) in metrics.statuses.iter().enumerate() {
                let n = counter.load(Ordering::Relaxed);
                if n > 0 {
                    let _ = writeln!(
                        out,
                        "pps_http_requests_total{{route=\"{route}\",method=\"{method}\",status=\"{}\"}} {n}",
                        offset + 100
                    );
                }
            }
        }
        out.push_str(
            "# HELP pps_http_request_duration_seconds Time to the response head, by route.\n",
        );
        out.push_str("# TYPE pps_http_request_duration_seconds histogram\n");
        for (route, method, metrics) in &sorted {
            let labels = format!("route=\"{route}\",method=\"{method}\"");
            let mut cumulative = 0;
            for (bound, bucket) in BUCKETS.iter().zip(&metrics.buckets) {
                cumulative += bucket.load(Ordering::Relaxed);
                let _ = writeln!(
                    out,
                    "pps_http_request_duration_seconds_bucket{{{labels},le=\"{bound}\"}} {cumulative}"
                );
            }
            let count = metrics.count.load(Ordering::Relaxed);
            let _ = writeln!(
                out,
                "pps_http_request_duration_seconds_bucket{{{labels},le=\"+Inf\"}} {count}"
            );
            let sum = metrics.sum_micros.load(Ordering::Relaxed) as f64 / 1e6;
            let _ = writeln!(out, "pps_http_request_duration_seconds_sum{{{labels}}} {sum}");
            let _ = writeln!(out, "pps_http_request_duration_seconds_count{{{labels}}} {count}");
        }
        let trials = self.trials_recorded.load(Ordering::Relaxed);
        let _ = write!(
            out,
            "# HELP pps_trials_recorded_total Trials stored since the server started (repeats not counted).\n\
             # TYPE pps_trials_recorded_total counter\npps_trials_recorded_total {trials}\n\
             # HELP pps_sse_clients Clients connected to the change feed.\n\
             # TYPE pps_sse_clients gauge\npps_sse_clients {sse_clients}\n"
        );
        out
    }
}

/// The label of a request method: the standard ones by name, anything else as `other`.
fn method_label(method: &Method) -> &'static str {
    static STANDARD: [Method; 9] = [
        Method::GET,
        Method::HEAD,
        Method::POST,
        Method::PUT,
        Method::DELETE,
        Method::PATCH,
        Method::OPTIONS,
        Method::TRACE,
        Method::CONNECT,
    ];
    STANDARD.iter().find(|standard| *standard == method).map_or("other", Method::as_str)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_counters_and_cumulative_buckets() {
        let metrics = Metrics::default();
        metrics.route("/api/v1/tags", &Method::GET).observe(200, 0.0007);
        metrics.route("/api/v1/tags", &Method::GET).observe(200, 0.02);
        metrics.route("/api/v1/tags", &Method::GET).observe(401, 0.0001);
        metrics.trial_recorded();
        let text = metrics.render(2);
        assert!(text.contains(
            "pps_http_requests_total{route=\"/api/v1/tags\",method=\"GET\",status=\"200\"} 2"
        ));
        assert!(text.contains("status=\"401\"} 1"));
        assert!(text.contains("le=\"0.001\"} 2"));
        assert!(text.contains("le=\"+Inf\"} 3"));
        assert!(text.contains("pps_trials_recorded_total 1"));
        assert!(text.contains("pps_sse_clients 2"));
    }

    #[test]
    fn made_up_methods_share_one_series() {
        let metrics = Metrics::default();
        for n in 0..100 {
            let method = Method::from_bytes(format!("X{n}").as_bytes()).unwrap();
            metrics.route("unmatched", &method).observe(405, 0.0001);
        }
        let text = metrics.render(0);
        assert!(text.contains("method=\"other\",status=\"405\"} 100"), "{text}");
        assert!(!text.contains("X1"));
    }
}
