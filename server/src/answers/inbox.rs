//! Answers about the inbox: EPCs robots read that nobody registered.

use schemars::JsonSchema;
use serde::Serialize;
use time::OffsetDateTime;

use super::{contract, stamp};
use crate::store::inbox::InboxItem;

/// An EPC that robots read and nobody registered.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "inbox_item")]
pub struct InboxAnswer {
    #[schemars(with = "contract::Epc")]
    pub epc: String,
    /// The GS1 pure-identity URI, when the EPC decodes into one.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(with = "String")]
    pub epc_uri: Option<String>,
    /// The robots that read it.
    #[schemars(with = "Vec<contract::RobotId>")]
    pub robots: Vec<String>,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub first_seen: OffsetDateTime,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub last_seen: OffsetDateTime,
    /// How many reads asked for it.
    #[schemars(range(min = 1))]
    pub count: i64,
}

impl From<InboxItem> for InboxAnswer {
    fn from(item: InboxItem) -> Self {
        Self {
            first_seen: item.first_seen,
            last_seen: item.last_seen,
            epc: item.epc,
            epc_uri: item.epc_uri,
            robots: item.robots,
            count: item.count,
        }
    }
}
