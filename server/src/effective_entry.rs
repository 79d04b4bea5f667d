//! A tag's effective entry for one robot, as the robots' hot path and the task queue read it.
//!
//! Served from memory when it can be; a miss reads the database once and caches the result.
//! A read never writes: an unknown EPC is noted for the inbox in memory.

use std::sync::Arc;

use axum::http::HeaderValue;
use pps_schema::{Epc, RobotId};
use sha2::{Digest, Sha256};

use crate::error::ApiError;
use crate::state::AppState;
use crate::store::{learned_colours, learned_sizes, learning, retired, robots, tags};
use crate::tags::effective::{LearnedLooks, merge};
use crate::tags::effective_cache::CachedEffective;

/// The effective entry of `epc` for `robot`, from memory when it can be.
pub(crate) async fn entry_for(
    state: &AppState,
    epc: &Epc,
    robot: &RobotId,
) -> Result<Arc<CachedEffective>, ApiError> {
    match state.effective.get(epc.as_hex(), robot.as_str()) {
        Some(entry) => Ok(entry),
        None => compute(state, epc, robot).await,
    }
}

/// Merges the entry from the database and caches it.
async fn compute(
    state: &AppState,
    parsed: &Epc,
    robot: &RobotId,
) -> Result<Arc<CachedEffective>, ApiError> {
    let generation = state.effective.generation();
    let pool = state.db.reader();
    let epc = parsed.as_hex();
    let tag = match tags::get(pool, parsed).await? {
        Some(tag) if !tag.archived => tag,
        Some(_) => {
            return Err(ApiError::NotFound(format!(
                "the tag {epc} is archived; a caretaker can restore it"
            )));
        }
        None => return Err(unknown(state, parsed, robot).await?),
    };
    let stored_robot = robots::get(pool, robot).await?;
    let class = stored_robot.as_ref().and_then(|r| r.class.as_deref());
    let learned = learning::learned_for(pool, parsed, class).await?;
    let (tag_colour, household) = learned_colours::learned(pool, parsed, class).await?;
    let size = learned_sizes::learned(pool, parsed).await?.map(|learned| learned.size);
    let looks = LearnedLooks { tag: tag_colour, household, size };
    let merged = merge(
        epc,
        tag.revision,
        &tag.entry,
        robot.as_str(),
        stored_robot.as_ref(),
        &learned,
        &looks,
    );
    let body = serde_json::to_vec(&merged).map_err(anyhow::Error::from)?;
    // The ETag is the content's hash, so it is stable across restarts and changes with it.
    let etag = format!("\"e{}\"", &hex::encode(Sha256::digest(&body))[..20]);
    let etag = HeaderValue::try_from(etag).map_err(anyhow::Error::from)?;
    let entry = Arc::new(CachedEffective { etag, body: body.into() });
    state.effective.insert(generation, epc, robot.as_str(), entry.clone());
    Ok(entry)
}

/// The answer for an EPC no active tag has; a never-registered one goes to the inbox.
async fn unknown(state: &AppState, epc: &Epc, robot: &RobotId) -> Result<ApiError, ApiError> {
    let mut conn = state.db.reader().acquire().await?;
    if let Some(successor) = retired::successor(&mut conn, epc).await? {
        return Ok(ApiError::NotFound(format!(
            "the EPC {epc} was retired when its worn tag was replaced; the tag now has the EPC {successor}"
        )));
    }
    state.sightings.note(epc.as_hex(), robot.as_str(), state.clock.now());
    Ok(ApiError::NotFound(format!(
        "no tag has the EPC {epc}; it is now in the inbox for a caretaker to register"
    )))
}
