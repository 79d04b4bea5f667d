//! Trials in the database: one row per attempt, in the order the registry received them.

use std::collections::BTreeMap;

use pps_schema::{Epc, Outcome, Purpose, RobotId, Trial};
use serde_json::value::RawValue;
use serde_json::{Value, json};
use sqlx::{AnyConnection, AnyPool};
use uuid::Uuid;

use crate::clock;
use crate::db::Dialect;
use crate::store::columns::{Flag, Id, MaybeFlag};
use crate::store::placeholders;
use crate::trial_filter::TrialFilter;

/// A stored trial.
#[derive(Debug, Clone, PartialEq, sqlx::FromRow)]
pub struct TrialRow {
    pub seq: i64,
    #[sqlx(try_from = "Id<Uuid>")]
    pub id: Uuid,
    #[sqlx(try_from = "Id<Epc>")]
    pub epc: Epc,
    #[sqlx(try_from = "Id<RobotId>")]
    pub robot: RobotId,
    pub robot_class: Option<String>,
    pub action: String,
    pub outcome: String,
    #[sqlx(try_from = "MaybeFlag")]
    pub confirmed: Option<bool>,
    pub purpose: String,
    pub received_at: String,
    pub body: String,
    /// Whether the trial's picture is held (sent, and not removed by retention).
    #[sqlx(try_from = "Flag")]
    pub has_picture: bool,
}

impl TrialRow {
    /// The trial as submitted, as the API returns it: with the verdict as it is now, its
    /// purpose spelled out also where real use went without saying, and the registry's
    /// `received_at` and `seq`.
    pub fn to_json(&self) -> Value {
        let mut trial: Value = serde_json::from_str(&self.body).unwrap_or_else(|_| json!({}));
        if let Some(object) = trial.as_object_mut() {
            object.insert("confirmed".into(), self.confirmed.map_or(Value::Null, Value::from));
            object.insert("purpose".into(), self.purpose.clone().into());
            object.insert("received_at".into(), self.received_at.clone().into());
            object.insert("seq".into(), self.seq.into());
            let picture = self.has_picture.then(|| picture_path(&self.id));
            object.insert("picture".into(), picture.map_or(Value::Null, Value::from));
        }
        trial
    }

    /// [`Self::to_json`] as text, the same bytes as `to_json().to_string()`, written without
    /// decoding the stored values: a trial's thousands of force samples are copied as they are,
    /// not parsed into numbers and printed again, the bulk of a page's cost.
    pub fn write_json(&self, out: &mut Vec<u8>) {
        let added = [
            ("confirmed", self.confirmed.map_or(Value::Null, Value::from)),
            ("purpose", self.purpose.clone().into()),
            ("received_at", self.received_at.clone().into()),
            ("seq", self.seq.into()),
            ("picture", self.has_picture.then(|| picture_path(&self.id)).into()),
        ];
        let added: Vec<(&str, Box<RawValue>)> = added
            .into_iter()
            .filter_map(|(key, value)| Some((key, serde_json::value::to_raw_value(&value).ok()?)))
            .collect();
        // Keys in the order a `Value`'s map keeps them, so both ways give the same text.
        let Ok(mut fields) = serde_json::from_str::<BTreeMap<String, &RawValue>>(&self.body) else {
            out.extend_from_slice(self.to_json().to_string().as_bytes());
            return;
        };
        for (key, value) in &added {
            fields.insert((*key).to_owned(), value);
        }
        let start = out.len();
        if serde_json::to_writer(&mut *out, &fields).is_err() {
            out.truncate(start);
            out.extend_from_slice(self.to_json().to_string().as_bytes());
        }
    }

    /// The trial as first submitted (the idempotency key's content).
    pub fn submitted(&self) -> Value {
        serde_json::from_str(&self.body).unwrap_or(Value::Null)
    }
}

/// Where a trial's picture is read.
pub fn picture_path(id: &Uuid) -> String {
    format!("/api/v1/trials/{id}/picture")
}

/// A checked trial as the batch that records it inserts it.
#[derive(Debug, Clone, Copy)]
pub struct NewTrial<'a> {
    pub trial: &'a Trial,
    /// The robot's class as it is now; the trial keeps it.
    pub robot_class: Option<&'a str>,
    pub received_at: &'a str,
    /// `trial` as submitted, serialised.
    pub body: &'a str,
}

/// Trials inserted by one statement at most (13 values each, well under SQLite's limit).
pub const INSERT_CHUNK: usize = 256;

