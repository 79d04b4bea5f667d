//! Learned colour models (`learned_colours`): a tag's own (keyed by its EPC) and its
//! household's (keyed by `""`) per robot class, and the colour looks of trials they are learned
//! from. What a model is, and how it is learned, is `colour_learning`'s.

use pps_schema::{Epc, LearnedColor, TagColor};
use sqlx::AnyConnection;

use crate::clock;
use crate::store::columns::At;
use crate::store::db::Dialect;

/// The learned colour of a tag and of its household for a robot class, as stored.
pub async fn learned(
    pool: &sqlx::AnyPool,
    epc: &Epc,
    robot_class: Option<&str>,
) -> sqlx::Result<(Option<LearnedColor>, Option<LearnedColor>)> {
    let rows: Vec<(String, String)> = sqlx::query_as(
        "select epc, model from learned_colours where epc in ($1, '') and robot_class = $2",
    )
    .bind(epc.as_hex())
    .bind(robot_class.unwrap_or(""))
    .fetch_all(pool)
    .await?;
    let model = |key: &str| {
        rows.iter()
            .find(|(epc, _)| epc == key)
            .and_then(|(_, model)| serde_json::from_str::<LearnedColor>(model).ok())
    };
    Ok((model(epc.as_hex()), model("")))
}

/// The colour statistics of the latest `window` real-use trials of `epc` (of every tag when
/// `None`) by robots of `robot_class`.
pub async fn looks(
    conn: &mut AnyConnection,
    epc: Option<&Epc>,
    robot_class: Option<&str>,
    window: i64,
) -> sqlx::Result<Vec<TagColor>> {
    let dialect = Dialect::of(conn);
    let rows: Vec<Option<String>> = sqlx::query_scalar(dialect.pick(
        "select json_extract(body, '$.tag_color') from trials
         where ($1 is null or epc = $1) and coalesce(robot_class, '') = coalesce($2, '')
           and purpose = 'use' and json_type(body, '$.tag_color') = 'object'
         order by seq desc limit $3",
        "select (body::jsonb -> 'tag_color')::text from trials
         where ($1::text is null or epc = $1) and coalesce(robot_class, '') = coalesce($2, '')
           and purpose = 'use' and jsonb_typeof(body::jsonb -> 'tag_color') = 'object'
         order by seq desc limit $3",
    ))
    .bind(epc.map(Epc::as_hex))
    .bind(robot_class)
    .bind(window)
    .fetch_all(conn)
    .await?;
    Ok(rows.into_iter().flatten().filter_map(|text| serde_json::from_str(&text).ok()).collect())
}

/// Stores (or, with `None`, forgets) the model of `epc` (`""` for the household); true when it
/// changed.
pub async fn store(
    conn: &mut AnyConnection,
    epc: &str,
    robot_class: Option<&str>,
    model: Option<LearnedColor>,
) -> sqlx::Result<bool> {
    let class = robot_class.unwrap_or("");
    let previous: Option<String> =
        sqlx::query_scalar("select model from learned_colours where epc = $1 and robot_class = $2")
            .bind(epc)
            .bind(class)
            .fetch_optional(&mut *conn)
            .await?;
    let Some(model) = model else {
        if previous.is_some() {
            sqlx::query("delete from learned_colours where epc = $1 and robot_class = $2")
                .bind(epc)
                .bind(class)
                .execute(conn)
                .await?;
        }
        return Ok(previous.is_some());
    };
    let text = serde_json::to_string(&model).map_err(|e| sqlx::Error::Encode(e.into()))?;
    if previous.as_deref() == Some(text.as_str()) {
        return Ok(false);
    }
    sqlx::query(
        "insert into learned_colours (epc, robot_class, model, trials, updated_at)
         values ($1, $2, $3, $4, $5)
         on conflict (epc, robot_class) do update set model = excluded.model,
             trials = excluded.trials, updated_at = excluded.updated_at",
    )
    .bind(epc)
    .bind(class)
    .bind(text)
    .bind(model.trials as i64)
    .bind(At(clock::recorded_now()))
    .execute(conn)
    .await?;
    Ok(true)
}
