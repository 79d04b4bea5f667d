//! Typed calls to the registry for everything a robot does with it.
//!
//! Longer than most files because it is the robot's whole vocabulary with the registry, one
//! method per call, each a few lines over the shared request helpers at the bottom; the task
//! calls live in `tasks.rs`, the cache, feed and outbox in their own files.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use pps_schema::{EffectiveEntry, Epc, Robot, RobotId, Trial};
use reqwest::StatusCode;
use reqwest::header::{ETAG, IF_NONE_MATCH};
use serde_json::Value;

use super::change_watch::ChangeWatch;
use super::entry_cache::{CachedEntry, EntryCache};
use super::error::RegistryError;
use super::outbox::TrialOutbox;
use super::state_file;

/// Where an effective entry came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// Read from the registry just now.
    Registry,
    /// Cached, and the registry confirmed it is current (304).
    Revalidated,
    /// Cached, and the live change feed announced no change since.
    Fresh,
    /// Cached; the registry could not be reached, so it may be out of date.
    Offline,
}

/// An effective entry and how it was obtained.
#[derive(Debug, Clone)]
pub struct Fetched {
    pub entry: EffectiveEntry,
    /// The document as the registry sent it, for passing on unchanged (typed, `10` and `10.0`
    /// would both come back as `10.0`).
    pub document: Value,
    pub etag: String,
    pub source: Source,
}

/// Internal errors on one trial, in a row, before it is set aside: enough to ride out a
/// registry bug being fixed and restarted, few enough that the trials behind it still go.
pub const MAX_FAILED_UPLOADS: u32 = 5;

/// What one attempt to empty the outbox did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct FlushReport {
    /// Stored by the registry now.
    pub uploaded: usize,
    /// The registry already had them (an earlier upload whose answer was lost).
    pub already_stored: usize,
    /// Refused for good and set aside in the outbox's `rejected/`.
    pub rejected: usize,
    /// Still waiting: the registry could not be reached, or failed on them (500).
    pub remaining: usize,
    /// Pictures the registry has now (sent with their trials, or found stored already).
    pub pictures: usize,
}

/// What became of a trial's picture.
enum PictureSent {
    Stored,
    /// Refused for good, with the registry's reason.
    Refused(String),
    /// Not now: the registry is away or failing; the trial waits with it.
    Later,
}

/// A robot's connection to the registry.
#[derive(Debug, Clone)]
pub struct RegistryClient {
    pub(super) http: reqwest::Client,
    pub(super) base: String,
    pub(super) token: String,
    robot: RobotId,
    cache: Arc<EntryCache>,
    outbox: TrialOutbox,
    feed_live: Arc<AtomicBool>,
    /// Where the robot's own record from the registry is kept for when it is unreachable.
    record_file: PathBuf,
}

impl RegistryClient {
    /// A client for `robot` at `base_url`, keeping its cache and outbox under `state_dir`.
    pub fn new(
        base_url: &str,
        token: &str,
        robot: RobotId,
        state_dir: &Path,
    ) -> Result<Self, RegistryError> {
        Ok(Self {
            http: http_client(None)?,
            base: base_url.trim_end_matches('/').to_owned(),
            token: token.to_owned(),
            robot,
            cache: Arc::new(EntryCache::open(state_dir.join("entries"))?),
            outbox: TrialOutbox::open(state_dir.join("outbox"))?,
            feed_live: Arc::new(AtomicBool::new(false)),
            record_file: state_dir.join("robot.json"),
        })
    }

    /// Trusts the registry's own certificate authority (PEM), as on a LAN where the registry
    /// serves HTTPS with a self-signed certificate; the system's roots stay trusted too.
    pub fn with_ca_certificate(mut self, pem: &[u8]) -> Result<Self, RegistryError> {
        self.http = http_client(Some(pem))?;
        Ok(self)
    }

    pub fn robot(&self) -> &RobotId {
        &self.robot
    }

    pub fn outbox(&self) -> &TrialOutbox {
        &self.outbox
    }

