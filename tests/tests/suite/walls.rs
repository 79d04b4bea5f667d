//! The walls the code declares, held.
//!
//! - What runs on a real robot (the task, the behaviours, perception, navigation, the registry
//!   client, the hardware traits, the readers, the sensor file formats) never reaches into the
//!   simulator or the command line: the simulator is one more implementation of `hal`, and the
//!   command line only parses and prints. A `use` across would make robot code work only inside
//!   our own world.
//! - The paper's experiment and the simulated task worker set up simulated trials, so they use
//!   the simulator, but never the command line: the command line parses their settings and
//!   prints what they report, nothing more.
//! - The registry's store never reaches into HTTP or the command line, not even through another
//!   module: it is what both stand on (a write's precondition is a store notion; HTTP only
//!   parses the headers into it).
//! - And nothing above the store writes SQL: the connections (`db`) and the backup's
//!   `VACUUM INTO` aside, every query is a store function, so there is one place to read them.
//!
//! The walls are read from the module graph as the compiler sees it (`pps_tests::module_graph`),
//! following every module a path leads to. Unit tests inside those modules may use anything
//! (test data from the simulator's noise, say); only the code that ships is held to the walls.

use std::path::{Path, PathBuf};

use pps_tests::module_graph::{ModuleGraph, ModulePath, Named};

fn graph(src: &str) -> ModuleGraph {
    ModuleGraph::read(&workspace().join(src).join("lib.rs"))
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

fn modules(names: &[&str]) -> Vec<ModulePath> {
    names.iter().map(|n| n.split("::").map(str::to_owned).collect()).collect()
}

/// Whether `named` is `module` of this crate or something inside it.
fn inside(named: &Named, module: &str) -> bool {
    named.internal && named.path.first().is_some_and(|first| first == module)
}

/// Whether `named` is the outside crate `name` or something inside it.
fn from_crate(named: &Named, name: &str) -> bool {
    !named.internal && named.path.first().is_some_and(|first| first == name)
}

fn report(found: Vec<(pps_tests::module_graph::Chain, Named)>) -> String {
    found
        .iter()
        .map(|(chain, named)| format!("{chain} names {}", named.path.join("::")))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn robot_code_never_reaches_into_the_simulator_or_the_command_line() {
    let robot = graph("robot_client/src");
    let code = modules(&[
        "task",
        "behaviors",
        "perception",
        "navigation",
        "registry",
        "hal",
        "rfid",
        "sensor_files",
    ]);
    let found = robot.reach(&code, |n| inside(n, "sim") || inside(n, "cli"));
    assert!(found.is_empty(), "robot code crosses its wall:\n{}", report(found));
}

#[test]
fn the_experiment_never_reaches_into_the_command_line() {
    let robot = graph("robot_client/src");
    let found = robot.reach(&modules(&["experiment", "worker"]), |n| inside(n, "cli"));
    assert!(found.is_empty(), "the experiment crosses its wall:\n{}", report(found));
}

#[test]
fn the_store_never_reaches_into_http() {
    let server = graph("server/src");
    let found = server.reach(&modules(&["store"]), |n| {
        inside(n, "http") || inside(n, "cli") || from_crate(n, "axum")
    });
    assert!(found.is_empty(), "the store crosses its wall:\n{}", report(found));
}

#[test]
fn nothing_above_the_store_writes_sql() {
    let found = sql_outside_the_store(&graph("server/src"));
    assert!(found.is_empty(), "SQL outside the store:\n{}", found.join("\n"));
}

/// Every place outside `store` that names one of sqlx's ways to send SQL.
fn sql_outside_the_store(graph: &ModuleGraph) -> Vec<String> {
    const SQL: [&str; 6] =
        ["query", "query_as", "query_scalar", "query_with", "raw_sql", "QueryBuilder"];
    let mut found = Vec::new();
    for (module, shipped) in &graph.modules {
        if module.first().is_some_and(|first| first == "store") {
            continue;
        }
        for named in &shipped.named {
            let sends_sql = named.path.get(1).is_some_and(|f| SQL.contains(&f.as_str()));
            if from_crate(named, "sqlx") && sends_sql {
                let (file, line, path) =
                    (shipped.file.display(), named.line, named.path.join("::"));
                found.push(format!("{file}:{line} names {path}"));
            }
        }
    }
    found
}

/// A crate made up for the check itself: a wall it must find two modules away, and test code it
/// must not hold to the wall.
#[test]
fn the_wall_check_follows_modules_and_leaves_test_code_out() {
    let dir = tempfile::tempdir().unwrap();
    let write = |path: &str, text: &str| {
        let file = dir.path().join(path);
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(file, text).unwrap();
    };
    write("lib.rs", "pub mod store;\npub mod middle;\npub mod http;\n");
    write("store/mod.rs", "mod rows;\n#[cfg(test)]\nmod tests { use crate::http::Router; }\n");
    write(
        "store/rows.rs",
        "use crate::middle::{self, Thing};\npub fn f() -> Thing { middle::make() }\n",
    );
    write(
        "middle.rs",
        "pub struct Thing;\npub fn make() -> Thing { super::http::serve(); Thing }\n",
    );
    write(
        "http/mod.rs",
        "use sqlx::query as q;\npub fn serve() { let _ = axum::Router::new(); q(\"\"); }\n",
    );
    let graph = ModuleGraph::read(&dir.path().join("lib.rs"));
    assert!(graph.modules.contains_key(&modules(&["store::rows"])[0]));

    let found = graph.reach(&modules(&["store"]), |n| inside(n, "http"));
    let chains: Vec<String> = found.iter().map(|(chain, _)| chain.to_string()).collect();
    let rows = dir.path().join("store/rows.rs");
    let middle = dir.path().join("middle.rs");
    assert_eq!(
        chains,
        [format!("store::rows ({}:1) → middle ({}:2)", rows.display(), middle.display())],
        "one way from the store to http, through `middle`, and none from the test module"
    );
    let axum = graph.reach(&modules(&["store"]), |n| from_crate(n, "axum"));
    assert_eq!(axum.len(), 1, "axum is two modules away from the store: {}", report(axum));
    let http = dir.path().join("http/mod.rs").display().to_string();
    assert_eq!(
        sql_outside_the_store(&graph),
        [format!("{http}:1 names sqlx::query"), format!("{http}:2 names sqlx::query")],
        "SQL in http, once imported under another name and once called by it"
    );
}
