//! Browser logins: password login, the session cookie and its flags, forgery protection,
//! logout, expiry, password changes, the login slow-down, user management and the CLI.
//!
//! Long because each test is a whole browser conversation (login, cookie, forgery token, the
//! next request); they share the login helpers at the top.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::time::Duration;

use pps_server::auth::session;
use pps_server::identity::password;
use pps_server::identity::{Role, UserName, secret};
use pps_server::store::{sessions, users};
use pps_test_kit::*;
use reqwest::header::{COOKIE, SET_COOKIE};
use reqwest::{Method, Response, StatusCode};
use serde_json::{Value, json};

const PASSWORD: &str = "correct horse battery";

/// A browser's credentials after login: the cookie it holds and the anti-forgery token.
struct Browser {
    cookie: String,
    csrf: String,
}

impl Browser {
    /// Sends a request the way the UI does: cookie, plus the token on unsafe methods.
    async fn send(
        &self,
        server: &TestServer,
        method: Method,
        path: &str,
        body: Option<Value>,
    ) -> Response {
        let unsafe_method = !matches!(method, Method::GET | Method::HEAD);
        let mut request = server.request(method, path, None).header(COOKIE, &self.cookie);
        if unsafe_method {
            request = request.header(session::CSRF_HEADER, &self.csrf);
        }
        if let Some(body) = body {
            request = request.json(&body);
        }
        request.send().await.unwrap()
    }
}

async fn add_user(server: &TestServer, name: &str, role: Role) {
    let hash = password::hash(PASSWORD).unwrap();
    users::create(&server.db, &UserName::parse(name).unwrap(), role, &hash).await.unwrap();
}

async fn login_response(server: &TestServer, username: &str, password: &str) -> Response {
    server
        .request(Method::POST, "/api/v1/session", None)
        .json(&json!({ "username": username, "password": password }))
        .send()
        .await
        .unwrap()
}

async fn log_in(server: &TestServer, username: &str, password: &str) -> Browser {
    let response = login_response(server, username, password).await;
    assert_eq!(response.status(), StatusCode::OK);
    let set_cookie = response.headers()[SET_COOKIE].to_str().unwrap().to_owned();
    let cookie = set_cookie.split(';').next().unwrap().to_owned();
    let body: Value = response.json().await.unwrap();
    Browser { cookie, csrf: body["csrf_token"].as_str().unwrap().to_owned() }
}

#[tokio::test]
async fn login_sets_a_strict_http_only_expiring_cookie_that_authenticates() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    // Phones capitalise the first letter; the login name is the same.
    let response = login_response(&server, "Anna", PASSWORD).await;
    assert_eq!(response.status(), StatusCode::OK);
    assert_eq!(response.headers()["cache-control"], "no-store");
    let set_cookie = response.headers()[SET_COOKIE].to_str().unwrap().to_owned();
    for flag in ["pps_session=", "HttpOnly", "SameSite=Strict", "Path=/", "Max-Age=43200"] {
        assert!(set_cookie.contains(flag), "{set_cookie} lacks {flag}");
    }
    let body: Value = response.json().await.unwrap();
    assert_eq!((body["name"].as_str(), body["role"].as_str()), (Some("anna"), Some("caretaker")));
    assert!(body["expires_at"].as_str().is_some());
    let cookie = set_cookie.split(';').next().unwrap();
    let browser =
        Browser { cookie: cookie.to_owned(), csrf: body["csrf_token"].as_str().unwrap().into() };

    let tags = browser.send(&server, Method::GET, "/api/v1/tags", None).await;
    assert_eq!(tags.status(), StatusCode::OK);
    let who: Value =
        browser.send(&server, Method::GET, "/api/v1/session", None).await.json().await.unwrap();
    assert_eq!(who["name"], "anna");
    assert_eq!(who["credential"], "session");
    assert_eq!(who["csrf_token"], body["csrf_token"], "a reloaded page gets the same token");

    // A change made through the session names the user in the history.
    let entry = new_entry("E20034120000000000007001", "hall switch");
    let created = server
        .request(Method::PUT, "/api/v1/tags/E20034120000000000007001", None)
        .header(COOKIE, &browser.cookie)
        .header(session::CSRF_HEADER, &browser.csrf)
        .header("if-none-match", "*")
        .json(&entry)
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    assert_eq!(created.json::<Value>().await.unwrap()["updated_by"], "anna");
}

