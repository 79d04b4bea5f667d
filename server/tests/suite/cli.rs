//! The `pps-server` binary as an operator uses it: first start, tokens, seed, export/import,
//! shutdown on SIGTERM.

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_pps-server");

fn cli(db: &Path, args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).arg("--db").arg(db).output().unwrap()
}

/// Creates the database at `db`, as `pps-server migrate` does for an operator.
fn migrate(db: &Path) {
    let output = Command::new(BIN).arg("migrate").arg("--db").arg(db).output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
}

fn stdout(output: &std::process::Output) -> String {
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout.clone()).unwrap()
}

/// A running `pps-server serve` and what its first-start banner said.
struct Served {
    child: Child,
    url: String,
    admin: String,
}

fn serve(db: &Path) -> Served {
    let mut child = Command::new(BIN)
        .args(["serve", "--listen", "127.0.0.1:0", "--db"])
        .arg(db)
        .env("RUST_LOG", "warn")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let (mut url, mut admin) = (None, None);
    while url.is_none() || admin.is_none() {
        let line = lines.next().expect("the server printed its banner").unwrap();
        if let Some(rest) = line.trim().strip_prefix("PPS-tag registry at ") {
            url = Some(rest.trim_end_matches('/').to_owned());
        } else if line.trim().starts_with("pps_") {
            admin = Some(line.trim().to_owned());
        }
    }
    // Keep draining stderr so the server never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines {});
    Served { child, url: url.unwrap(), admin: admin.unwrap() }
}

fn blocking_get(url: &str, token: &str) -> (u16, Value) {
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    runtime.block_on(async {
        let response = reqwest::Client::new().get(url).bearer_auth(token).send().await.unwrap();
        let status = response.status().as_u16();
        (status, response.json().await.unwrap_or(Value::Null))
    })
}

#[test]
fn first_start_prints_a_working_admin_token_once_and_serves_the_seeds() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("registry.db");
    let mut served = serve(&db);
    let (status, entry) = blocking_get(
        &format!("{}/api/v1/tags/355AB1C60000002000000001", served.url),
        &served.admin,
    );
    assert_eq!(status, 200);
    assert_eq!(entry["properties"]["name"], "A D A light switch 1");

    // A token minted by the CLI while the server runs works at once.
    let caretaker =
        stdout(&cli(&db, &["token", "create", "--role", "caretaker", "--name", "nurse"]));
    let caretaker = caretaker.trim();
    assert!(
        caretaker.starts_with("pps_") && !caretaker.contains('\n'),
        "the token alone on stdout"
    );
    assert_eq!(blocking_get(&format!("{}/api/v1/tags", served.url), caretaker).0, 200);

    let listed = stdout(&cli(&db, &["token", "list", "--json"]));
    let listed: Vec<Value> = serde_json::from_str(&listed).unwrap();
    assert_eq!(listed.len(), 2);
    assert!(
        !serde_json::to_string(&listed).unwrap().contains(caretaker),
        "list never shows secrets"
    );
    let id =
        listed.iter().find(|t| t["name"] == "nurse").unwrap()["id"].as_str().unwrap().to_owned();
    stdout(&cli(&db, &["token", "revoke", &id]));
    let revoked = cli(&db, &["token", "revoke", &id]);
    assert!(!revoked.status.success(), "revoking twice says so");

    nix_terminate(&served.child);
    let status = served.child.wait().unwrap();
    assert!(status.success(), "SIGTERM shuts down cleanly: {status:?}");

    // A second start finds the admin credential and prints no new token.
    let mut again = Command::new(BIN)
        .args(["serve", "--listen", "127.0.0.1:0", "--db"])
        .arg(&db)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(again.stderr.take().unwrap()).lines();
    let first = lines.find(|l| l.as_ref().unwrap().contains("serving")).unwrap().unwrap();
    assert!(!first.contains("pps_"));
    nix_terminate(&again);
    let rest: Vec<String> = lines.map(Result::unwrap).collect();
    assert!(rest.iter().all(|l| !l.contains("pps_")), "the admin token is never printed again");
    again.wait().unwrap();
}

fn nix_terminate(child: &Child) {
    let status = Command::new("kill").arg("-TERM").arg(child.id().to_string()).status().unwrap();
    assert!(status.success());
}

