//! Credentials tested as a table: every route of the router × every kind of caller, against
//! the roles of DESIGN §4. No credential, a malformed, expired or revoked one is 401 on every
//! route that is not open; a role without the right is 403; a role with it gets past both.
//!
//! The rows come from the router's own route table, so a new route fails this test until its
//! DESIGN rule and a real request for it are written down in [`rule`] and [`probe`].

use std::fmt::Write as _;

use pps_server::RouteSpec;
use pps_server::identity::Role;
use pps_server::store::tokens;
use pps_test_kit::*;
use reqwest::{Method, RequestBuilder, StatusCode};
use serde_json::{Value, json};

/// Who may call a route, in the words of DESIGN §4's table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rule {
    Open,
    All,
    Editors,
    Admin,
    /// "that robot, caretaker, admin": a robot only for its own robot id or records.
    ThatRobotAndEditors,
    /// "that robot": only the robot itself.
    ThatRobot,
    /// "that user, admin".
    ThatUserAndAdmin,
}

/// The columns of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Caller {
    Admin,
    Caretaker,
    /// A robot token bound to `el-e-1`, the robot every probe names.
    OwnRobot,
    /// A robot token bound to another robot.
    OtherRobot,
    /// A caretaker logged in through the browser login: cookie and anti-forgery token.
    CaretakerSession,
    Nobody,
    Malformed,
    Expired,
    Revoked,
}

const CALLERS: [Caller; 9] = [
    Caller::Admin,
    Caller::Caretaker,
    Caller::OwnRobot,
    Caller::OtherRobot,
    Caller::CaretakerSession,
    Caller::Nobody,
    Caller::Malformed,
    Caller::Expired,
    Caller::Revoked,
];

/// What the table demands of one cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Verdict {
    Unauthenticated,
    Forbidden,
    /// Past authentication and authorisation: neither 401 nor 403 (nor a server error).
    Allowed,
}

fn verdict(rule: Rule, caller: Caller) -> Verdict {
    use Caller as C;
    use Rule as R;
    match (rule, caller) {
        (R::Open, _) => Verdict::Allowed,
        (_, C::Nobody | C::Malformed | C::Expired | C::Revoked) => Verdict::Unauthenticated,
        (R::All, _) => Verdict::Allowed,
        (R::Editors | R::ThatRobotAndEditors, C::Admin | C::Caretaker | C::CaretakerSession) => {
            Verdict::Allowed
        }
        (R::Admin | R::ThatUserAndAdmin, C::Admin) => Verdict::Allowed,
        (R::ThatRobotAndEditors | R::ThatRobot, C::OwnRobot) => Verdict::Allowed,
        _ => Verdict::Forbidden,
    }
}

/// DESIGN §4's rule for a route of the router.
fn rule(route: &RouteSpec) -> Rule {
    use Rule::*;
    match (route.method.as_str(), route.path) {
        (
            "GET",
            "/healthz" | "/readyz" | "/metrics" | "/api/v1/openapi.json" | "/api/v1/schema/{name}",
        ) => Open,
        ("POST", "/api/v1/session") => Open,
        ("GET", "/api/v1/tags" | "/api/v1/tags/{epc}" | "/api/v1/tags/{epc}/stats") => All,
        ("GET", "/api/v1/robots" | "/api/v1/robots/{robot}" | "/api/v1/events") => All,
        // Not in DESIGN's table: who the credential belongs to, for any credential.
        ("GET", "/api/v1/session") => All,
        // "that session": any caller may ask; only a browser session has one to end.
        ("DELETE", "/api/v1/session") => All,
        ("PUT" | "DELETE", "/api/v1/tags/{epc}") => Editors,
        ("GET", "/api/v1/tags/{epc}/revisions" | "/api/v1/inbox") => Editors,
        // A tag's newest picture, for the tag list: people's, not robots' (a robot reads the
        // pictures of its own trials).
        ("GET", "/api/v1/tags/{epc}/picture") => Editors,
        ("POST", "/api/v1/tags/{epc}/retag" | "/api/v1/validate/tag") => Editors,
        ("GET", "/api/v1/robots/{robot}/tags/{epc}") => ThatRobotAndEditors,
        ("GET" | "PATCH", "/api/v1/trials/{id}") | ("GET", "/api/v1/trials") => ThatRobotAndEditors,
        ("PUT", "/api/v1/trials/{id}") => ThatRobot,
        // DESIGN §10: readable by whoever may read the trial; sent by the robot that made it.
        ("GET", "/api/v1/trials/{id}/picture") => ThatRobotAndEditors,
        ("PUT", "/api/v1/trials/{id}/picture") => ThatRobot,
        ("POST", "/api/v1/tasks" | "/api/v1/tasks/{id}/cancel") => Editors,
        // "caretaker, admin; a robot: those it may claim or holds".
        ("GET", "/api/v1/tasks" | "/api/v1/tasks/{id}") => ThatRobotAndEditors,
        // "that robot" and "the holder".
        ("POST", "/api/v1/robots/{robot}/tasks/claim") => ThatRobot,
        (
            "POST",
            "/api/v1/tasks/{id}/heartbeat"
            | "/api/v1/tasks/{id}/finish"
            | "/api/v1/tasks/{id}/decline",
        ) => ThatRobot,
        ("PUT", "/api/v1/robots/{robot}") => Admin,
        ("GET" | "POST", "/api/v1/users" | "/api/v1/tokens") => Admin,
        ("GET", "/api/v1/home-assistant") => Admin,
        ("DELETE", "/api/v1/users/{name}" | "/api/v1/tokens/{id}") => Admin,
        ("PUT", "/api/v1/users/{name}/password") => ThatUserAndAdmin,
        (method, path) => panic!("{method} {path} is not in DESIGN §4's table: add its rule"),
    }
}