#[tokio::test]
async fn a_wrong_password_and_an_unknown_user_get_the_same_plain_answer() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    for (user, pass) in [("anna", "not her password"), ("nobody", PASSWORD), ("<b>", PASSWORD)] {
        let response = login_response(&server, user, pass).await;
        assert!(!response.headers().contains_key(SET_COOKIE));
        let body = problem(response, StatusCode::UNAUTHORIZED).await;
        assert_eq!(body["detail"], "wrong user name or password");
    }
}

#[tokio::test]
async fn unsafe_requests_with_the_cookie_need_the_anti_forgery_token() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    let browser = log_in(&server, "anna", PASSWORD).await;
    let entry = new_entry("E20034120000000000007002", "forged");
    let path = "/api/v1/tags/E20034120000000000007002";
    let wrong = session::csrf_token("some other session");
    for token in [None, Some(wrong.as_str()), Some("")] {
        let mut request = server
            .request(Method::PUT, path, None)
            .header(COOKIE, &browser.cookie)
            .header("if-none-match", "*")
            .json(&entry);
        if let Some(token) = token {
            request = request.header(session::CSRF_HEADER, token);
        }
        let body = problem(request.send().await.unwrap(), StatusCode::FORBIDDEN).await;
        assert!(body["detail"].as_str().unwrap().contains("anti-forgery"), "{body}");
    }
    let logout = server
        .request(Method::DELETE, "/api/v1/session", None)
        .header(COOKIE, &browser.cookie)
        .send()
        .await
        .unwrap();
    problem(logout, StatusCode::FORBIDDEN).await;
    assert!(
        server
            .get(&format!("/api/v1/tags/{ADA_SWITCH}"), &server.admin)
            .await
            .status()
            .is_success()
    );

    // Bearer tokens carry no cookie credential and need no anti-forgery token.
    let caretaker = server.token(Role::Caretaker, "script").await;
    let created = server.put(path, &caretaker, &entry, Some(("if-none-match", "*"))).await;
    assert_eq!(created.status(), StatusCode::CREATED);
    // A stale cookie never blocks logging in again.
    let relogin = server
        .request(Method::POST, "/api/v1/session", None)
        .header(COOKIE, "pps_session=stale")
        .json(&json!({ "username": "anna", "password": PASSWORD }))
        .send()
        .await
        .unwrap();
    assert_eq!(relogin.status(), StatusCode::OK);
}

#[tokio::test]
async fn logout_ends_the_session_and_clears_the_cookie() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    let browser = log_in(&server, "anna", PASSWORD).await;
    let other = log_in(&server, "anna", PASSWORD).await;
    let response = browser.send(&server, Method::DELETE, "/api/v1/session", None).await;
    assert_eq!(response.status(), StatusCode::NO_CONTENT);
    let cleared = response.headers()[SET_COOKIE].to_str().unwrap();
    assert!(cleared.starts_with("pps_session=;") && cleared.contains("Max-Age=0"), "{cleared}");
    let after = browser.send(&server, Method::GET, "/api/v1/tags", None).await;
    problem(after, StatusCode::UNAUTHORIZED).await;
    assert_eq!(
        other.send(&server, Method::GET, "/api/v1/tags", None).await.status(),
        StatusCode::OK,
        "logging out on one device leaves the others"
    );
    let token = server.admin.clone();
    let with_token =
        server.request(Method::DELETE, "/api/v1/session", Some(&token)).send().await.unwrap();
    problem(with_token, StatusCode::BAD_REQUEST).await;
}

