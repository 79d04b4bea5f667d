//! Which trials a list or an export wants: `GET /api/v1/trials` and `pps-server export-trials`
//! take the same six filters, spelled as text, and both turn them into one [`TrialFilter`] here,
//! so a filter means the same thing (and a bad one is refused in the same words) on either side.

use pps_schema::{Epc, Outcome, Purpose, RobotId};
use time::OffsetDateTime;

/// Which trials a list wants; every filter given must hold.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct TrialFilter {
    pub epc: Option<Epc>,
    pub robot: Option<RobotId>,
    pub action: Option<String>,
    pub outcome: Option<Outcome>,
    /// Trials that started at or after this time.
    pub since: Option<OffsetDateTime>,
    pub purpose: Option<Purpose>,
}

/// The filters as a person spells them, in a query string or on the command line.
#[derive(Debug, Default, Clone, Copy)]
pub struct FilterText<'a> {
    /// Hex or any EPC URI form.
    pub epc: Option<&'a str>,
    pub robot: Option<&'a str>,
    pub action: Option<&'a str>,
    /// success, failure, aborted or error.
    pub outcome: Option<&'a str>,
    /// RFC 3339.
    pub since: Option<&'a str>,
    /// use, experiment or test.
    pub purpose: Option<&'a str>,
}

/// A filter that does not parse, and what it should have been.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FilterError {
    #[error("{raw:?} is not an EPC: {reason}")]
    Epc { raw: String, reason: String },
    #[error("{raw:?} is not a robot id: {reason}")]
    Robot { raw: String, reason: String },
    #[error("outcome is one of success, failure, aborted, error; not {0:?}")]
    Outcome(String),
    #[error("since must be an RFC 3339 time such as 2026-11-22T09:00:00Z, not {0:?}")]
    Since(String),
    #[error("purpose is one of use, experiment, test; not {0:?}")]
    Purpose(String),
}

impl TrialFilter {
    /// Parses every filter given; the first that does not parse is the error.
    pub fn parse(text: FilterText<'_>) -> Result<Self, FilterError> {
        let epc = text
            .epc
            .map(|raw| {
                Epc::parse(raw).map_err(|error| FilterError::Epc {
                    raw: raw.into(),
                    reason: error.to_string(),
                })
            })
            .transpose()?;
        let robot = text
            .robot
            .map(|raw| {
                RobotId::parse(raw).map_err(|error| FilterError::Robot {
                    raw: raw.into(),
                    reason: error.to_string(),
                })
            })
            .transpose()?;
        let outcome = text
            .outcome
            .map(|raw| {
                Outcome::ALL
                    .into_iter()
                    .find(|outcome| outcome.as_str() == raw)
                    .ok_or_else(|| FilterError::Outcome(raw.into()))
            })
            .transpose()?;
        let since = text
            .since
            .map(|raw| crate::clock::parse(raw).ok_or_else(|| FilterError::Since(raw.into())))
            .transpose()?;
        let purpose = text
            .purpose
            .map(|raw| Purpose::parse(raw).ok_or_else(|| FilterError::Purpose(raw.into())))
            .transpose()?;
        Ok(Self { epc, robot, action: text.action.map(str::to_owned), outcome, since, purpose })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_filter_parses_into_its_type() {
        let filter = TrialFilter::parse(FilterText {
            epc: Some("urn:epc:tag:sgtin-96:3.0614141.812345.6789"),
            robot: Some("el-e-1"),
            action: Some("push"),
            outcome: Some("failure"),
            since: Some("2026-11-22T10:00:00+01:00"),
            purpose: Some("experiment"),
        })
        .unwrap();
        assert_eq!(
            filter.epc,
            Some(Epc::parse("urn:epc:tag:sgtin-96:3.0614141.812345.6789").unwrap())
        );
        assert_eq!(filter.robot.as_ref().map(RobotId::as_str), Some("el-e-1"));
        assert_eq!(filter.outcome, Some(Outcome::Failure));
        assert_eq!(
            filter.since.map(crate::clock::format).as_deref(),
            Some("2026-11-22T09:00:00.000Z")
        );
        assert_eq!(filter.purpose, Some(Purpose::Experiment));
        assert_eq!(TrialFilter::parse(FilterText::default()).unwrap(), TrialFilter::default());
    }

    #[test]
    fn a_bad_filter_says_which_and_why() {
        let bad = |text: FilterText<'_>| TrialFilter::parse(text).unwrap_err().to_string();
        assert!(bad(FilterText { epc: Some("zz"), ..Default::default() }).contains("not an EPC"));
        assert!(
            bad(FilterText { robot: Some("Robot 1"), ..Default::default() })
                .starts_with("\"Robot 1\" is not a robot id")
        );
        assert!(bad(FilterText { outcome: Some("won"), ..Default::default() }).contains("\"won\""));
        assert!(
            bad(FilterText { since: Some("today"), ..Default::default() }).contains("RFC 3339")
        );
        assert_eq!(
            bad(FilterText { purpose: Some("demo"), ..Default::default() }),
            "purpose is one of use, experiment, test; not \"demo\""
        );
    }
}
