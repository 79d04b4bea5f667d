//! The Home Assistant bridge's lease in the store: one holder at a time, renewed by its
//! holder, taken over only once it ran out or was given up; and the bridge's credential as the
//! bridge reads it. On the store under test (SQLite, or PostgreSQL with `PPS_TEST_STORE`).

use pps_server::identity::Role;
use pps_server::store::home_assistant::{self, Credential};
use pps_server::store::tokens;
use pps_server::{Db, clock};
use pps_test_kit::TestServer;

const NAME: &str = "Home Assistant bridge";

fn in_seconds(seconds: i64) -> String {
    clock::format(time::OffsetDateTime::now_utc() + time::Duration::seconds(seconds))
}

async fn take(db: &Db, holder: &str, until: &str) -> bool {
    let mut tx = db.begin_write().await.unwrap();
    let held = home_assistant::take_lease(&mut tx, holder, until).await.unwrap();
    tx.commit().await.unwrap();
    held
}

async fn holds(db: &Db, holder: &str) -> bool {
    let mut conn = db.reader().acquire().await.unwrap();
    home_assistant::holds_lease(&mut conn, holder).await.unwrap()
}

#[tokio::test]
async fn one_holder_at_a_time_until_its_lease_runs_out_or_is_given_up() {
    let server = TestServer::start().await;
    let db = &server.db;
    assert!(take(db, "replica-a", &in_seconds(20)).await, "a free lease is taken");
    assert!(!take(db, "replica-b", &in_seconds(20)).await, "a held lease is not");
    assert!(take(db, "replica-a", &in_seconds(20)).await, "its holder renews it");
    assert!(holds(db, "replica-a").await && !holds(db, "replica-b").await);

    // A renewal that ends in the past: as if replica-a died long ago.
    assert!(!take(db, "replica-a", &in_seconds(-1)).await, "a lease that ran out is not held");
    assert!(take(db, "replica-b", &in_seconds(20)).await, "a lease that ran out is taken over");
    assert!(!holds(db, "replica-a").await, "the old holder knows it lost it");

    let mut tx = db.begin_write().await.unwrap();
    home_assistant::release_lease(&mut tx, "replica-b").await.unwrap();
    tx.commit().await.unwrap();
    assert!(take(db, "replica-a", &in_seconds(20)).await, "a lease given up is taken at once");
}

#[tokio::test]
async fn the_bridge_credential_is_missing_live_or_revoked() {
    let server = TestServer::start().await;
    let state = || home_assistant::credential(server.db.reader(), NAME);
    assert_eq!(state().await.unwrap(), Credential::Missing);
    let minted = tokens::create(&server.db, Role::Caretaker, NAME, None).await.unwrap();
    assert_eq!(state().await.unwrap(), Credential::Live);
    assert!(tokens::revoke(&server.db, &minted.record.id).await.unwrap());
    assert_eq!(state().await.unwrap(), Credential::Revoked);
    // An admin token of that name is not the bridge's caretaker credential.
    tokens::create(&server.db, Role::Admin, NAME, None).await.unwrap();
    assert_eq!(state().await.unwrap(), Credential::Revoked);
    tokens::create(&server.db, Role::Caretaker, NAME, None).await.unwrap();
    assert_eq!(state().await.unwrap(), Credential::Live, "a new caretaker token allows presses");
}