/// What the probes need besides the seeds and the constants below.
struct Fixture {
    victim_token_id: String,
    /// A task meant for `el-e-1` alone, claimed by it.
    task_id: String,
    /// The caretaker's password login, for the login route and the session column.
    login: Value,
}

const TRIAL_ID: &str = "6f1c0d9e-2b7a-4c3e-9d51-7a2b3c4d5e6f";
const CARETAKER: &str = "alice";
const PASSWORD: &str = "correct horse battery";
/// A user whose password the probes change, so the session's user stays logged in.
const OTHER_USER: &str = "bob";
/// A user the probes delete.
const DOOMED_USER: &str = "erin";
const LAMP: &str = "355AB1C60000003000000001";

/// A real request for a route: a path with real ids, and the body and precondition a client
/// that means it would send.
struct Probe {
    path: String,
    body: Option<Value>,
    /// A picture's bytes, sent as PNG, instead of a JSON body.
    picture: Option<Vec<u8>>,
    if_match: bool,
}

fn probe(route: &RouteSpec, fixture: &Fixture) -> Probe {
    let trial_path = format!("/api/v1/trials/{TRIAL_ID}");
    let (path, body): (String, Option<Value>) = match (route.method.as_str(), route.path) {
        (_, "/api/v1/schema/{name}") => ("/api/v1/schema/tag".into(), None),
        ("PUT", "/api/v1/tags/{epc}") => {
            (format!("/api/v1/tags/{ADA_SWITCH}"), Some(new_entry(ADA_SWITCH, "ADA switch")))
        }
        ("DELETE", "/api/v1/tags/{epc}") => (format!("/api/v1/tags/{DRAWER}"), None),
        (_, "/api/v1/tags/{epc}/retag") => (
            format!("/api/v1/tags/{LAMP}/retag"),
            Some(json!({ "new_epc": "E2003412000000000000BEEF" })),
        ),
        (_, "/api/v1/validate/tag") => (route.path.into(), Some(new_entry(ADA_SWITCH, "check"))),
        ("PUT", "/api/v1/robots/{robot}") => (
            "/api/v1/robots/el-e-1".into(),
            Some(json!({ "class": "el-e", "name": "EL-E", "capabilities": ["light_switch"] })),
        ),
        ("PUT", "/api/v1/trials/{id}") => {
            (trial_path, Some(trial(TRIAL_ID, ADA_SWITCH, "el-e-1", "on", "push_top", "success")))
        }
        ("PATCH", "/api/v1/trials/{id}") => (trial_path, Some(json!({ "confirmed": true }))),
        ("GET", "/api/v1/trials") => ("/api/v1/trials?robot=el-e-1".into(), None),
        ("POST", "/api/v1/tasks") => (
            route.path.into(),
            Some(json!({ "epc": ADA_SWITCH, "action": "on", "robot": "el-e-1" })),
        ),
        ("GET", "/api/v1/tasks") => ("/api/v1/tasks?robot=el-e-1".into(), None),
        (_, "/api/v1/robots/{robot}/tasks/claim") => {
            ("/api/v1/robots/el-e-1/tasks/claim?wait=0".into(), None)
        }
        (_, "/api/v1/tasks/{id}/finish") => (
            format!("/api/v1/tasks/{}/finish", fixture.task_id),
            Some(json!({ "trial": TRIAL_ID, "outcome": "success" })),
        ),
        (_, "/api/v1/tasks/{id}/decline") => (
            format!("/api/v1/tasks/{}/decline", fixture.task_id),
            Some(json!({ "reason": "its arm cannot reach the switch" })),
        ),
        (_, path) if path.starts_with("/api/v1/tasks/{id}") => {
            (path.replace("{id}", &fixture.task_id), None)
        }
        ("POST", "/api/v1/tokens") => {
            (route.path.into(), Some(json!({ "role": "caretaker", "name": "new nurse" })))
        }
        ("DELETE", "/api/v1/tokens/{id}") => {
            (format!("/api/v1/tokens/{}", fixture.victim_token_id), None)
        }
        ("POST", "/api/v1/session") => (route.path.into(), Some(fixture.login.clone())),
        ("POST", "/api/v1/users") => (
            route.path.into(),
            Some(json!({ "name": "carol", "role": "caretaker", "password": PASSWORD })),
        ),
        ("DELETE", "/api/v1/users/{name}") => (format!("/api/v1/users/{DOOMED_USER}"), None),
        (_, "/api/v1/users/{name}/password") => (
            format!("/api/v1/users/{OTHER_USER}/password"),
            Some(json!({ "password": "another long password" })),
        ),
        (_, path) => (
            path.replace("{epc}", ADA_SWITCH)
                .replace("{robot}", "el-e-1")
                .replace("{id}", TRIAL_ID),
            None,
        ),
    };
    assert!(!path.contains('{'), "{} {}: give the probe real ids", route.method, route.path);
    let tag_write = route.path == "/api/v1/tags/{epc}" && route.method != Method::GET;
    let picture = (route.method == Method::PUT && route.path.ends_with("/picture"))
        .then(|| b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x10\0\0\0\x10\x08\x02\0\0\0".to_vec());
    Probe { path, body, picture, if_match: tag_write }
}

/// A browser session: the cookie and the anti-forgery token its login returned.
struct BrowserSession {
    cookie: String,
    csrf: String,
}

async fn log_in(server: &TestServer, login: &Value) -> BrowserSession {
    let response =
        server.request(Method::POST, "/api/v1/session", None).json(login).send().await.unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let cookie = response.headers()["set-cookie"].to_str().unwrap();
    let cookie = cookie.split(';').next().unwrap().to_owned();
    let body: Value = response.json().await.unwrap();
    BrowserSession { cookie, csrf: body["csrf_token"].as_str().unwrap().to_owned() }
}

async fn add_user(server: &TestServer, name: &str) {
    let response = server
        .request(Method::POST, "/api/v1/users", Some(&server.admin))
        .json(&json!({ "name": name, "role": "caretaker", "password": PASSWORD }))
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::CREATED);
}