#[tokio::test]
async fn an_expired_session_no_longer_authenticates() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    let short = session::mint_secret();
    let long = session::mint_secret();
    let name = UserName::parse("anna").unwrap();
    let now = server.now();
    let five_minutes = Duration::from_secs(5 * 60);
    let (soon, later) = (now + five_minutes, now + 2 * five_minutes);
    sessions::create(&server.db, &secret::hash(&short), &name, now, soon).await.unwrap();
    sessions::create(&server.db, &secret::hash(&long), &name, now, later).await.unwrap();
    let status = |secret: &str| {
        let request = server.request(Method::GET, "/api/v1/tags", None);
        let cookie = format!("pps_session={secret}");
        async move { request.header(COOKIE, cookie).send().await.unwrap() }
    };
    assert_eq!(status(&short).await.status(), StatusCode::OK);
    server.advance(five_minutes);
    let body = problem(status(&short).await, StatusCode::UNAUTHORIZED).await;
    assert!(body["detail"].as_str().unwrap().contains("log in again"), "{body}");
    assert_eq!(status(&long).await.status(), StatusCode::OK, "the other one still lives");
}

#[tokio::test]
async fn password_changes_need_the_current_password_or_an_admin() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    add_user(&server, "bert", Role::Caretaker).await;
    add_user(&server, "root", Role::Admin).await;
    let anna = log_in(&server, "anna", PASSWORD).await;
    let anna_elsewhere = log_in(&server, "anna", PASSWORD).await;
    let path = "/api/v1/users/anna/password";

    let missing =
        anna.send(&server, Method::PUT, path, Some(json!({ "password": "new secret 1" }))).await;
    assert_eq!(
        pointers(&problem(missing, StatusCode::UNPROCESSABLE_ENTITY).await),
        ["/current_password"]
    );
    let wrong = json!({ "password": "new secret 1", "current_password": "a guess" });
    let wrong = anna.send(&server, Method::PUT, path, Some(wrong)).await;
    assert_eq!(
        pointers(&problem(wrong, StatusCode::UNPROCESSABLE_ENTITY).await),
        ["/current_password"]
    );
    let short = json!({ "password": "short", "current_password": PASSWORD });
    let short = anna.send(&server, Method::PUT, path, Some(short)).await;
    assert_eq!(pointers(&problem(short, StatusCode::UNPROCESSABLE_ENTITY).await), ["/password"]);
    let bert = json!({ "password": "new secret 1", "current_password": PASSWORD });
    let bert = anna.send(&server, Method::PUT, "/api/v1/users/bert/password", Some(bert)).await;
    problem(bert, StatusCode::FORBIDDEN).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let by_robot = server
        .request(Method::PUT, path, Some(&robot))
        .json(&json!({ "password": "new secret 1", "current_password": PASSWORD }))
        .send()
        .await
        .unwrap();
    problem(by_robot, StatusCode::FORBIDDEN).await;

    let own = json!({ "password": "new secret 1", "current_password": PASSWORD });
    assert_eq!(
        anna.send(&server, Method::PUT, path, Some(own)).await.status(),
        StatusCode::NO_CONTENT
    );
    assert_eq!(
        anna.send(&server, Method::GET, "/api/v1/tags", None).await.status(),
        StatusCode::OK
    );
    let ended = anna_elsewhere.send(&server, Method::GET, "/api/v1/tags", None).await;
    problem(ended, StatusCode::UNAUTHORIZED).await;
    problem(login_response(&server, "anna", PASSWORD).await, StatusCode::UNAUTHORIZED).await;
    log_in(&server, "anna", "new secret 1").await;

    // An admin sets anyone's password without knowing it.
    let root = log_in(&server, "root", PASSWORD).await;
    let reset = root
        .send(
            &server,
            Method::PUT,
            "/api/v1/users/bert/password",
            Some(json!({ "password": "fresh start" })),
        )
        .await;
    assert_eq!(reset.status(), StatusCode::NO_CONTENT);
    log_in(&server, "bert", "fresh start").await;
    let nobody = root
        .send(
            &server,
            Method::PUT,
            "/api/v1/users/nobody/password",
            Some(json!({ "password": "fresh start" })),
        )
        .await;
    problem(nobody, StatusCode::NOT_FOUND).await;
}

