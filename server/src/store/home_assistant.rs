//! What the Home Assistant bridge keeps and reads in the database: the lease that lets one
//! replica run it, its credential, and the newest trials of a tag (where a device's state comes
//! from).

use pps_schema::Epc;
use sqlx::{AnyConnection, AnyPool};
use time::OffsetDateTime;

use crate::identity::Role;
use crate::store::columns::{At, MaybeFlag};

/// The lease row's key.
const BRIDGE: &str = "home_assistant";

/// Takes the lease for `holder` from `now` until `until`, or renews it; true when `holder`
/// holds it then.
/// Another holder's lease is taken over only once it ran out. Runs inside a write transaction,
/// so of two replicas asking at once exactly one gets it.
#[tracing::instrument(skip_all)]
pub async fn take_lease(
    tx: &mut AnyConnection,
    holder: &str,
    now: OffsetDateTime,
    until: OffsetDateTime,
) -> sqlx::Result<bool> {
    sqlx::query(
        "insert into bridge_lease (bridge, holder, until) values ($1, $2, $3)
         on conflict (bridge) do update set holder = excluded.holder, until = excluded.until
         where bridge_lease.holder = excluded.holder or bridge_lease.until <= $4",
    )
    .bind(BRIDGE)
    .bind(holder)
    .bind(At(until))
    .bind(At(now))
    .execute(&mut *tx)
    .await?;
    holds_lease(tx, holder, now).await
}

/// Whether `holder` holds a lease that has not run out by `now`.
pub async fn holds_lease(
    conn: &mut AnyConnection,
    holder: &str,
    now: OffsetDateTime,
) -> sqlx::Result<bool> {
    let held: Option<String> = sqlx::query_scalar(
        "select holder from bridge_lease where bridge = $1 and holder = $2 and until > $3",
    )
    .bind(BRIDGE)
    .bind(holder)
    .bind(At(now))
    .fetch_optional(&mut *conn)
    .await?;
    Ok(held.is_some())
}

/// Gives the lease up (the holder is stopping), so another replica need not wait it out.
pub async fn release_lease(tx: &mut AnyConnection, holder: &str) -> sqlx::Result<()> {
    sqlx::query("delete from bridge_lease where bridge = $1 and holder = $2")
        .bind(BRIDGE)
        .bind(holder)
        .execute(&mut *tx)
        .await?;
    Ok(())
}

/// Where a caretaker token of this name stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Credential {
    /// One works now.
    Live,
    /// Some were minted, none works any more (revoked or expired).
    Revoked,
    /// None was ever minted.
    Missing,
}

/// Where the caretaker tokens named `name` stand at `now`.
#[tracing::instrument(skip_all)]
pub async fn credential(
    pool: &AnyPool,
    name: &str,
    now: OffsetDateTime,
) -> sqlx::Result<Credential> {
    let (minted, live): (i64, i64) = sqlx::query_as(
        "select count(*),
                coalesce(sum(case when revoked_at is null
                                   and (expires_at is null or expires_at > $3)
                             then 1 else 0 end), 0)
         from tokens where name = $1 and role = $2",
    )
    .bind(name)
    .bind(Role::Caretaker.as_str())
    .bind(At(now))
    .fetch_one(pool)
    .await?;
    Ok(match (minted, live) {
        (0, _) => Credential::Missing,
        (_, 0) => Credential::Revoked,
        _ => Credential::Live,
    })
}

/// What one trial says about its tag, as much as a device's state needs.
#[derive(Debug, Clone, PartialEq, sqlx::FromRow)]
pub struct TrialVerdict {
    pub action: String,
    pub outcome: String,
    #[sqlx(try_from = "MaybeFlag")]
    pub confirmed: Option<bool>,
    /// The trial as the robot sent it (JSON), for its `detector`.
    pub body: String,
}

/// The newest `limit` trials on a tag, newest first.
#[tracing::instrument(skip_all)]
pub async fn newest_trials(
    pool: &AnyPool,
    epc: &Epc,
    limit: u32,
) -> sqlx::Result<Vec<TrialVerdict>> {
    sqlx::query_as(
        "select action, outcome, confirmed, body from trials where epc = $1
         order by seq desc limit $2",
    )
    .bind(epc.as_hex())
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await
}