/// The credential of every column but the session's, which is logged in per cell.
struct Credentials {
    admin: String,
    caretaker: String,
    own_robot: String,
    other_robot: String,
    expired: String,
    revoked: String,
}

impl Credentials {
    async fn mint(server: &TestServer) -> Self {
        let yesterday = server.now() - time::Duration::days(1);
        let expired = tokens::create(&server.db, Role::Admin, "expired", Some(yesterday));
        // Revoked before its first use, so no cache has seen it.
        let revoked = tokens::create(&server.db, Role::Admin, "revoked", None).await.unwrap();
        assert!(tokens::revoke(&server.db, &revoked.record.id).await.unwrap());
        Self {
            admin: server.admin.clone(),
            caretaker: server.token(Role::Caretaker, "nurse").await,
            own_robot: server.token(Role::Robot, "el-e-1").await,
            other_robot: server.token(Role::Robot, "el-e-2").await,
            expired: expired.await.unwrap().token,
            revoked: revoked.token,
        }
    }

    fn apply(
        &self,
        caller: Caller,
        request: RequestBuilder,
        session: Option<&BrowserSession>,
    ) -> RequestBuilder {
        match (caller, session) {
            (Caller::Admin, _) => request.bearer_auth(&self.admin),
            (Caller::Caretaker, _) => request.bearer_auth(&self.caretaker),
            (Caller::OwnRobot, _) => request.bearer_auth(&self.own_robot),
            (Caller::OtherRobot, _) => request.bearer_auth(&self.other_robot),
            (Caller::CaretakerSession, Some(session)) => {
                request.header("cookie", &session.cookie).header("x-csrf-token", &session.csrf)
            }
            (Caller::CaretakerSession, None) => panic!("the session column logs in first"),
            (Caller::Nobody, _) => request,
            (Caller::Malformed, _) => request.header("authorization", "Bearer not a token"),
            (Caller::Expired, _) => request.bearer_auth(&self.expired),
            (Caller::Revoked, _) => request.bearer_auth(&self.revoked),
        }
    }
}

