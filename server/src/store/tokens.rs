//! API tokens in the database: only their SHA-256 is ever stored.

use serde::Serialize;
use sqlx::AnyPool;
use time::OffsetDateTime;

use crate::store::columns::{At, Flag, MaybeAt};

use crate::clock;
use crate::identity::{Role, secret};
use crate::store::db::Db;
use crate::store::users;

/// A token as listed: everything but the secret, which is shown once at creation.
#[derive(Debug, Clone, Serialize, sqlx::FromRow)]
pub struct TokenRecord {
    pub id: String,
    pub name: String,
    pub role: String,
    pub robot_id: Option<String>,
    #[serde(with = "clock::stored")]
    #[sqlx(try_from = "At")]
    pub created_at: OffsetDateTime,
    #[serde(with = "clock::stored::option")]
    #[sqlx(try_from = "MaybeAt")]
    pub expires_at: Option<OffsetDateTime>,
    #[serde(with = "clock::stored::option")]
    #[sqlx(try_from = "MaybeAt")]
    pub revoked_at: Option<OffsetDateTime>,
}

/// A token just minted: the record plus the secret, which exists nowhere else.
#[derive(Debug, Serialize)]
pub struct MintedToken {
    #[serde(flatten)]
    pub record: TokenRecord,
    pub token: String,
}

/// Why `name` cannot name a token of `role`, in words for whoever chose it: a robot token's
/// name is its robot's id; any other is 1 to 100 characters, none of them control characters
/// (which would garble `token list` in a terminal).
pub fn name_problem(role: Role, name: &str) -> Option<String> {
    if role == Role::Robot {
        return pps_schema::RobotId::parse(name)
            .err()
            .map(|e| format!("a robot token's name is the robot's id: {e}"));
    }
    if name.trim().is_empty() || name.chars().count() > 100 {
        Some("a token's name is 1 to 100 characters".into())
    } else if name.chars().any(char::is_control) {
        Some("a token's name cannot hold control characters (newlines, tabs, escapes)".into())
    } else {
        None
    }
}

/// Mints a token. For a robot token, `name` is the robot id it is bound to.
#[tracing::instrument(skip_all, fields(role = %role))]
pub async fn create(
    db: &Db,
    role: Role,
    name: &str,
    expires_at: Option<OffsetDateTime>,
) -> sqlx::Result<MintedToken> {
    let mut tx = db.begin_write().await?;
    let minted = insert(&mut tx, role, name, expires_at).await?;
    tx.commit().await?;
    Ok(minted)
}

/// Mints the first admin token, unless an admin credential exists (a live admin token, or an
/// admin user of the web UI). Looked for and minted under the write lock, so of several
/// replicas starting together on one new database exactly one mints it.
pub async fn create_first_admin(db: &Db, now: OffsetDateTime) -> sqlx::Result<Option<MintedToken>> {
    let mut tx = db.begin_write().await?;
    if live_admin_exists(&mut *tx, now).await? || users::admin_exists(&mut *tx).await? {
        return Ok(None);
    }
    let minted = insert(&mut tx, Role::Admin, "first admin", None).await?;
    tx.commit().await?;
    Ok(Some(minted))
}

async fn insert(
    tx: &mut sqlx::AnyConnection,
    role: Role,
    name: &str,
    expires_at: Option<OffsetDateTime>,
) -> sqlx::Result<MintedToken> {
    let token = secret::mint_token();
    let record = TokenRecord {
        id: secret::mint_id(),
        name: name.to_owned(),
        role: role.as_str().to_owned(),
        robot_id: (role == Role::Robot).then(|| name.to_owned()),
        created_at: clock::recorded_now(),
        expires_at,
        revoked_at: None,
    };
    sqlx::query(
        "insert into tokens (id, name, role, robot_id, secret_hash, created_at, expires_at)
         values ($1, $2, $3, $4, $5, $6, $7)",
    )
    .bind(&record.id)
    .bind(&record.name)
    .bind(&record.role)
    .bind(&record.robot_id)
    .bind(secret::hash(&token))
    .bind(At(record.created_at))
    .bind(MaybeAt(record.expires_at))
    .execute(&mut *tx)
    .await?;
    Ok(MintedToken { record, token })
}

#[tracing::instrument(skip_all)]
pub async fn list(pool: &AnyPool) -> sqlx::Result<Vec<TokenRecord>> {
    sqlx::query_as(
        "select id, name, role, robot_id, created_at, expires_at, revoked_at
         from tokens order by created_at, id",
    )
    .fetch_all(pool)
    .await
}

/// Revokes a token; false when no token has that id or it was already revoked.
#[tracing::instrument(skip_all)]
pub async fn revoke(db: &Db, id: &str) -> sqlx::Result<bool> {
    let mut tx = db.begin_write().await?;
    let done =
        sqlx::query("update tokens set revoked_at = $1 where id = $2 and revoked_at is null")
            .bind(At(clock::recorded_now()))
            .bind(id)
            .execute(&mut *tx)
            .await?
            .rows_affected()
            == 1;
    tx.commit().await?;
    Ok(done)
}

/// The live (not revoked, not expired by `now`) token with this secret hash.
#[tracing::instrument(skip_all)]
pub async fn find_live(
    pool: &AnyPool,
    secret_hash: &str,
    now: OffsetDateTime,
) -> sqlx::Result<Option<TokenRecord>> {
    sqlx::query_as(
        "select id, name, role, robot_id, created_at, expires_at, revoked_at
         from tokens
         where secret_hash = $1 and revoked_at is null and (expires_at is null or expires_at > $2)",
    )
    .bind(secret_hash)
    .bind(At(now))
    .fetch_optional(pool)
    .await
}

/// Whether any admin credential that still works at `now` exists.
pub async fn live_admin_exists(
    executor: impl sqlx::AnyExecutor<'_>,
    now: OffsetDateTime,
) -> sqlx::Result<bool> {
    let found: Flag = sqlx::query_scalar(
        "select case when exists (select 1 from tokens where role = 'admin' and revoked_at is null
                                  and (expires_at is null or expires_at > $1))
                then 1 else 0 end",
    )
    .bind(At(now))
    .fetch_one(executor)
    .await?;
    Ok(found.into())
}
