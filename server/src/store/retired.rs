//! EPCs retired when a worn tag was replaced, each pointing at its successor.

use pps_schema::Epc;
use sqlx::AnyConnection;

use crate::clock;

/// The EPC that replaced `epc`, following a chain of replacements to the current one.
pub async fn successor(conn: &mut AnyConnection, epc: &Epc) -> sqlx::Result<Option<Epc>> {
    let mut current: Option<String> = None;
    let mut next = epc.as_hex().to_owned();
    // A chain longer than this would mean a cycle, which retagging never creates.
    for _ in 0..64 {
        let found: Option<String> =
            sqlx::query_scalar("select successor from retired_epcs where epc = $1")
                .bind(&next)
                .fetch_optional(&mut *conn)
                .await?;
        match found {
            Some(successor) => {
                current = Some(successor.clone());
                next = successor;
            }
            None => break,
        }
    }
    current
        .map(|hex| Epc::parse(&hex).map_err(|error| sqlx::Error::Decode(error.into())))
        .transpose()
}

/// The first EPC the tag behind `epc` ever had, following its replacements back (`epc` itself
/// when it never replaced one): what stays the same when a worn tag is replaced.
pub async fn origin(conn: &mut AnyConnection, epc: &Epc) -> sqlx::Result<Epc> {
    let mut first = epc.as_hex().to_owned();
    // A chain longer than this would mean a cycle, which retagging never creates.
    for _ in 0..64 {
        let found: Option<String> =
            sqlx::query_scalar("select epc from retired_epcs where successor = $1")
                .bind(&first)
                .fetch_optional(&mut *conn)
                .await?;
        match found {
            Some(predecessor) => first = predecessor,
            None => break,
        }
    }
    Epc::parse(&first).map_err(|error| sqlx::Error::Decode(error.into()))
}

pub async fn retire(
    conn: &mut AnyConnection,
    epc: &Epc,
    successor: &Epc,
    by: &str,
) -> sqlx::Result<()> {
    sqlx::query(
        "insert into retired_epcs (epc, successor, retired_at, retired_by) values ($1, $2, $3, $4)",
    )
    .bind(epc.as_hex())
    .bind(successor.as_hex())
    .bind(clock::now())
    .bind(by)
    .execute(conn)
    .await?;
    Ok(())
}
