//! `GET /api/v1/tags/{epc}/stats`: how a tag's actions have gone, per robot class, in real use
//! unless asked to count experiments and tests too.

use axum::Json;
use axum::extract::State;
use serde::Deserialize;
use serde_json::Value;

use pps_schema::pointer::escape;
use pps_schema::{Epc, Purpose};

use crate::answers::stamp;
use crate::answers::stats::{ActionStats, LearnedSizeAnswer, LearnedValue, TagStats};
use crate::error::ApiError;
use crate::http::extract::ApiQuery;
use crate::http::ids::InPath;
use crate::http::openapi::doc::{Doc, Param, ParamType, Reply};
use crate::learning::{RELIABILITY_WINDOW, is_reliable};
use crate::state::AppState;
use crate::store::trial_counts::{self, GroupKey};
use crate::store::{learned_sizes, learning, tags};
use crate::trials::counted_purposes::CountedPurposes;

pub const GET: Doc = Doc::new("getTagStats", "How a tag's actions have gone, per robot class")
    .describe(
        "Attempts, detected and confirmed successes, agreement between the robots' detectors \
         and the people's verdicts, the reliable flag and the learned values (the tag's learned size beside the groups). Only trials of \
         real use count unless `include` names other purposes; `counted` says which did, and \
         `not_counted` how many trials of each other purpose were left out. Learned values are \
         always those robots get, learned from real use.",
    )
    .params(&[
        Param::EPC,
        Param::query(
            "include",
            ParamType::SomeOf(&["use", "experiment", "test"]),
            "Purposes to count beside real use, separated by commas, e.g. `experiment,test`",
        ),
    ])
    .replies(&[
        Reply::json(200, "The statistics", "tag_stats"),
        Reply::problem(400, "`include` names something that is not a purpose"),
        Reply::problem(404, "No tag has this EPC"),
    ]);

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatsParams {
    include: Option<String>,
}

pub async fn get(
    State(state): State<AppState>,
    InPath(epc): InPath<Epc>,
    ApiQuery(params): ApiQuery<StatsParams>,
) -> Result<Json<TagStats>, ApiError> {
    let counted = match params.include.as_deref() {
        None => CountedPurposes::real_use(),
        Some(include) => CountedPurposes::including(include).map_err(ApiError::BadRequest)?,
    };
    let pool = state.db.reader();
    let Some(tag) = tags::get(pool, &epc).await? else {
        return Err(ApiError::NotFound(format!("no tag has the EPC {epc}")));
    };
    let rows = trial_counts::group_counts(pool, &epc, &counted).await?;
    let learned = learning::learned_all(pool, &epc).await?;
    let keys: Vec<GroupKey<'_>> = rows
        .iter()
        .map(|(action, class, ..)| GroupKey { epc: &epc, action, robot_class: class.as_deref() })
        .collect();
    let latest = trial_counts::latest_outcomes(
        &mut *pool.acquire().await?,
        &keys,
        RELIABILITY_WINDOW,
        &counted,
    )
    .await?;
    let mut groups = Vec::with_capacity(rows.len());
    for (
        (action, class, attempts, detected, confirmed, confirmed_ok, agreeing, successes, last),
        (recent, recent_ok),
    ) in rows.into_iter().zip(latest)
    {
        // Only what the action's own behaviour uses: `close` has nothing of `pull_open`'s.
        let behavior = tag.entry.pointer(&format!("/actions/{}", escape(&action)));
        let prefix = behavior.and_then(Value::as_str).map(|b| format!("/behaviors/{}/", escape(b)));
        let learned_here = learned
            .iter()
            .filter(|(c, ..)| *c == class)
            .filter(|(_, pointer, ..)| prefix.as_ref().is_some_and(|p| pointer.starts_with(p)))
            .map(|(_, pointer, value, trials)| {
                (pointer.clone(), LearnedValue { value: *value, trials: *trials })
            })
            .collect();
        groups.push(ActionStats {
            action,
            robot_class: class,
            attempts,
            detected_successes: detected,
            confirmed,
            confirmed_successes: confirmed_ok,
            agreement: ratio(agreeing, confirmed),
            success_rate: ratio(successes, attempts),
            reliable: is_reliable(recent, recent_ok),
            last_attempt: stamp::stored_option(last.as_deref()),
            learned: learned_here,
        });
    }
    let not_counted = trial_counts::purpose_counts(pool, &epc)
        .await?
        .into_iter()
        .filter(|(purpose, _)| Purpose::parse(purpose).is_some_and(|p| !counted.counts(p)))
        .collect();
    let learned_size = learned_sizes::learned(pool, &epc).await?.map(|learned| LearnedSizeAnswer {
        width: learned.size.width,
        height: learned.size.height,
        trials: learned.trials as i64,
    });
    Ok(Json(TagStats {
        epc: epc.as_hex().to_owned(),
        counted: counted.purposes().iter().map(|p| p.as_str()).collect(),
        not_counted,
        groups,
        learned_size,
    }))
}

fn ratio(part: i64, whole: i64) -> Option<f64> {
    (whole > 0).then(|| (part as f64 / whole as f64 * 1000.0).round() / 1000.0)
}