#[tokio::test]
async fn repeated_wrong_passwords_slow_login_down_but_never_tokens() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    add_user(&server, "bert", Role::Caretaker).await;
    for _ in 0..pps_server::auth::login_throttle::FREE_FAILURES {
        problem(login_response(&server, "anna", "guess").await, StatusCode::UNAUTHORIZED).await;
    }
    // Now even the right password must wait, so guessing cannot go faster.
    let slowed = login_response(&server, "anna", PASSWORD).await;
    let retry_after: u64 = slowed.headers()["retry-after"].to_str().unwrap().parse().unwrap();
    assert!((1..=60).contains(&retry_after), "{retry_after}");
    problem(slowed, StatusCode::TOO_MANY_REQUESTS).await;
    assert_eq!(login_response(&server, "bert", PASSWORD).await.status(), StatusCode::OK);
    let robot = server.token(Role::Robot, "el-e-1").await;
    for _ in 0..50 {
        let read = server.get(&format!("/api/v1/tags/{ADA_SWITCH}"), &robot).await;
        assert_eq!(read.status(), StatusCode::OK, "token calls are never rate limited");
    }
    // Not a moment before the time it gave...
    server.advance(Duration::from_secs(retry_after) - Duration::from_millis(500));
    let early = login_response(&server, "anna", PASSWORD).await;
    problem(early, StatusCode::TOO_MANY_REQUESTS).await;
    // ...and then the right password works at once.
    server.advance(Duration::from_millis(500));
    assert_eq!(login_response(&server, "anna", PASSWORD).await.status(), StatusCode::OK);
}

