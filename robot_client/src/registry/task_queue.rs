//! The robot's side of the registry's task queue (DESIGN §8): claim the next one under a lease,
//! keep the lease alive, finish it with the trial it ended in, or decline it with a reason.

use std::time::Duration;

use pps_schema::{Epc, Outcome, TaskState};
use reqwest::StatusCode;
use serde::Deserialize;
use time::OffsetDateTime;
use uuid::Uuid;

use super::client::RegistryClient;
use super::error::RegistryError;

/// A caretaker's request as the registry's task queue hands it out. Doing it runs the
/// paper's four-phase [`crate::task`], which is a different thing of the same name.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct QueuedTask {
    pub id: Uuid,
    pub epc: Epc,
    pub action: String,
    #[serde(default)]
    pub note: Option<String>,
    pub state: TaskState,
    /// When the lease runs out unless a heartbeat extends it.
    #[serde(default, with = "time::serde::rfc3339::option")]
    pub lease_until: Option<OffsetDateTime>,
    pub attempts: u32,
    #[serde(default)]
    pub trial: Option<Uuid>,
}

impl QueuedTask {
    /// How often to heartbeat: a third of the lease left, so two beats may be lost in a row.
    pub fn heartbeat_every(&self) -> Duration {
        let left = self
            .lease_until
            .map_or(time::Duration::ZERO, |until| until - OffsetDateTime::now_utc());
        Duration::try_from(left / 3).unwrap_or_default().max(Duration::from_millis(100))
    }
}

/// How much longer than the claim's wait the request may take before it counts as lost.
const CLAIM_SLACK: Duration = Duration::from_secs(10);

impl RegistryClient {
    /// Claims the next task this robot should do, waiting up to `wait` (at most 30 s) for one
    /// to be asked for; `None` when none came.
    pub async fn claim_task(&self, wait: Duration) -> Result<Option<QueuedTask>, RegistryError> {
        let url = format!(
            "{}/api/v1/robots/{}/tasks/claim?wait={}",
            self.base,
            self.robot(),
            wait.as_secs_f64()
        );
        let response = self
            .http
            .post(url)
            .bearer_auth(&self.token)
            .timeout(wait + CLAIM_SLACK)
            .send()
            .await
            .map_err(RegistryError::Unreachable)?;
        match response.status() {
            StatusCode::NO_CONTENT => Ok(None),
            status if status.is_success() => task_from(response).await.map(Some),
            _ => Err(RegistryError::from_response(response).await),
        }
    }

    /// Extends the lease on a task this robot holds; a 409 means the lease was lost (it ran
    /// out, or the task was cancelled): stop working on it.
    pub async fn heartbeat_task(&self, id: Uuid) -> Result<QueuedTask, RegistryError> {
        self.post_task(&format!("/api/v1/tasks/{id}/heartbeat"), None).await
    }

    /// Ends a task this robot holds with `trial`, which the registry must have stored already.
    pub async fn finish_task(
        &self,
        id: Uuid,
        trial: Uuid,
        outcome: Outcome,
    ) -> Result<QueuedTask, RegistryError> {
        let body = serde_json::json!({ "trial": trial, "outcome": outcome.as_str() });
        self.post_task(&format!("/api/v1/tasks/{id}/finish"), Some(body)).await
    }

    /// Says this robot cannot do the task, why in a caretaker's words, and what the robot
    /// itself said (`detail`, shown on request), each one line of at most 500 characters: the
    /// registry gives it to the other robots and never offers it to this one again.
    pub async fn decline_task(
        &self,
        id: Uuid,
        reason: &str,
        detail: Option<&str>,
    ) -> Result<QueuedTask, RegistryError> {
        let body = serde_json::json!({ "reason": reason, "detail": detail });
        self.post_task(&format!("/api/v1/tasks/{id}/decline"), Some(body)).await
    }

    async fn post_task(
        &self,
        path: &str,
        body: Option<serde_json::Value>,
    ) -> Result<QueuedTask, RegistryError> {
        let mut request = self.http.post(format!("{}{path}", self.base)).bearer_auth(&self.token);
        if let Some(body) = body {
            request = request.json(&body);
        }
        let response = request.send().await.map_err(RegistryError::Unreachable)?;
        if !response.status().is_success() {
            return Err(RegistryError::from_response(response).await);
        }
        task_from(response).await
    }
}

async fn task_from(response: reqwest::Response) -> Result<QueuedTask, RegistryError> {
    response.json().await.map_err(|e| RegistryError::Malformed(format!("a task: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heartbeats_come_three_times_a_lease() {
        let task: QueuedTask = serde_json::from_value(serde_json::json!({
            "id": Uuid::new_v4(), "epc": "355AB1C60000002000000001", "action": "off",
            "state": "claimed", "attempts": 1, "note": null, "trial": null,
            "lease_until": (OffsetDateTime::now_utc() + time::Duration::seconds(30))
                .format(&time::format_description::well_known::Rfc3339).unwrap(),
        }))
        .unwrap();
        let every = task.heartbeat_every();
        assert!(every > Duration::from_secs(9) && every <= Duration::from_secs(10), "{every:?}");
        let ended = QueuedTask { lease_until: None, ..task };
        assert_eq!(ended.heartbeat_every(), Duration::from_millis(100));
    }
}
