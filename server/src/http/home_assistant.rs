//! `GET /api/v1/home-assistant`: whether this replica's Home Assistant bridge is connected, for
//! the admin page.

use axum::Json;
use axum::extract::State;

use crate::answers::meta::HomeAssistantBridge;

use crate::http::openapi::doc::{Doc, Reply};
use crate::state::AppState;

pub const GET: Doc =
    Doc::new("getHomeAssistantBridge", "The Home Assistant bridge, as this replica sees it")
        .describe(
            "`bridge` is `off` (no `--mqtt`), `standby` (another replica runs it), `connecting` \
         (this replica runs it and cannot use the broker now; `problem` says why) or \
         `connected`.",
        )
        .replies(&[Reply::json(200, "The bridge's status", "home_assistant_bridge")]);

pub async fn get(State(state): State<AppState>) -> Json<HomeAssistantBridge> {
    let configured = state.home_assistant.broker();
    Json(HomeAssistantBridge {
        bridge: state.home_assistant.get(),
        broker: configured.map(|(broker, _)| broker.to_owned()),
        prefix: configured.map(|(_, prefix)| prefix.to_owned()),
        problem: state.home_assistant.problem(),
    })
}
