//! Logins for the web UI. Only the argon2id hash of a password is stored, never the password.

use serde::Serialize;
use sqlx::AnyPool;
use time::OffsetDateTime;

use crate::store::columns::{At, Flag};

use crate::clock;
use crate::identity::{Role, UserName};
use crate::store::db::Db;

/// A user as listed: everything but the password hash.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, sqlx::FromRow)]
pub struct UserRecord {
    pub name: String,
    pub role: String,
    #[serde(with = "clock::stored")]
    #[sqlx(try_from = "At")]
    pub created_at: OffsetDateTime,
    #[serde(with = "clock::stored")]
    #[sqlx(try_from = "At")]
    pub password_changed_at: OffsetDateTime,
}

/// Creates a user; a name that exists already is a unique violation the caller maps.
#[tracing::instrument(skip_all, fields(name = %name, role = %role))]
pub async fn create(
    db: &Db,
    name: &UserName,
    role: Role,
    password_hash: &str,
) -> sqlx::Result<UserRecord> {
    let now = clock::recorded_now();
    let record = UserRecord {
        name: name.as_str().to_owned(),
        role: role.as_str().to_owned(),
        created_at: now,
        password_changed_at: now,
    };
    let mut tx = db.begin_write().await?;
    sqlx::query(
        "insert into users (name, role, password_hash, created_at, password_changed_at)
         values ($1, $2, $3, $4, $5)",
    )
    .bind(&record.name)
    .bind(&record.role)
    .bind(password_hash)
    .bind(At(record.created_at))
    .bind(At(record.password_changed_at))
    .execute(&mut *tx)
    .await?;
    tx.commit().await?;
    Ok(record)
}

/// Up to `limit` users after the name `after`, in name order.
#[tracing::instrument(skip_all)]
pub async fn list(
    pool: &AnyPool,
    after: Option<&str>,
    limit: u32,
) -> sqlx::Result<Vec<UserRecord>> {
    sqlx::query_as(
        "select name, role, created_at, password_changed_at from users
         where ($1 is null or name > $1) order by name limit $2",
    )
    .bind(after)
    .bind(i64::from(limit))
    .fetch_all(pool)
    .await
}

/// A user and their password hash, for checking a password.
#[tracing::instrument(skip_all)]
pub async fn find_with_hash(
    pool: &AnyPool,
    name: &UserName,
) -> sqlx::Result<Option<(UserRecord, String)>> {
    let row: Option<(String, String, At, At, String)> = sqlx::query_as(
        "select name, role, created_at, password_changed_at, password_hash from users
         where name = $1",
    )
    .bind(name.as_str())
    .fetch_optional(pool)
    .await?;
    Ok(row.map(|(name, role, created_at, password_changed_at, hash)| {
        let (At(created_at), At(password_changed_at)) = (created_at, password_changed_at);
        (UserRecord { name, role, created_at, password_changed_at }, hash)
    }))
}

/// Replaces a user's password hash; false when there is no such user.
#[tracing::instrument(skip_all, fields(name = %name))]
pub async fn set_password(db: &Db, name: &UserName, password_hash: &str) -> sqlx::Result<bool> {
    let mut tx = db.begin_write().await?;
    let changed = sqlx::query(
        "update users set password_hash = $1, password_changed_at = $2 where name = $3",
    )
    .bind(password_hash)
    .bind(At(clock::recorded_now()))
    .bind(name.as_str())
    .execute(&mut *tx)
    .await?
    .rows_affected()
        == 1;
    tx.commit().await?;
    Ok(changed)
}

/// Deletes a user and, through the foreign key, their sessions; false when there is none.
#[tracing::instrument(skip_all, fields(name = %name))]
pub async fn delete(db: &Db, name: &UserName) -> sqlx::Result<bool> {
    let mut tx = db.begin_write().await?;
    let deleted = sqlx::query("delete from users where name = $1")
        .bind(name.as_str())
        .execute(&mut *tx)
        .await?
        .rows_affected()
        == 1;
    tx.commit().await?;
    Ok(deleted)
}

/// Whether an admin login exists: the first start makes an admin token only when neither an
/// admin token nor an admin user does.
pub async fn admin_exists(executor: impl sqlx::AnyExecutor<'_>) -> sqlx::Result<bool> {
    let found: Flag = sqlx::query_scalar(
        "select case when exists (select 1 from users where role = 'admin') then 1 else 0 end",
    )
    .fetch_one(executor)
    .await?;
    Ok(found.into())
}
