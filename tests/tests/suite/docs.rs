//! The README and `docs/` as a newcomer uses them: the quickstart and the curl tour run as
//! written, in one shell, in an empty directory, against the server the quickstart starts; every
//! command must succeed and print what the text shows. Every relative link must lead to a file.
//!
//! A block runs when it is fenced as ```` ```console tested ````. In it, `$ ` starts a command
//! (a line ending in `\` continues it); the lines up to the next command are what it prints on
//! stdout, exactly, except that a line `...` stands for any number of lines and `[..]` for any
//! text within a line. A command shown without output must print nothing.

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use pps_test_kit::workspace_bin;

const TESTED: &str = "```console tested";
/// The files whose tested blocks run, in this order, in one shell.
const RUN_IN_ORDER: [&str; 2] = ["README.md", "docs/api.md"];
/// The address the text uses; each run takes a free port instead, so runs can share a machine.
const DOCUMENTED_ADDRESS: &str = "127.0.0.1:8080";

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("tests/ is in the repository").into()
}

/// One command of a tested block and what the text says it prints.
#[derive(Debug)]
struct Step {
    place: String,
    command: String,
    expected: Vec<String>,
}

fn tested_steps(file: &str) -> Vec<Step> {
    let text = std::fs::read_to_string(repository().join(file)).expect("the doc is readable");
    let mut steps: Vec<Step> = Vec::new();
    let mut in_block = false;
    let mut continuing = false;
    for (number, line) in text.lines().enumerate() {
        if !in_block {
            in_block = line.trim_end() == TESTED;
            continue;
        }
        if line.starts_with("```") {
            in_block = false;
        } else if continuing {
            let step = steps.last_mut().expect("a command is being continued");
            step.command.push('\n');
            step.command.push_str(line);
            continuing = line.ends_with('\\');
        } else if let Some(command) = line.strip_prefix("$ ") {
            let place = format!("{file}:{}", number + 1);
            steps.push(Step { place, command: command.to_owned(), expected: Vec::new() });
            continuing = command.ends_with('\\');
        } else {
            let step = steps.last_mut().unwrap_or_else(|| {
                panic!("{file}:{}: output before any command in a tested block", number + 1)
            });
            step.expected.push(line.to_owned());
        }
    }
    assert!(!in_block, "{file}: a tested block is not closed");
    steps
}

/// Whether `line` matches `pattern`, where `[..]` matches any text.
fn line_matches(pattern: &str, line: &str) -> bool {
    let mut pieces = pattern.split("[..]");
    let first = pieces.next().unwrap_or_default();
    let Some(mut rest) = line.strip_prefix(first) else {
        return false;
    };
    let pieces: Vec<&str> = pieces.collect();
    let Some((last, middle)) = pieces.split_last() else {
        return rest.is_empty();
    };
    for piece in middle {
        match rest.find(piece) {
            Some(at) => rest = &rest[at + piece.len()..],
            None => return false,
        }
    }
    rest.len() >= last.len() && rest.ends_with(last)
}

/// Whether `actual` lines match `expected`, where a line `...` matches any number of lines.
fn lines_match(expected: &[String], actual: &[&str]) -> bool {
    match expected.split_first() {
        None => actual.is_empty(),
        Some((first, rest)) if first == "..." => {
            (0..=actual.len()).any(|skip| lines_match(rest, &actual[skip..]))
        }
        Some((first, rest)) => actual
            .split_first()
            .is_some_and(|(line, others)| line_matches(first, line) && lines_match(rest, others)),
    }
}

/// Stops everything the documented commands left running (the server they started in the
/// background), also when the test fails half-way.
#[derive(Debug)]
struct ProcessGroup(u32);

impl Drop for ProcessGroup {
    fn drop(&mut self) {
        let _ = Command::new("kill").args(["-TERM", "--", &format!("-{}", self.0)]).status();
    }
}

