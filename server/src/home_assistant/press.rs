//! A button pressed in Home Assistant becomes a task, as the web UI's "Ask a robot" makes one,
//! asked by the bridge's own caretaker credential. What cannot be a press (a wrong payload, an
//! unknown device or action, a revoked credential) is logged once and otherwise ignored.

use std::collections::HashSet;

use super::CREDENTIAL;
use super::device::TagDevice;
use super::discovery::{self, PRESS};
use super::lease::Lease;
use crate::error::ApiError;
use crate::identity::Role;
use crate::state::AppState;
use crate::store::home_assistant::{self, Credential};
use crate::store::tokens;
use crate::tasks::ask::ask;
use crate::tasks::request::TaskRequest;

/// A press is one word; a bigger payload is not read.
const MAX_PRESS_BYTES: usize = 64;
/// Problems remembered as logged; past this many, new ones are no longer logged at all.
const MAX_REMEMBERED: usize = 1024;

/// Turns presses into tasks.
#[derive(Debug)]
pub struct Presses<'a> {
    state: &'a AppState,
    lease: &'a Lease,
    /// Problems logged already, so a flood logs each once.
    logged: HashSet<String>,
}

impl<'a> Presses<'a> {
    pub fn new(state: &'a AppState, lease: &'a Lease) -> Self {
        Self { state, lease, logged: HashSet::new() }
    }

    /// Handles one message on a press topic; `devices` are the devices announced, by id.
    pub async fn handle<'d>(
        &mut self,
        topic: &str,
        payload: &[u8],
        mut devices: impl Iterator<Item = (&'d str, &'d TagDevice)>,
    ) {
        let Some((id, action)) = discovery::parse_press_topic(topic) else { return };
        if payload.len() > MAX_PRESS_BYTES || payload != PRESS.as_bytes() {
            let shown = String::from_utf8_lossy(&payload[..payload.len().min(MAX_PRESS_BYTES)]);
            return self.once(
                format!("payload {topic}"),
                format!(
                    "ignored a message on {topic}: a press is the payload {PRESS}, not {} bytes \
                     starting {shown:?}",
                    payload.len()
                ),
            );
        }
        let Some((_, device)) = devices.find(|(known, _)| *known == id) else {
            return self.once(
                format!("device {id}"),
                format!("ignored a press for {id}: no active tag is that device"),
            );
        };
        if !device.actions.iter().any(|(known, _)| known == action) {
            return self.once(
                format!("action {id} {action}"),
                format!(
                    "ignored a press of {action} on {}: the tag has no such action",
                    device.name
                ),
            );
        }
        match home_assistant::credential(self.state.db.reader(), CREDENTIAL, self.state.clock.now())
            .await
        {
            Ok(Credential::Live) => {}
            Ok(_) => {
                return self.once(
                    "credential".into(),
                    format!(
                        "refused presses from Home Assistant: the caretaker credential \
                         {CREDENTIAL:?} was revoked; an admin mints a new caretaker token of \
                         that name to allow them again"
                    ),
                );
            }
            Err(error) => return tracing::warn!(%error, "cannot check the bridge's credential"),
        }
        // Allowed again: a later revocation is worth a line again.
        self.logged.remove("credential");
        let asked = TaskRequest::action_on(
            device.epc.clone(),
            action.to_owned(),
            Some("pressed in Home Assistant".into()),
            self.state.clock.now(),
        );
        match ask(self.state, asked, CREDENTIAL, Some(self.lease.holder())).await {
            Ok(task) => tracing::info!(
                task = %task.id, epc = %task.epc, action, "a press in Home Assistant became a task"
            ),
            Err(ApiError::Invalid(errors)) => {
                let why: Vec<String> = errors.iter().map(ToString::to_string).collect();
                tracing::warn!(epc = %device.epc, action, "a press could not be a task: {}", why.join("; "));
            }
            Err(error) => {
                tracing::warn!(%error, epc = %device.epc, action, "a press could not be a task")
            }
        }
    }

    fn once(&mut self, key: String, message: String) {
        if self.logged.contains(&key) {
            return tracing::debug!("{message}");
        }
        if self.logged.len() < MAX_REMEMBERED {
            self.logged.insert(key);
            tracing::warn!("{message}");
        }
    }
}

/// Mints the bridge's credential the first time it runs; a revoked one stays revoked.
pub async fn mint_credential_once(state: &AppState) {
    match home_assistant::credential(state.db.reader(), CREDENTIAL, state.clock.now()).await {
        Ok(Credential::Missing) => {
            match tokens::create(&state.db, Role::Caretaker, CREDENTIAL, None).await {
                Ok(minted) => tracing::info!(
                    token = %minted.record.id,
                    "made the caretaker credential {CREDENTIAL:?} presses in Home Assistant are \
                     asked with; revoke it to refuse them"
                ),
                Err(error) => tracing::warn!(%error, "cannot make the bridge's credential"),
            }
        }
        Ok(_) => {}
        Err(error) => tracing::warn!(%error, "cannot check the bridge's credential"),
    }
}