/// Inserts up to [`INSERT_CHUNK`] trials with one statement; returns the id and sequence number
/// of each that was new. A trial whose id is stored already (also earlier in `trials`) is left
/// as it is: the caller tells a retry from a conflict.
pub async fn insert_new(
    conn: &mut AnyConnection,
    trials: &[NewTrial<'_>],
) -> sqlx::Result<Vec<(Uuid, i64)>> {
    let statement = format!(
        "insert into trials (id, epc, robot, robot_class, action, behavior, outcome, \
         confirmed, started_at, finished_at, received_at, body, purpose) values {} \
         on conflict (id) do nothing returning id, seq",
        placeholders::rows(trials.len(), 13)
    );
    let mut insert = sqlx::query_as(sqlx::AssertSqlSafe(statement));
    for new in trials {
        let trial = new.trial;
        insert = insert
            .bind(trial.id.hyphenated().to_string())
            .bind(trial.epc.as_hex())
            .bind(trial.robot.as_str())
            .bind(new.robot_class)
            .bind(&trial.action)
            .bind(&trial.behavior)
            .bind(trial.outcome.as_str())
            .bind(trial.confirmed.map(i64::from))
            .bind(clock::format(trial.started_at))
            .bind(clock::format(trial.finished_at))
            .bind(new.received_at)
            .bind(new.body)
            .bind(trial.purpose.as_str());
    }
    let inserted: Vec<(String, i64)> = insert.fetch_all(conn).await?;
    inserted
        .into_iter()
        .map(|(id, seq)| {
            let id = Uuid::parse_str(&id).map_err(|error| sqlx::Error::Decode(error.into()))?;
            Ok((id, seq))
        })
        .collect()
}

pub async fn find(conn: &mut AnyConnection, id: &Uuid) -> sqlx::Result<Option<TrialRow>> {
    sqlx::query_as(
        "select seq, id, epc, robot, robot_class, action, outcome, confirmed, purpose,
                received_at, body,
                case when exists (select 1 from trial_pictures p
                                  where p.trial = trials.id and p.bytes is not null)
                     then cast(1 as bigint) else cast(0 as bigint) end as has_picture
         from trials where id = $1",
    )
    .bind(id.hyphenated().to_string())
    .fetch_optional(conn)
    .await
}

#[tracing::instrument(skip_all)]
pub async fn get(pool: &AnyPool, id: &Uuid) -> sqlx::Result<Option<TrialRow>> {
    let mut conn = pool.acquire().await?;
    find(&mut conn, id).await
}

/// How much of the trial history one query reads.
#[derive(Debug, Clone, Copy)]
pub struct Window {
    /// Trials after this sequence number.
    pub after: i64,
    /// Trials at most.
    pub limit: u32,
    /// Stored bytes at most (the first trial is always read, whatever its size).
    pub max_bytes: usize,
    /// With the force samples, the bulk of a trial; without, `forces` is left out.
    pub forces: bool,
}

/// Trials in `window`, oldest first, read one by one so that no more than `max_bytes` of them
/// are held; the flag says the byte bound (not the limit or the end) stopped the read.
#[tracing::instrument(skip_all)]
pub async fn list(
    pool: &AnyPool,
    filter: &TrialFilter,
    window: Window,
) -> sqlx::Result<(Vec<TrialRow>, bool)> {
    use futures_util::TryStreamExt;
    let mut rows = sqlx::query_as::<_, TrialRow>(Dialect::of_pool(pool).pick(
        "select seq, id, epc, robot, robot_class, action, outcome, confirmed, purpose, received_at,
                case when $8 then body else json_remove(body, '$.forces') end as body,
                case when exists (select 1 from trial_pictures p
                                  where p.trial = trials.id and p.bytes is not null)
                     then cast(1 as bigint) else cast(0 as bigint) end as has_picture
         from trials
         where seq > $1
           and ($2 is null or epc = $2)
           and ($3 is null or robot = $3)
           and ($4 is null or action = $4)
           and ($5 is null or outcome = $5)
           and ($6 is null or started_at >= $6)
           and ($9 is null or purpose = $9)
         order by seq
         limit $7",
        "select seq, id, epc, robot, robot_class, action, outcome, confirmed, purpose, received_at,
                case when $8 then body else (body::jsonb - 'forces')::text end as body,
                case when exists (select 1 from trial_pictures p
                                  where p.trial = trials.id and p.bytes is not null)
                     then cast(1 as bigint) else cast(0 as bigint) end as has_picture
         from trials
         where seq > $1
           and ($2::text is null or epc = $2)
           and ($3::text is null or robot = $3)
           and ($4::text is null or action = $4)
           and ($5::text is null or outcome = $5)
           and ($6::text is null or started_at >= $6)
           and ($9::text is null or purpose = $9)
         order by seq
         limit $7",
    ))
    .bind(window.after)
    .bind(filter.epc.as_ref().map(Epc::as_hex))
    .bind(filter.robot.as_ref().map(RobotId::as_str))
    .bind(filter.action.as_deref())
    .bind(filter.outcome.map(Outcome::as_str))
    .bind(filter.since.map(clock::format))
    .bind(i64::from(window.limit))
    .bind(window.forces)
    .bind(filter.purpose.map(Purpose::as_str))
    .fetch(pool);
    let (mut listed, mut bytes) = (Vec::new(), 0);
    while let Some(row) = rows.try_next().await? {
        bytes += row.body.len();
        if bytes > window.max_bytes && !listed.is_empty() {
            return Ok((listed, true));
        }
        listed.push(row);
    }
    Ok((listed, false))
}

/// Sets the person's verdict; false when no trial has this id.
pub async fn set_confirmed(
    conn: &mut AnyConnection,
    id: &Uuid,
    confirmed: Option<bool>,
) -> sqlx::Result<bool> {
    let done = sqlx::query("update trials set confirmed = $1 where id = $2")
        .bind(confirmed.map(i64::from))
        .bind(id.hyphenated().to_string())
        .execute(conn)
        .await?;
    Ok(done.rows_affected() == 1)
}

/// Moves every trial of a retagged tag to its new EPC.
pub async fn move_to(conn: &mut AnyConnection, from: &Epc, to: &Epc) -> sqlx::Result<u64> {
    Ok(sqlx::query("update trials set epc = $1 where epc = $2")
        .bind(to.as_hex())
        .bind(from.as_hex())
        .execute(conn)
        .await?
        .rows_affected())
}

/// Trials received before `cutoff` that still carry force samples, after sequence number
/// `after`, oldest first: `(seq, body)`.
#[tracing::instrument(skip_all)]
pub async fn with_forces_received_before(
    pool: &AnyPool,
    cutoff: &str,
    after: i64,
    limit: u32,
) -> sqlx::Result<Vec<(i64, String)>> {
    sqlx::query_as(Dialect::of_pool(pool).pick(
        "select seq, body from trials
         where seq > $1 and received_at < $2 and json_array_length(body, '$.forces') > 0
         order by seq
         limit $3",
        "select seq, body from trials
         where seq > $1 and received_at < $2
           and jsonb_typeof(body::jsonb -> 'forces') = 'array'
           and body::jsonb -> 'forces' != '[]'::jsonb
         order by seq
         limit $3",
    ))
    .bind(after)
    .bind(cutoff)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await
}

/// Replaces a trial's stored body, unless it changed since it was read as `old` (another
/// process thinning at the same time); false then.
pub async fn replace_body(
    conn: &mut AnyConnection,
    seq: i64,
    old: &str,
    new: &str,
) -> sqlx::Result<bool> {
    let done = sqlx::query("update trials set body = $1 where seq = $2 and body = $3")
        .bind(new)
        .bind(seq)
        .bind(old)
        .execute(conn)
        .await?;
    Ok(done.rows_affected() == 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(body: &str, confirmed: Option<bool>, has_picture: bool) -> TrialRow {
        TrialRow {
            seq: 42,
            id: Uuid::parse_str("0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10").unwrap(),
            epc: Epc::parse("355AB1C60000002000000001").unwrap(),
            robot: RobotId::parse("el-e-1").unwrap(),
            robot_class: Some("el-e".into()),
            action: "on".into(),
            outcome: "success".into(),
            confirmed,
            purpose: "experiment".into(),
            received_at: "2026-11-22T10:00:31Z".into(),
            body: body.into(),
            has_picture,
        }
    }

    fn written(row: &TrialRow) -> String {
        let mut out = Vec::new();
        row.write_json(&mut out);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn a_trial_is_written_as_its_json_value_prints() {
        let stored = json!({
            "id": "0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10", "epc": "355AB1C60000002000000001",
            "robot": "el-e-1", "action": "on", "behavior": "push_top", "outcome": "success",
            "confirmed": false, "purpose": "experiment", "notes": "a \"quoted\" é\u{2028}\t",
            "forces": [{ "t": 0.1, "finger": "left", "force": [1e-7, -2.5, 1.2345678901234567] }],
            "measurements": { "zeta": 1, "alpha": [true, null] }
        })
        .to_string();
        for body in [stored.as_str(), "{}", "[1,2]", "not json"] {
            for (confirmed, picture) in [(None, false), (Some(true), true), (Some(false), false)] {
                let row = row(body, confirmed, picture);
                assert_eq!(written(&row), row.to_json().to_string(), "{body} {confirmed:?}");
            }
        }
    }

    #[test]
    fn writing_appends_to_what_is_there() {
        let row = row("{}", None, false);
        let mut out = b"[".to_vec();
        row.write_json(&mut out);
        assert_eq!(out, format!("[{}", row.to_json()).into_bytes());
    }
}