    /// The entry for `epc` as this robot should use it: from the cache when the change feed
    /// vouches for it, revalidated otherwise, and from the cache when the registry is away.
    pub async fn effective_entry(&self, epc: &Epc) -> Result<Fetched, RegistryError> {
        let key = epc.as_hex();
        let cached = self.cache.get(key);
        if let Some((cached, true)) = &cached {
            return Ok(Fetched {
                entry: parse_entry(&cached.entry)?,
                document: cached.entry.clone(),
                etag: cached.etag.clone(),
                source: Source::Fresh,
            });
        }
        let url = format!("{}/api/v1/robots/{}/tags/{key}", self.base, self.robot);
        let mut request = self.http.get(url).bearer_auth(&self.token);
        if let Some((cached, _)) = &cached {
            request = request.header(IF_NONE_MATCH, &cached.etag);
        }
        let live = self.feed_live.load(Ordering::Acquire);
        let response = match request.send().await {
            Ok(response) => response,
            Err(error) => {
                return match cached {
                    Some((cached, _)) => Ok(Fetched {
                        entry: parse_entry(&cached.entry)?,
                        document: cached.entry,
                        etag: cached.etag,
                        source: Source::Offline,
                    }),
                    None => Err(RegistryError::Unreachable(error)),
                };
            }
        };
        match response.status() {
            StatusCode::NOT_MODIFIED => {
                let (cached, _) = cached.ok_or_else(|| {
                    RegistryError::Malformed("304 for an entry never read".into())
                })?;
                self.cache.confirm(key, live);
                Ok(Fetched {
                    entry: parse_entry(&cached.entry)?,
                    document: cached.entry,
                    etag: cached.etag,
                    source: Source::Revalidated,
                })
            }
            StatusCode::OK => {
                let etag = response
                    .headers()
                    .get(ETAG)
                    .and_then(|v| v.to_str().ok())
                    .unwrap_or_default()
                    .to_owned();
                let entry: Value =
                    response.json().await.map_err(|e| RegistryError::Malformed(e.to_string()))?;
                let parsed = parse_entry(&entry)?;
                self.cache.put(
                    key,
                    CachedEntry { etag: etag.clone(), entry: entry.clone() },
                    live,
                )?;
                Ok(Fetched { entry: parsed, document: entry, etag, source: Source::Registry })
            }
            status => {
                if status == StatusCode::NOT_FOUND {
                    self.cache.remove(key);
                }
                Err(RegistryError::from_response(response).await)
            }
        }
    }

    /// Reads the effective entry of every registered tag into the cache (and forgets tags no
    /// longer registered), as a robot does when it starts: then it knows the home's tags (and
    /// the colours its camera sees them in) before reading any of them, also while the registry
    /// is away. Returns how many tags there are.
    pub async fn sync_entries(&self) -> Result<usize, RegistryError> {
        let mut epcs = Vec::new();
        let mut cursor: Option<String> = None;
        loop {
            let mut path = String::from("/api/v1/tags?limit=500");
            if let Some(cursor) = &cursor {
                path.push_str("&cursor=");
                path.push_str(cursor);
            }
            let page: TagPage = self.get_json(&path).await?;
            epcs.extend(page.items.into_iter().map(|tag| tag.epc));
            match page.next_cursor {
                Some(next) => cursor = Some(next),
                None => break,
            }
        }
        self.cache.keep_only(&epcs.iter().map(|epc| epc.as_hex().to_owned()).collect());
        for epc in &epcs {
            match self.effective_entry(epc).await {
                // Archived since the listing: the fetch already forgot it.
                Err(error) if error.status() == Some(404) => {}
                Err(error) => return Err(error),
                Ok(_) => {}
            }
        }
        Ok(epcs.len())
    }

    /// The effective entries this robot holds, as its cache has them (unchecked against the
    /// registry: for what does not depend on the latest revision, such as the tags' colours).
    pub fn known_entries(&self) -> Vec<EffectiveEntry> {
        self.cache.entries().iter().filter_map(|cached| parse_entry(&cached.entry).ok()).collect()
    }

