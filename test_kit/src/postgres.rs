//! Databases in the throwaway PostgreSQL cluster the test command starts
//! (`tests/postgres/start`), named by `PPS_TEST_POSTGRES`. The load benchmark uses it too.

use pps_server::store::db::Location;
use sqlx::Connection;

/// The cluster's URL; the tests that need PostgreSQL cannot run without one.
pub fn cluster() -> String {
    std::env::var("PPS_TEST_POSTGRES").unwrap_or_else(|_| {
        panic!(
            "PPS_TEST_POSTGRES names no PostgreSQL cluster: run the test command (tests/run), \
             or start one with `tests/postgres/start DIR` and export the URL it prints"
        )
    })
}

/// A new, empty database in the cluster, for one test.
pub async fn fresh_database() -> Location {
    fresh_database_in(&cluster()).await.unwrap()
}

/// A new, empty database in the cluster at `cluster`.
pub async fn fresh_database_in(cluster: &str) -> anyhow::Result<Location> {
    let name = format!("test_{}", uuid::Uuid::new_v4().simple());
    let mut admin = sqlx::PgConnection::connect(cluster).await?;
    sqlx::raw_sql(sqlx::AssertSqlSafe(format!("create database {name}")))
        .execute(&mut admin)
        .await?;
    admin.close().await?;
    let mut url = url::Url::parse(cluster)?;
    url.set_path(&name);
    Ok(Location::Postgres(url.to_string()))
}
