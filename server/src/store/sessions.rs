//! Browser sessions: the SHA-256 of each session's secret, its user and its fixed expiry.
//!
//! Reading a session writes nothing: the expiry is set at login and never extended.

use sqlx::AnyPool;

use crate::clock;
use crate::identity::UserName;
use crate::store::db::Db;

/// A live session's user, as the access check needs it.
#[derive(Debug, Clone, PartialEq, Eq, sqlx::FromRow)]
pub struct SessionUser {
    pub name: String,
    pub role: String,
    pub expires_at: String,
}

/// Stores a new session, and clears out sessions that have expired on the way.
#[tracing::instrument(skip_all, fields(user = %user))]
pub async fn create(
    db: &Db,
    secret_hash: &str,
    user: &UserName,
    expires_at: &str,
) -> sqlx::Result<()> {
    let now = clock::now();
    let mut tx = db.begin_write().await?;
    sqlx::query("delete from sessions where expires_at <= $1").bind(&now).execute(&mut *tx).await?;
    sqlx::query(
        "insert into sessions (secret_hash, user_name, created_at, expires_at) values ($1, $2, $3, $4)",
    )
    .bind(secret_hash)
    .bind(user.as_str())
    .bind(&now)
    .bind(expires_at)
    .execute(&mut *tx)
    .await?;
    tx.commit().await
}

/// The user of the unexpired session with this secret hash.
#[tracing::instrument(skip_all)]
pub async fn find_live(pool: &AnyPool, secret_hash: &str) -> sqlx::Result<Option<SessionUser>> {
    sqlx::query_as(
        "select users.name, users.role, sessions.expires_at
         from sessions join users on users.name = sessions.user_name
         where sessions.secret_hash = $1 and sessions.expires_at > $2",
    )
    .bind(secret_hash)
    .bind(clock::now())
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