    /// Reads again the entries the change feed announced changed (an edit, a colour learned
    /// from the latest trials), so that [`Self::known_entries`] holds what the registry knows
    /// now; an entry that cannot be read now stays as cached, and is tried again next time.
    pub async fn refresh_announced(&self) {
        for key in self.cache.announced() {
            if let Ok(epc) = Epc::parse(&key) {
                let _ = self.effective_entry(&epc).await;
            }
        }
    }

    /// Records a trial: durably into the outbox first, then uploads what is waiting.
    pub async fn record_trial(&self, trial: &Trial) -> Result<FlushReport, RegistryError> {
        self.record_trial_with_picture(trial, None).await
    }

    /// Records a trial and what the robot saw (PNG bytes): both durably into the outbox first,
    /// then uploads what is waiting, each picture right after its trial.
    pub async fn record_trial_with_picture(
        &self,
        trial: &Trial,
        picture: Option<&[u8]>,
    ) -> Result<FlushReport, RegistryError> {
        self.outbox.push_with_picture(trial, picture)?;
        self.flush().await
    }

    /// Uploads waiting trials, oldest first, until the outbox is empty or the registry is
    /// unreachable. Ids are chosen by the robot, so a trial uploaded twice is stored once.
    pub async fn flush(&self) -> Result<FlushReport, RegistryError> {
        let mut report = FlushReport::default();
        let pending = self.outbox.pending()?;
        for (index, waiting) in pending.iter().enumerate() {
            let url = format!("{}/api/v1/trials/{}", self.base, waiting.trial.id);
            let sent =
                self.http.put(url).bearer_auth(&self.token).json(&waiting.trial).send().await;
            let response = match sent {
                Ok(response) => response,
                Err(_) => {
                    report.remaining += pending.len() - index;
                    return Ok(report);
                }
            };
            match response.status() {
                StatusCode::CREATED => report.uploaded += 1,
                StatusCode::OK => report.already_stored += 1,
                // This trial's own trouble: keep it, and let the trials behind it go ahead; one
                // the registry keeps failing on is set aside rather than retried forever.
                StatusCode::INTERNAL_SERVER_ERROR => {
                    let refusal = RegistryError::from_response(response).await;
                    if self.outbox.failed_upload(waiting) >= MAX_FAILED_UPLOADS {
                        let reason = format!(
                            "the registry failed on this trial {MAX_FAILED_UPLOADS} times in a row; \
                             last: {refusal}"
                        );
                        self.outbox.reject(waiting, &reason)?;
                        report.rejected += 1;
                    } else {
                        report.remaining += 1;
                    }
                    continue;
                }
                status
                    if status.is_server_error()
                        || status == StatusCode::UNAUTHORIZED
                        || status == StatusCode::TOO_MANY_REQUESTS =>
                {
                    // Passing trouble for every trial (or a credential to fix): try later.
                    report.remaining += pending.len() - index;
                    return Ok(report);
                }
                _ => {
                    let refusal = RegistryError::from_response(response).await;
                    self.outbox.reject(waiting, &refusal.to_string())?;
                    report.rejected += 1;
                    continue;
                }
            }
            if let Some(picture) = waiting.picture_bytes()? {
                match self.send_picture(&waiting.trial.id, picture).await {
                    PictureSent::Stored => report.pictures += 1,
                    PictureSent::Refused(reason) => {
                        self.outbox.reject_picture(waiting, &reason)?;
                        continue;
                    }
                    PictureSent::Later => {
                        report.remaining += pending.len() - index;
                        return Ok(report);
                    }
                }
            }
            self.outbox.uploaded(waiting)?;
        }
        Ok(report)
    }

    /// Sends a recorded trial's picture; the same bytes twice are stored once.
    async fn send_picture(&self, trial: &uuid::Uuid, picture: Vec<u8>) -> PictureSent {
        let url = format!("{}/api/v1/trials/{trial}/picture", self.base);
        let sent = self
            .http
            .put(url)
            .bearer_auth(&self.token)
            .header(reqwest::header::CONTENT_TYPE, "image/png")
            .body(picture)
            .send()
            .await;
        match sent {
            Err(_) => PictureSent::Later,
            Ok(response) => match response.status() {
                StatusCode::CREATED | StatusCode::OK => PictureSent::Stored,
                status
                    if status.is_server_error()
                        || status == StatusCode::UNAUTHORIZED
                        || status == StatusCode::TOO_MANY_REQUESTS =>
                {
                    PictureSent::Later
                }
                _ => PictureSent::Refused(RegistryError::from_response(response).await.to_string()),
            },
        }
    }

