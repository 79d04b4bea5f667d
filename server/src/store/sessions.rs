//! Browser sessions: the SHA-256 of each session's secret, its user and its fixed expiry.
//!
//! Reading a session writes nothing: the expiry is set at login and never extended.

use sqlx::AnyPool;
use time::OffsetDateTime;

use crate::identity::UserName;
use crate::store::columns::At;
use crate::store::db::Db;

/// A live session's user, as the access check needs it.
#[derive(Debug, Clone, PartialEq, Eq, sqlx::FromRow)]
pub struct SessionUser {
    pub name: String,
    pub role: String,
    #[sqlx(try_from = "At")]
    pub expires_at: OffsetDateTime,
}

/// Stores a new session made `now`, and clears out sessions that have expired on the way.
#[tracing::instrument(skip_all, fields(user = %user))]
pub async fn create(
    db: &Db,
    secret_hash: &str,
    user: &UserName,
    now: OffsetDateTime,
    expires_at: OffsetDateTime,
) -> sqlx::Result<()> {
    let mut tx = db.begin_write().await?;
    sqlx::query("delete from sessions where expires_at <= $1")
        .bind(At(now))
        .execute(&mut *tx)
        .await?;
    sqlx::query(
        "insert into sessions (secret_hash, user_name, created_at, expires_at) values ($1, $2, $3, $4)",
    )
    .bind(secret_hash)
    .bind(user.as_str())
    .bind(At(now))
    .bind(At(expires_at))
    .execute(&mut *tx)
    .await?;
    tx.commit().await
}

/// The user of the session with this secret hash, unless it expired by `now`.
#[tracing::instrument(skip_all)]
pub async fn find_live(
    pool: &AnyPool,
    secret_hash: &str,
    now: OffsetDateTime,
) -> sqlx::Result<Option<SessionUser>> {
    sqlx::query_as(
        "select users.name, users.role, sessions.expires_at
         from sessions join users on users.name = sessions.user_name
         where sessions.secret_hash = $1 and sessions.expires_at > $2",
    )
    .bind(secret_hash)
    .bind(At(now))
    .fetch_optional(pool)
    .await
}

/// Ends one session (logout); false when it did not exist.
#[tracing::instrument(skip_all)]
pub async fn delete(db: &Db, secret_hash: &str) -> sqlx::Result<bool> {
    let mut tx = db.begin_write().await?;
    let deleted = sqlx::query("delete from sessions where secret_hash = $1")
        .bind(secret_hash)
        .execute(&mut *tx)
        .await?
        .rows_affected()
        == 1;
    tx.commit().await?;
    Ok(deleted)
}

/// Ends every session of a user except `keep` (the one that changed the password, if any).
#[tracing::instrument(skip_all, fields(user = %user))]
pub async fn delete_for_user(db: &Db, user: &UserName, keep: Option<&str>) -> sqlx::Result<u64> {
    let mut tx = db.begin_write().await?;
    let deleted = sqlx::query(
        "delete from sessions where user_name = $1 and ($2 is null or secret_hash != $2)",
    )
    .bind(user.as_str())
    .bind(keep)
    .execute(&mut *tx)
    .await?
    .rows_affected();
    tx.commit().await?;
    Ok(deleted)
}
