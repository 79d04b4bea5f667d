//! What the task did, phase by phase, for a person to read.

use std::fmt;

use pps_schema::{Epc, Outcome};
use uuid::Uuid;

/// One phase: what was done, and whether the task could go on.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseReport {
    pub phase: u8,
    pub name: &'static str,
    pub lines: Vec<String>,
    pub ok: bool,
    /// What the person who asked for the task can do about what stopped this phase, in their
    /// words, when the robot knows; its lines stay the robot's own.
    pub advice: Option<String>,
}

/// The whole task.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TaskReport {
    pub phases: Vec<PhaseReport>,
    /// The tag read, once phase 3 read one.
    pub epc: Option<Epc>,
    pub action: Option<String>,
    pub behavior: Option<String>,
    /// The behaviour's own verdict; `None` when the task stopped before acting.
    pub outcome: Option<Outcome>,
    /// The person's answer.
    pub confirmed: Option<bool>,
    /// The trial written to the outbox (and uploaded, when the registry was reachable).
    pub trial: Option<Uuid>,
    /// Trials still waiting in the outbox after this one was recorded.
    pub waiting_upload: usize,
}

impl TaskReport {
    pub(crate) fn phase(&mut self, phase: u8, name: &'static str) -> &mut PhaseReport {
        self.phases.push(PhaseReport { phase, name, lines: Vec::new(), ok: true, advice: None });
        self.phases.last_mut().expect("just pushed")
    }

    /// Whether the behaviour's detector declared success.
    pub fn succeeded(&self) -> bool {
        self.outcome == Some(Outcome::Success)
    }
}

impl PhaseReport {
    pub(crate) fn note(&mut self, line: impl Into<String>) {
        self.lines.push(line.into());
    }

    pub(crate) fn fail(&mut self, line: impl Into<String>) {
        self.lines.push(line.into());
        self.ok = false;
    }

    /// [`Self::fail`], with what the person can do about it.
    pub(crate) fn fail_advising(&mut self, line: impl Into<String>, advice: impl Into<String>) {
        self.fail(line);
        self.advice = Some(advice.into());
    }

    /// What the robot could not do when this phase stopped it, in the words of the person who
    /// asked for the task: the phases' own names are the paper's.
    pub fn could_not(&self) -> &'static str {
        match self.phase {
            1 => "get near the tag",
            2 => "find the tag",
            3 => "read the tag",
            _ => "act on the tag",
        }
    }
}

impl fmt::Display for TaskReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for phase in &self.phases {
            let mark = if phase.ok { "" } else { "  [stopped]" };
            writeln!(f, "phase {}: {}{mark}", phase.phase, phase.name)?;
            for line in &phase.lines {
                writeln!(f, "  - {line}")?;
            }
            if let Some(advice) = &phase.advice {
                writeln!(f, "  what to do: {advice}")?;
            }
        }
        match (&self.outcome, &self.trial) {
            (Some(outcome), Some(trial)) => {
                let confirmed = match self.confirmed {
                    Some(true) => "yes",
                    Some(false) => "no",
                    None => "no answer",
                };
                writeln!(
                    f,
                    "result: {} (the person says it worked: {confirmed}); trial {trial}{}",
                    outcome.as_str(),
                    if self.waiting_upload > 0 {
                        format!(", {} trial(s) waiting to upload", self.waiting_upload)
                    } else {
                        ", stored in the registry".to_owned()
                    }
                )
            }
            _ => writeln!(f, "result: the task stopped before acting; no trial recorded"),
        }
    }
}