/// The records the probes name, made as a caretaker and a robot would make them.
async fn fixture(server: &TestServer, credentials: &Credentials) -> Fixture {
    register_robot(server, "el-e-1", "el-e", &["light_switch", "push", "drop"], 15.0).await;
    for name in [CARETAKER, OTHER_USER, DOOMED_USER] {
        add_user(server, name).await;
    }
    let recorded = server
        .put(
            &format!("/api/v1/trials/{TRIAL_ID}"),
            &credentials.own_robot,
            &trial(TRIAL_ID, ADA_SWITCH, "el-e-1", "on", "push_top", "success"),
            None,
        )
        .await;
    assert_eq!(recorded.status(), StatusCode::CREATED);
    let victim = tokens::create(&server.db, Role::Caretaker, "victim", None).await.unwrap();
    let task = server
        .request(Method::POST, "/api/v1/tasks", Some(&server.admin))
        .json(&json!({ "epc": ADA_SWITCH, "action": "on", "robot": "el-e-1" }))
        .send()
        .await
        .unwrap();
    assert_eq!(task.status(), StatusCode::CREATED);
    let task: Value = task.json().await.unwrap();
    let claimed = server
        .request(Method::POST, "/api/v1/robots/el-e-1/tasks/claim", Some(&credentials.own_robot))
        .send()
        .await
        .unwrap();
    assert_eq!(claimed.status(), StatusCode::OK);
    Fixture {
        victim_token_id: victim.record.id,
        task_id: task["id"].as_str().unwrap().to_owned(),
        login: json!({ "username": CARETAKER, "password": PASSWORD }),
    }
}

#[tokio::test]
async fn every_route_answers_every_caller_as_design_says() {
    let server = TestServer::start().await;
    let credentials = Credentials::mint(&server).await;
    let fixture = fixture(&server, &credentials).await;
    let routes = server.route_table();
    let mut table = String::new();
    let mut mismatches = Vec::new();
    for route in &routes {
        let rule = rule(route);
        let probe = probe(route, &fixture);
        let _ = write!(table, "{:<7}{:<40}", route.method.as_str(), route.path);
        for caller in CALLERS {
            // A fresh session per cell: logging out and password changes end sessions.
            let session = match caller {
                Caller::CaretakerSession => Some(log_in(&server, &fixture.login).await),
                _ => None,
            };
            let mut request = server
                .client
                .request(route.method.clone(), format!("{}{}", server.url, probe.path));
            if let Some(body) = &probe.body {
                request = request.json(body);
            }
            if let Some(picture) = &probe.picture {
                request = request.header("content-type", "image/png").body(picture.clone());
            }
            if probe.if_match {
                request = request.header("if-match", "*");
            }
            // The change feed's answer is a stream that never ends: its head is enough.
            let status =
                credentials.apply(caller, request, session.as_ref()).send().await.unwrap().status();
            let _ = write!(table, " {}", status.as_u16());
            let expected = verdict(rule, caller);
            let got = match status {
                StatusCode::UNAUTHORIZED => Verdict::Unauthenticated,
                StatusCode::FORBIDDEN => Verdict::Forbidden,
                _ => Verdict::Allowed,
            };
            if got != expected || status.is_server_error() {
                mismatches.push(format!(
                    "{} {} as {caller:?}: {status}; DESIGN says {expected:?} ({rule:?})",
                    route.method, route.path
                ));
            }
        }
        table.push('\n');
    }
    println!(
        "{} routes × {} callers = {} cells; columns: {CALLERS:?}\n{table}",
        routes.len(),
        CALLERS.len(),
        routes.len() * CALLERS.len(),
    );
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}