#[tokio::test]
async fn admins_manage_users_and_a_deleted_user_is_logged_out() {
    let server = TestServer::start().await;
    add_user(&server, "anna", Role::Caretaker).await;
    let anna = log_in(&server, "anna", PASSWORD).await;
    let admin = server.admin.clone();
    let create = |body: Value| {
        server.request(Method::POST, "/api/v1/users", Some(&admin)).json(&body).send()
    };

    let created =
        create(json!({ "name": "Night.Nurse", "role": "caretaker", "password": PASSWORD }))
            .await
            .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    assert_eq!(created.headers()["location"], "/api/v1/users/night.nurse");
    let created: Value = created.json().await.unwrap();
    assert_eq!(created["name"], "night.nurse");
    assert!(created.get("password_hash").is_none() && created.get("password").is_none());
    let again = create(json!({ "name": "night.nurse", "role": "admin", "password": PASSWORD }))
        .await
        .unwrap();
    problem(again, StatusCode::CONFLICT).await;
    let bad =
        create(json!({ "name": "no spaces", "role": "robot", "password": "short" })).await.unwrap();
    let bad = problem(bad, StatusCode::UNPROCESSABLE_ENTITY).await;
    assert_eq!(pointers(&bad), ["/name", "/role", "/password"]);

    let by_caretaker = anna
        .send(
            &server,
            Method::POST,
            "/api/v1/users",
            Some(json!({ "name": "x", "role": "admin", "password": PASSWORD })),
        )
        .await;
    problem(by_caretaker, StatusCode::FORBIDDEN).await;
    problem(anna.send(&server, Method::GET, "/api/v1/users", None).await, StatusCode::FORBIDDEN)
        .await;

    let list = server.get_json("/api/v1/users").await;
    let names: Vec<&str> =
        list["items"].as_array().unwrap().iter().map(|u| u["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["anna", "night.nurse"]);

    let delete =
        server.request(Method::DELETE, "/api/v1/users/anna", Some(&admin)).send().await.unwrap();
    assert_eq!(delete.status(), StatusCode::NO_CONTENT);
    problem(anna.send(&server, Method::GET, "/api/v1/tags", None).await, StatusCode::UNAUTHORIZED)
        .await;
    let twice =
        server.request(Method::DELETE, "/api/v1/users/anna", Some(&admin)).send().await.unwrap();
    problem(twice, StatusCode::NOT_FOUND).await;
}

#[tokio::test]
async fn passwords_and_session_secrets_are_stored_only_as_hashes() {
    let server = TestServer::start_sqlite().await;
    add_user(&server, "anna", Role::Caretaker).await;
    let response = login_response(&server, "anna", PASSWORD).await;
    let set_cookie = response.headers()[SET_COOKIE].to_str().unwrap().to_owned();
    let session_secret =
        set_cookie.split(';').next().unwrap().trim_start_matches("pps_session=").to_owned();
    let (user, hash) = users::find_with_hash(server.db.reader(), &UserName::parse("anna").unwrap())
        .await
        .unwrap()
        .unwrap();
    assert_eq!(user.role, "caretaker");
    assert!(hash.starts_with("$argon2id$"), "{hash}");
    server.db.close().await;
    let file = std::fs::read(&server.db_path).unwrap();
    let wal = std::fs::read(server.db_path.with_extension("db-wal")).unwrap_or_default();
    for bytes in [file, wal] {
        for plain in [PASSWORD, session_secret.as_str()] {
            assert!(
                !bytes.windows(plain.len()).any(|w| w == plain.as_bytes()),
                "{plain:?} is stored in plain text"
            );
        }
    }
}

#[test]
fn the_cli_adds_users_from_stdin_and_an_admin_user_counts_as_the_first_admin() {
    let bin = env!("CARGO_BIN_EXE_pps-server");
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("pps.db");
    let migrated = Command::new(bin).args(["migrate", "--db"]).arg(&db).output().unwrap();
    assert!(migrated.status.success(), "{}", String::from_utf8_lossy(&migrated.stderr));
    let add = |name: &str, role: &str, input: &str| {
        let mut child = Command::new(bin)
            .args(["user", "add", name, "--role", role, "--password-stdin", "--db"])
            .arg(&db)
            .stdin(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        child.stdin.take().unwrap().write_all(input.as_bytes()).unwrap();
        child.wait_with_output().unwrap()
    };
    let added = add("anna", "admin", &format!("{PASSWORD}\r\nignored second line\n"));
    assert!(added.status.success(), "{}", String::from_utf8_lossy(&added.stderr));
    let twice = add("anna", "caretaker", &format!("{PASSWORD}\n"));
    assert!(!twice.status.success());
    assert!(String::from_utf8_lossy(&twice.stderr).contains("already a user named anna"));
    assert!(!add("bert", "caretaker", "short\n").status.success(), "the password rules hold");

    let mut server = Command::new(bin)
        .args(["serve", "--listen", "127.0.0.1:0", "--db"])
        .arg(&db)
        .env("RUST_LOG", "info")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut printed = Vec::new();
    // The server logs that it serves only after deciding about the first admin.
    let serving = BufReader::new(server.stderr.take().unwrap())
        .lines()
        .map_while(Result::ok)
        .inspect(|line| printed.push(line.clone()))
        .any(|line| line.contains("serving the PPS-tag registry"));
    let _ = server.kill();
    let _ = server.wait();
    assert!(serving, "the server started: {printed:?}");
    assert!(
        !printed.iter().any(|line| line.trim().starts_with("pps_")),
        "an admin user exists, so no admin token is made: {printed:?}"
    );

    // The password from stdin, without its line ending, is the one that logs in.
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    let hash = runtime.block_on(async {
        let db = pps_server::Db::open_file(&db).await.unwrap();
        let found =
            users::find_with_hash(db.reader(), &UserName::parse("anna").unwrap()).await.unwrap();
        db.close().await;
        found.unwrap().1
    });
    assert!(password::verify(PASSWORD, &hash));
}