#[test]
fn export_import_round_trips_and_a_bad_import_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("a.db");
    migrate(&source);
    stdout(&cli(&source, &["seed"]));
    let exported = stdout(&cli(&source, &["export"]));
    let tags: Vec<Value> = serde_json::from_str(&exported).unwrap();
    assert_eq!(tags.len(), 5);

    let target = dir.path().join("b.db");
    migrate(&target);
    let mut import = Command::new(BIN)
        .args(["import", "--db"])
        .arg(&target)
        .stdin(Stdio::piped())
        .spawn()
        .unwrap();
    import.stdin.take().unwrap().write_all(exported.as_bytes()).unwrap();
    assert!(import.wait().unwrap().success());
    let reexported: Vec<Value> = serde_json::from_str(&stdout(&cli(&target, &["export"]))).unwrap();
    let strip = |tags: &[Value]| -> Vec<Value> {
        tags.iter()
            .map(|t| {
                let mut t = t.clone();
                for field in ["updated_at", "updated_by", "revision"] {
                    t.as_object_mut().unwrap().remove(field);
                }
                t
            })
            .collect()
    };
    assert_eq!(strip(&reexported), strip(&tags));

    let mut broken = tags.clone();
    broken[3]["behaviors"] = Value::Null;
    let file = dir.path().join("broken.json");
    std::fs::write(&file, serde_json::to_string(&broken).unwrap()).unwrap();
    let fresh = dir.path().join("c.db");
    migrate(&fresh);
    let failed = cli(&fresh, &["import", file.to_str().unwrap()]);
    assert!(!failed.status.success());
    let message = String::from_utf8_lossy(&failed.stderr);
    assert!(message.contains("entry 3") && message.contains("/behaviors"), "{message}");
    assert_eq!(stdout(&cli(&fresh, &["export"])).trim(), "[]", "nothing was imported");
}

#[test]
fn token_create_checks_its_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("t.db");
    migrate(&db);
    let bad_robot = cli(&db, &["token", "create", "--role", "robot", "--name", "Not A Robot Id"]);
    assert!(!bad_robot.status.success());
    let bad_expiry =
        cli(&db, &["token", "create", "--role", "admin", "--name", "x", "--expires-in", "soon"]);
    assert!(!bad_expiry.status.success());
    let robot = stdout(&cli(
        &db,
        &["token", "create", "--role", "robot", "--name", "el-e-1", "--expires-in", "30d"],
    ));
    assert!(robot.trim().starts_with("pps_"));
    let listed: Vec<Value> =
        serde_json::from_str(&stdout(&cli(&db, &["token", "list", "--json"]))).unwrap();
    assert_eq!(listed[0]["robot_id"], "el-e-1");
    assert!(listed[0]["expires_at"].is_string());
}

/// Runs the server with every log level on, uses tokens and passwords the way robots and people
/// do, and then looks for them in the database files and in everything the server wrote.
#[test]
fn no_secret_is_stored_or_logged_in_plain_text() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("secrets.db");
    let password = "correct horse battery staple";
    migrate(&db);
    let mut add = Command::new(BIN)
        .args(["user", "add", "anna", "--role", "caretaker", "--password-stdin", "--db"])
        .arg(&db)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    writeln!(add.stdin.take().unwrap(), "{password}").unwrap();
    let added = add.wait_with_output().unwrap();
    assert!(added.status.success());
    let robot = stdout(&cli(&db, &["token", "create", "--role", "robot", "--name", "el-e-1"]))
        .trim()
        .to_owned();

    let log = dir.path().join("server.log");
    let mut child = Command::new(BIN)
        .args(["serve", "--listen", "127.0.0.1:0", "--db"])
        .arg(&db)
        .env("RUST_LOG", "trace")
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let patience = std::time::Duration::from_secs(20);
    let (url, admin) = pps_test_kit::wait_until_blocking(patience, "the banner", || {
        let text = std::fs::read_to_string(&log).unwrap();
        let url = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("PPS-tag registry at "))
            .map(|u| u.trim_end_matches('/').to_owned());
        let admin = text.lines().map(str::trim).find(|l| l.starts_with("pps_")).map(str::to_owned);
        url.zip(admin)
    });
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    runtime.block_on(async {
        let http = reqwest::Client::new();
        for token in [&admin, &robot, &format!("{robot}x")] {
            http.get(format!("{url}/api/v1/tags")).bearer_auth(token).send().await.unwrap();
        }
        for attempt in [password, "wrong password"] {
            let login = serde_json::json!({ "username": "anna", "password": attempt });
            http.post(format!("{url}/api/v1/session")).json(&login).send().await.unwrap();
        }
    });
    nix_terminate(&child);
    assert!(child.wait().unwrap().success());

    let secrets = [admin.as_str(), robot.as_str(), password, "wrong password"];
    let text = std::fs::read_to_string(&log).unwrap();
    // The first-start banner shows the admin token once, by design; nothing else may.
    let rule = "=".repeat(78);
    let mut blocks = text.split(&rule);
    let (before, _banner, after) =
        (blocks.next().unwrap(), blocks.next().unwrap(), blocks.collect::<String>());
    assert!(after.len() > 1000, "trace logging was on: {} bytes after the banner", after.len());
    for secret in secrets {
        assert!(!before.contains(secret) && !after.contains(secret), "{secret:?} is in the log");
    }
    for file in ["secrets.db", "secrets.db-wal", "secrets.db-shm"] {
        let bytes = std::fs::read(dir.path().join(file)).unwrap_or_default();
        for secret in secrets {
            assert!(
                !bytes.windows(secret.len()).any(|w| w == secret.as_bytes()),
                "{secret:?} is stored in {file}"
            );
        }
    }
}

