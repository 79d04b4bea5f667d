//! `GET /api/v1/tags/{epc}/stats`: how a tag's actions have gone, per robot class, in real use
//! unless asked to count experiments and tests too.

use axum::Json;
use axum::extract::State;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value, json};

use pps_schema::pointer::escape;
use pps_schema::{Epc, Purpose};

use crate::error::ApiError;
use crate::http::extract::ApiQuery;
use crate::http::ids::InPath;
use crate::http::openapi::{Doc, Param, ParamType, Reply};
use crate::learning::{RELIABILITY_WINDOW, is_reliable};
use crate::state::AppState;
use crate::store::trial_counts::{self, GroupKey};
use crate::store::{learning, tags};
use crate::trials::counted_purposes::CountedPurposes;

/// One action as done by one robot class.
#[derive(Debug, Serialize)]
pub struct GroupStats {
    action: String,
    /// `null` for robots registered without a class.
    robot_class: Option<String>,
    attempts: i64,
    /// Trials the robot's own detector called a success.
    detected_successes: i64,
    /// Trials the person gave a verdict on, and how many they called a success.
    confirmed: i64,
    confirmed_successes: i64,
    /// Share of verdicts that agree with the detector; `null` before any verdict.
    agreement: Option<f64>,
    /// Successes (the person's verdict where given, else the detector's) over attempts.
    success_rate: Option<f64>,
    /// The lab's rule over the most recent attempts: at least 20, at least 90 % successful.
    reliable: bool,
    last_attempt: Option<String>,
    learned: Map<String, Value>,
}

pub const GET: Doc = Doc::new("getTagStats", "How a tag's actions have gone, per robot class")
    .describe(
        "Attempts, detected and confirmed successes, agreement between the robots' detectors \
         and the people's verdicts, the reliable flag and the learned values. Only trials of \
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
) -> Result<Json<Value>, ApiError> {
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
                (pointer.clone(), json!({ "value": value, "trials": trials }))
            })
            .collect();
        groups.push(GroupStats {
            action,
            robot_class: class,
            attempts,
            detected_successes: detected,
            confirmed,
            confirmed_successes: confirmed_ok,
            agreement: ratio(agreeing, confirmed),
            success_rate: ratio(successes, attempts),
            reliable: is_reliable(recent, recent_ok),
            last_attempt: last,
            learned: learned_here,
        });
    }
    let not_counted: Map<String, Value> = trial_counts::purpose_counts(pool, &epc)
        .await?
        .into_iter()
        .filter(|(purpose, _)| Purpose::parse(purpose).is_some_and(|p| !counted.counts(p)))
        .map(|(purpose, trials)| (purpose, trials.into()))
        .collect();
    let counted: Vec<&str> = counted.purposes().iter().map(|p| p.as_str()).collect();
    Ok(Json(json!({
        "epc": epc.as_hex(),
        "counted": counted,
        "not_counted": not_counted,
        "groups": groups,
    })))
}

fn ratio(part: i64, whole: i64) -> Option<f64> {
    (whole > 0).then(|| (part as f64 / whole as f64 * 1000.0).round() / 1000.0)
}