    /// Sets the person's verdict on a recorded trial.
    pub async fn confirm_trial(
        &self,
        id: uuid::Uuid,
        confirmed: Option<bool>,
    ) -> Result<(), RegistryError> {
        let url = format!("{}/api/v1/trials/{id}", self.base);
        let body = serde_json::json!({ "confirmed": confirmed });
        let response = self
            .http
            .patch(url)
            .bearer_auth(&self.token)
            .header(reqwest::header::CONTENT_TYPE, "application/merge-patch+json")
            .body(body.to_string())
            .send()
            .await
            .map_err(RegistryError::Unreachable)?;
        if response.status().is_success() {
            Ok(())
        } else {
            Err(RegistryError::from_response(response).await)
        }
    }

    /// A trial as the registry stored it.
    pub async fn trial(&self, id: uuid::Uuid) -> Result<Trial, RegistryError> {
        self.get_json(&format!("/api/v1/trials/{id}")).await
    }

    /// This robot's record in the robot registry (its class, capabilities and limits); the copy
    /// kept from the last time when the registry is unreachable.
    pub async fn robot_record(&self) -> Result<Robot, RegistryError> {
        match self.get_json::<Robot>(&format!("/api/v1/robots/{}", self.robot)).await {
            Ok(record) => {
                let kept = serde_json::to_vec(&record).expect("a robot record serialises");
                state_file::replace(&self.record_file, &kept)?;
                Ok(record)
            }
            Err(unreachable @ RegistryError::Unreachable(_)) => std::fs::read(&self.record_file)
                .ok()
                .and_then(|kept| serde_json::from_slice(&kept).ok())
                .ok_or(unreachable),
            Err(other) => Err(other),
        }
    }

    /// Keeps the entry cache in step with the registry's change feed while it runs.
    pub fn watch_changes(&self) -> ChangeWatch {
        ChangeWatch::start(
            self.http.clone(),
            self.base.clone(),
            self.token.clone(),
            self.cache.clone(),
            self.feed_live.clone(),
        )
    }

    async fn get_json<T: serde::de::DeserializeOwned>(
        &self,
        path: &str,
    ) -> Result<T, RegistryError> {
        let response = self
            .http
            .get(format!("{}{path}", self.base))
            .bearer_auth(&self.token)
            .send()
            .await
            .map_err(RegistryError::Unreachable)?;
        if !response.status().is_success() {
            return Err(RegistryError::from_response(response).await);
        }
        response.json().await.map_err(|e| RegistryError::Malformed(e.to_string()))
    }
}

/// One page of the tag list; only the EPCs matter here.
#[derive(serde::Deserialize)]
struct TagPage {
    items: Vec<ListedTag>,
    next_cursor: Option<String>,
}

#[derive(serde::Deserialize)]
struct ListedTag {
    epc: Epc,
}

/// The HTTP client: short connect timeout (a robot must notice quickly that it is offline), an
/// idle-connection timeout below the registry's keep-alive limit, and optionally an extra CA.
fn http_client(ca_pem: Option<&[u8]>) -> Result<reqwest::Client, RegistryError> {
    let mut builder = reqwest::Client::builder()
        .connect_timeout(std::time::Duration::from_secs(3))
        .timeout(std::time::Duration::from_secs(15))
        .pool_idle_timeout(std::time::Duration::from_secs(20));
    if let Some(pem) = ca_pem {
        let certificate = reqwest::Certificate::from_pem(pem)
            .map_err(|e| RegistryError::Malformed(format!("the CA certificate is not PEM: {e}")))?;
        builder = builder.add_root_certificate(certificate);
    }
    builder.build().map_err(RegistryError::Unreachable)
}

fn parse_entry(entry: &Value) -> Result<EffectiveEntry, RegistryError> {
    serde_json::from_value(entry.clone())
        .map_err(|e| RegistryError::Malformed(format!("effective entry: {e}")))
}
