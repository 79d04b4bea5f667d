//! EPCs retired when a worn tag was replaced, each pointing at its successor.

use pps_schema::Epc;
use sqlx::AnyConnection;

use crate::clock;
use crate::store::columns::At;

/// The EPC that replaced `epc`, following the chain of replacements, however long, to the
/// current one.
pub async fn successor(conn: &mut AnyConnection, epc: &Epc) -> sqlx::Result<Option<Epc>> {
    chain_end(conn, epc, Direction::Forward).await
}

/// The first EPC the tag behind `epc` ever had, following its replacements back, however
/// many (`epc` itself when it never replaced one): what stays the same when a worn tag is
/// replaced.
pub async fn origin(conn: &mut AnyConnection, epc: &Epc) -> sqlx::Result<Epc> {
    Ok(chain_end(conn, epc, Direction::Back).await?.unwrap_or_else(|| epc.clone()))
}

/// Which way a chain of replacements is walked.
enum Direction {
    /// To the EPC that replaced it, and on.
    Forward,
    /// To the EPC it replaced, and back.
    Back,
}

/// The far end of the chain of replacements from `epc`, `None` when the chain is empty.
async fn chain_end(
    conn: &mut AnyConnection,
    epc: &Epc,
    direction: Direction,
) -> sqlx::Result<Option<Epc>> {
    // One statement walks the whole chain. Retagging never makes a cycle (a retired EPC is
    // never reused), so the depth bound only keeps a damaged table from looping forever.
    let statement = match direction {
        Direction::Forward => {
            "with recursive chain (epc, depth) as (
                 select successor, 1 from retired_epcs where epc = $1
                 union all
                 select retired_epcs.successor, chain.depth + 1
                 from retired_epcs join chain on retired_epcs.epc = chain.epc
                 where chain.depth < $2
             )
             select epc from chain order by depth desc limit 1"
        }
        Direction::Back => {
            "with recursive chain (epc, depth) as (
                 select epc, 1 from retired_epcs where successor = $1
                 union all
                 select retired_epcs.epc, chain.depth + 1
                 from retired_epcs join chain on retired_epcs.successor = chain.epc
                 where chain.depth < $2
             )
             select epc from chain order by depth desc limit 1"
        }
    };
    let end: Option<String> = sqlx::query_scalar(statement)
        .bind(epc.as_hex())
        .bind(MAX_CHAIN)
        .fetch_optional(&mut *conn)
        .await?;
    end.map(|hex| Epc::parse(&hex).map_err(|error| sqlx::Error::Decode(error.into()))).transpose()
}

/// More replacements of one tag than a household could make in centuries.
const MAX_CHAIN: i64 = 1_000_000;

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
    .bind(At(clock::recorded_now()))
    .bind(by)
    .execute(conn)
    .await?;
    Ok(())
}
