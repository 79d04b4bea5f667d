//! Databases in the throwaway PostgreSQL cluster the test command starts
//! (`tests/postgres/start`), named by `PPS_TEST_POSTGRES`.

use pps_server::db::Location;
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
    let cluster = cluster();
    let name = format!("test_{}", uuid::Uuid::new_v4().simple());
    let mut admin = sqlx::PgConnection::connect(&cluster).await.unwrap();
    sqlx::raw_sql(sqlx::AssertSqlSafe(format!("create database {name}")))
        .execute(&mut admin)
        .await
        .unwrap();
    admin.close().await.unwrap();
    let mut url = url::Url::parse(&cluster).unwrap();
    url.set_path(&name);
    Location::Postgres(url.to_string())
}