/// Every command but `serve` and `migrate`, with the arguments it needs beyond `--db`.
const COMMANDS_ON_A_REGISTRY: &[&[&str]] = &[
    &["token", "create", "--role", "admin", "--name", "me"],
    &["token", "list"],
    &["token", "revoke", "0"],
    &["user", "add", "anna", "--role", "admin", "--password-stdin"],
    &["seed"],
    &["export"],
    &["import", "tags.json"],
    &["backup", "--to", "copy.db"],
    &["export-trials", "--format", "jsonl"],
    &["thin-forces", "--older-than", "30"],
];

/// A typo or the wrong directory must not make a fresh, empty registry that then refuses the
/// token just minted in it.
#[test]
fn commands_other_than_serve_and_migrate_refuse_a_missing_database() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tags.json"), "[]").unwrap();
    let absolute = dir.path().canonicalize().unwrap().join("pps.bd");
    for args in COMMANDS_ON_A_REGISTRY {
        let output = Command::new(BIN)
            .args(*args)
            .args(["--db", "pps.bd"])
            .current_dir(dir.path().canonicalize().unwrap())
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert!(!output.status.success(), "{args:?} succeeded");
        let said = String::from_utf8_lossy(&output.stderr);
        let expected = format!(
            "error: there is no database at {0}; create it with `pps-server migrate --db {0}`",
            absolute.display()
        );
        assert!(said.starts_with(&expected), "{args:?} said: {said}");
        assert_eq!(said.lines().count(), 1, "{args:?} said one sentence: {said}");
        assert!(!absolute.exists(), "{args:?} created the database");
    }
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["tags.json"], "no command left a file behind");

    migrate(&absolute);
    assert!(absolute.exists());
    let token = stdout(&cli(&absolute, &["token", "create", "--role", "admin", "--name", "me"]));
    assert!(token.starts_with("pps_"));
}

#[test]
fn serve_on_a_port_in_use_touches_no_database() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("pps.db");
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let address = taken.local_addr().unwrap().to_string();
    let output = Command::new(BIN)
        .args(["serve", "--listen", &address, "--db"])
        .arg(&db)
        .env("RUST_LOG", "warn")
        .output()
        .unwrap();
    assert!(!output.status.success());
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(said.contains(&format!("cannot listen on {address}")), "{said}");
    assert!(!db.exists(), "the database was created before the port was checked");
}

#[test]
fn commands_that_write_a_file_say_what_they_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("pps.db");
    migrate(&db);
    stdout(&cli(&db, &["seed"]));
    let tags = dir.path().join("tags.json");
    let output = cli(&db, &["export", "--out", tags.to_str().unwrap()]);
    assert_eq!(stdout(&output), "");
    assert_eq!(
        String::from_utf8_lossy(&output.stderr).trim(),
        format!("wrote 5 tags to {}", tags.display())
    );
    assert_eq!(
        serde_json::from_slice::<Vec<Value>>(&std::fs::read(&tags).unwrap()).unwrap().len(),
        5
    );

    let trials = dir.path().join("trials.csv");
    let output = cli(&db, &["export-trials", "--format", "csv", "--out", trials.to_str().unwrap()]);
    assert_eq!(stdout(&output), "");
    assert_eq!(
        String::from_utf8_lossy(&output.stderr).trim(),
        format!("exported 0 trials to {}", trials.display())
    );
    assert!(trials.exists());
}

#[test]
fn a_template_is_a_seed_entry_ready_to_put_under_a_new_epc() {
    let template =
        |args: &[&str]| Command::new(BIN).args(["tags", "template"]).args(args).output().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let output = template(&[
        "light-switch",
        "--epc",
        "e2003412000000000000abcd",
        "--name",
        "desk lamp switch",
    ]);
    let entry: Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(entry["epc"], "E2003412000000000000ABCD");
    assert_eq!(entry["properties"]["type"], "light switch");
    assert_eq!(entry["properties"]["name"], "desk lamp switch");
    assert_eq!(entry["actions"]["on"], "flip_up");

    let mut served = serve(&dir.path().join("pps.db"));
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    let status = runtime.block_on(async {
        reqwest::Client::new()
            .put(format!("{}/api/v1/tags/E2003412000000000000ABCD", served.url))
            .bearer_auth(&served.admin)
            .header("if-none-match", "*")
            .json(&entry)
            .send()
            .await
            .unwrap()
            .status()
    });
    assert_eq!(status, 201);
    nix_terminate(&served.child);
    assert!(served.child.wait().unwrap().success());

    let unknown = template(&["toaster"]);
    assert!(!unknown.status.success());
    let said = String::from_utf8_lossy(&unknown.stderr);
    assert_eq!(
        said.trim(),
        "error: there is no device kind \"toaster\"; the kinds are: light switch, ada light \
         switch, lamp, drawer, trash can"
    );
    let bad_epc = template(&["lamp", "--epc", "xyz"]);
    assert!(!bad_epc.status.success());
    assert!(String::from_utf8_lossy(&bad_epc.stderr).starts_with("error: --epc xyz: "));
}
