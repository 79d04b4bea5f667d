//! The Home Assistant bridge's lease in the store: one holder at a time, renewed by its
//! holder, taken over only once it ran out or was given up; and the bridge's credential as the
//! bridge reads it. On the store under test (SQLite, or PostgreSQL with `PPS_TEST_STORE`).

use pps_server::Db;
use pps_server::identity::Role;
use pps_server::store::home_assistant::{self, Credential};
use pps_server::store::tokens;
use pps_test_kit::TestServer;
use time::{Duration, OffsetDateTime};

const NAME: &str = "Home Assistant bridge";
const LEASE: Duration = Duration::seconds(20);

/// Takes or renews the lease at `now` for [`LEASE`].
async fn take(db: &Db, holder: &str, now: OffsetDateTime) -> bool {
    let mut tx = db.begin_write().await.unwrap();
    let held = home_assistant::take_lease(&mut tx, holder, now, now + LEASE).await.unwrap();
    tx.commit().await.unwrap();
    held
}

async fn holds(db: &Db, holder: &str, now: OffsetDateTime) -> bool {
    let mut conn = db.reader().acquire().await.unwrap();
    home_assistant::holds_lease(&mut conn, holder, now).await.unwrap()
}

#[tokio::test]
async fn one_holder_at_a_time_until_its_lease_runs_out_or_is_given_up() {
    let server = TestServer::start().await;
    let db = &server.db;
    let start = server.now();
    assert!(take(db, "replica-a", start).await, "a free lease is taken");
    assert!(!take(db, "replica-b", start).await, "a held lease is not");
    let renewed = start + Duration::seconds(15);
    assert!(take(db, "replica-a", renewed).await, "its holder renews it");
    let after_first = start + LEASE + Duration::seconds(1);
    assert!(
        holds(db, "replica-a", after_first).await && !holds(db, "replica-b", after_first).await
    );
    assert!(!take(db, "replica-b", after_first).await, "the renewal counts from when it was made");

    // replica-a dies: no renewal, and its lease runs out.
    let ran_out = renewed + LEASE;
    assert!(!holds(db, "replica-a", ran_out).await, "a lease that ran out is not held");
    assert!(take(db, "replica-b", ran_out).await, "a lease that ran out is taken over");
    assert!(!holds(db, "replica-a", ran_out).await, "the old holder knows it lost it");
    assert!(!take(db, "replica-a", ran_out).await, "and cannot take it back");

    let mut tx = db.begin_write().await.unwrap();
    home_assistant::release_lease(&mut tx, "replica-b").await.unwrap();
    tx.commit().await.unwrap();
    assert!(take(db, "replica-a", ran_out).await, "a lease given up is taken at once");
}

#[tokio::test]
async fn the_bridge_credential_is_missing_live_or_revoked() {
    let server = TestServer::start().await;
    let state = || home_assistant::credential(server.db.reader(), NAME, server.now());
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
    let expiring = server.now() + Duration::hours(1);
    tokens::create(&server.db, Role::Caretaker, "bridge, for an hour", Some(expiring))
        .await
        .unwrap();
    let named = |now| home_assistant::credential(server.db.reader(), "bridge, for an hour", now);
    assert_eq!(named(server.now()).await.unwrap(), Credential::Live);
    assert_eq!(
        named(expiring).await.unwrap(),
        Credential::Revoked,
        "expired is as good as revoked"
    );
}