#[test]
fn the_quickstart_and_the_curl_tour_run_as_written() {
    let steps: Vec<Step> = RUN_IN_ORDER.iter().flat_map(|file| tested_steps(file)).collect();
    for file in RUN_IN_ORDER {
        assert!(steps.iter().any(|s| s.place.starts_with(file)), "{file} has no tested block");
    }
    let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let address = format!("127.0.0.1:{port}");

    let work = tempfile::tempdir().unwrap();
    let outputs = tempfile::tempdir().unwrap();
    let mut script = String::from("set -u\n");
    for (n, step) in steps.iter().enumerate() {
        let command = step.command.replace(DOCUMENTED_ADDRESS, &address);
        let out = outputs.path().join(format!("{n}"));
        // Braces, not a subshell: `export` and `cd` carry over to the next command.
        script.push_str(&format!(
            "{{ {command}\n}} > '{0}.out' 2> '{0}.err' < /dev/null\nstatus=$?\n\
             if [ $status -ne 0 ]; then echo $status > '{0}.failed'; exit 1; fi\n",
            out.display()
        ));
    }
    let binaries = workspace_bin("pps-server").parent().unwrap().to_owned();
    workspace_bin("pps-robot");
    let path = format!("{}:{}", binaries.display(), std::env::var("PATH").unwrap_or_default());
    let started = std::time::Instant::now();
    let shell = Command::new("bash")
        .args(["-c", &script])
        .current_dir(work.path())
        .env_clear()
        .env("PATH", path)
        .env("HOME", work.path())
        .env("PPS_LISTEN", &address)
        .env("RUST_LOG", "warn")
        .stdin(Stdio::null())
        .process_group(0)
        .spawn()
        .unwrap();
    let _group = ProcessGroup(shell.id());
    let finished = shell.wait_with_output().unwrap();
    eprintln!("the documented commands took {:.1} s", started.elapsed().as_secs_f64());

    for (n, step) in steps.iter().enumerate() {
        let read = |ext: &str| {
            std::fs::read_to_string(outputs.path().join(format!("{n}.{ext}"))).unwrap_or_default()
        };
        let (stdout, stderr) = (read("out"), read("err"));
        let failed = read("failed");
        assert!(
            failed.is_empty(),
            "{}: `{}` exited with status {}\n--- stdout\n{stdout}\n--- stderr\n{stderr}",
            step.place,
            step.command,
            failed.trim()
        );
        assert!(
            outputs.path().join(format!("{n}.out")).exists(),
            "{}: `{}` never ran",
            step.place,
            step.command
        );
        let actual: Vec<&str> = stdout.lines().map(|line| line.trim_end_matches('\r')).collect();
        assert!(
            lines_match(&step.expected, &actual),
            "{}: `{}` printed what the text does not show\n--- the text shows\n{}\n--- it \
             printed\n{stdout}\n--- stderr\n{stderr}",
            step.place,
            step.command,
            step.expected.join("\n")
        );
    }
    assert!(finished.status.success(), "the shell failed: {finished:?}");
}

/// `[text](target)` links of a Markdown file that point into the repository.
fn relative_links(text: &str) -> Vec<String> {
    let mut links = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_code = !in_code;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            let target = &after[..end];
            if !target.contains("://") && !target.starts_with('#') && !target.starts_with("mailto:")
            {
                links.push(target.split('#').next().unwrap_or_default().to_owned());
            }
            rest = &after[end..];
        }
    }
    links
}

#[test]
fn every_relative_link_in_the_docs_leads_to_a_file() {
    let root = repository();
    let mut files = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|ext| ext == "md") {
            files.push(path);
        }
    }
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for link in relative_links(&text) {
            let target = file.parent().unwrap().join(&link);
            assert!(target.exists(), "{}: the link {link} leads nowhere", file.display());
            checked += 1;
        }
    }
    assert!(checked >= 10, "only {checked} relative links were found in {files:?}");
}

#[test]
fn the_output_patterns_match_what_they_say() {
    assert!(line_matches("HTTP/1.1 201 Created", "HTTP/1.1 201 Created"));
    assert!(!line_matches("HTTP/1.1 201 Created", "HTTP/1.1 412 Precondition Failed"));
    assert!(line_matches("trial [..], stored", "trial 6f1c, stored"));
    assert!(!line_matches("trial [..], stored", "trial 6f1c, lost"));
    assert!(line_matches("{[..]\"revision\":1,[..]}", "{\"a\":2,\"revision\":1,\"z\":0}"));
    assert!(!line_matches("[..]ab[..]ab", "xab"));
    let lines = |text: &str| text.lines().map(str::to_owned).collect::<Vec<_>>();
    assert!(lines_match(&lines("HTTP/1.1 200 OK\n...\n{}"), &["HTTP/1.1 200 OK", "a: b", "{}"]));
    assert!(lines_match(&lines("...\nend"), &["end"]));
    assert!(!lines_match(&lines("...\nend"), &["end", "more"]));
    assert!(!lines_match(&[], &["unexpected output"]));
}
