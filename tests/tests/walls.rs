//! The walls the code declares, held.
//!
//! - What runs on a real robot (the task, the behaviours, perception, navigation, the registry
//!   client, the hardware traits, the readers, the recording formats) never reaches into the
//!   simulator or the command line: the simulator is one more implementation of `hal`, and the
//!   command line only parses and prints. A `use` across would make robot code work only inside
//!   our own world.
//! - The paper's experiment and the simulated task worker set up simulated trials, so they use
//!   the simulator, but never the command line: the command line parses their settings and
//!   prints what they report, nothing more.
//! - The registry's store never reaches into HTTP or the command line: it is what both stand on
//!   (a write's precondition is a store notion; HTTP only parses the headers into it).
//! - And nothing above the store writes SQL: the connections (`db`) and the backup's
//!   `VACUUM INTO` aside, every query is a store function, so there is one place to read them.
//!
//! Unit tests inside those modules may use anything (test data from the simulator's noise, say);
//! only the code that ships is held to the walls.

use std::path::{Path, PathBuf};

/// Modules of a crate that must not use some others.
struct Wall {
    what: &'static str,
    /// The crate's `src`, from the workspace root.
    src: &'static str,
    /// Directories or files under `src` the wall holds.
    modules: &'static [&'static str],
    /// Directories or files among them it does not.
    except: &'static [&'static str],
    beyond: &'static [&'static str],
}

const WALLS: [Wall; 4] = [
    Wall {
        what: "robot code",
        src: "robot_client/src",
        modules: &[
            "task",
            "behaviors",
            "perception",
            "navigation",
            "registry",
            "hal",
            "rfid",
            "recording",
        ],
        except: &[],
        beyond: &["crate::sim", "crate::cli", "super::sim", "super::cli"],
    },
    Wall {
        what: "the experiment",
        src: "robot_client/src",
        modules: &["experiment", "worker.rs"],
        except: &[],
        beyond: &["crate::cli", "super::cli"],
    },
    Wall {
        what: "the store",
        src: "server/src",
        modules: &["store"],
        except: &[],
        beyond: &["crate::http", "crate::cli", "super::http", "axum"],
    },
    Wall {
        what: "the server above its store",
        src: "server/src",
        modules: &["."],
        except: &["store", "db", "backup.rs"],
        beyond: &[
            "sqlx::query",
            "sqlx::query_as",
            "sqlx::query_scalar",
            "sqlx::query_with",
            "sqlx::raw_sql",
            "sqlx::QueryBuilder",
        ],
    },
];

fn rust_files(dir: &Path, into: &mut Vec<PathBuf>) {
    if dir.is_file() {
        into.push(dir.to_path_buf());
        return;
    }
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, into);
        } else if path.extension().is_some_and(|e| e == "rs") {
            into.push(path);
        }
    }
}

/// The lines of a source file that are not test code, numbered from 1, and the names of the
/// modules it declares test-only (`#[cfg(test)] mod name;`, whose files are test code too).
fn shipped_code(text: &str) -> (Vec<(usize, &str)>, Vec<String>) {
    let (mut kept, mut test_modules) = (Vec::new(), Vec::new());
    let mut lines = text.lines().enumerate();
    while let Some((n, line)) = lines.next() {
        if line.trim() != "#[cfg(test)]" {
            kept.push((n + 1, line));
            continue;
        }
        // The item the attribute applies to: a module declared here or inline, or one line.
        let Some((_, item)) = lines.next() else { break };
        let item = item.trim();
        if let Some(name) = item.strip_prefix("mod ").and_then(|rest| rest.strip_suffix(';')) {
            test_modules.push(name.to_owned());
        } else if item.ends_with('{') {
            let mut depth = 1i32;
            for (_, body) in lines.by_ref() {
                depth += body.matches('{').count() as i32 - body.matches('}').count() as i32;
                if depth <= 0 {
                    break;
                }
            }
        }
    }
    (kept, test_modules)
}

/// Whether `line` names the module `path` itself (`crate::sim`, not `crate::simple`).
fn names(line: &str, path: &str) -> bool {
    line.match_indices(path).any(|(at, _)| {
        !line[at + path.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
    })
}

/// The lines of `wall`'s modules that cross it, each as `path:line uses what: code`.
fn breaches(wall: &Wall) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let src = root.join(wall.src);
    let mut files = Vec::new();
    for module in wall.modules {
        rust_files(&src.join(module), &mut files);
    }
    // `src/./x.rs` as `src/x.rs`, so that paths compare and read as written.
    let mut files: Vec<PathBuf> = files.iter().map(|f| f.components().collect()).collect();
    let excepted: Vec<PathBuf> = wall.except.iter().map(|e| src.join(e)).collect();
    files.retain(|f| !excepted.iter().any(|e| f.starts_with(e)));
    assert!(!files.is_empty(), "no sources of {} under {}", wall.what, src.display());
    files.sort();
    let sources: Vec<(&PathBuf, String)> =
        files.iter().map(|f| (f, std::fs::read_to_string(f).unwrap())).collect();
    // Files of test-only modules, wherever in the tree they are declared.
    let test_only: Vec<PathBuf> = sources
        .iter()
        .flat_map(|(file, text)| {
            let dir = file.parent().unwrap().to_path_buf();
            shipped_code(text).1.into_iter().map(move |m| dir.join(format!("{m}.rs")))
        })
        .collect();
    let mut found = Vec::new();
    for (file, text) in sources.iter().filter(|(f, _)| !test_only.contains(f)) {
        for (n, line) in shipped_code(text).0 {
            if let Some(path) = wall.beyond.iter().find(|p| names(line, p)) {
                let shown = file.strip_prefix(root).unwrap().display();
                found.push(format!("{shown}:{n} uses {path}: {}", line.trim()));
            }
        }
    }
    found
}

#[test]
fn robot_code_never_reaches_into_the_simulator_or_the_command_line() {
    let found = breaches(&WALLS[0]);
    assert!(found.is_empty(), "robot code crosses its wall:\n{}", found.join("\n"));
}

#[test]
fn the_experiment_never_reaches_into_the_command_line() {
    let found = breaches(&WALLS[1]);
    assert!(found.is_empty(), "the experiment crosses its wall:\n{}", found.join("\n"));
}

#[test]
fn the_store_never_reaches_into_http() {
    let found = breaches(&WALLS[2]);
    assert!(found.is_empty(), "the store crosses its wall:\n{}", found.join("\n"));
}

#[test]
fn nothing_above_the_store_writes_sql() {
    let found = breaches(&WALLS[3]);
    assert!(found.is_empty(), "SQL outside the store:\n{}", found.join("\n"));
}

#[test]
fn the_wall_check_sees_through_test_modules_but_not_around_code() {
    let text = "use crate::hal::Clock;\n\
                use crate::sim::SimRobot;\n\
                #[cfg(test)]\n\
                mod helpers;\n\
                #[cfg(test)]\n\
                mod tests {\n\
                    use crate::sim::gaussian;\n\
                    fn f() { if true { } }\n\
                }\n\
                fn after() {}\n";
    let (code, test_modules) = shipped_code(text);
    let lines: Vec<&str> = code.iter().map(|(_, l)| *l).collect();
    assert_eq!(lines, ["use crate::hal::Clock;", "use crate::sim::SimRobot;", "fn after() {}"]);
    assert_eq!(code[1].0, 2);
    assert_eq!(test_modules, ["helpers"]);
    assert!(names("use crate::sim::{Room};", "crate::sim"));
    assert!(names("crate::sim", "crate::sim"));
    assert!(!names("use super::client::Thing;", "super::cli"));
}
