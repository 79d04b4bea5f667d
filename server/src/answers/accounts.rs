//! Answers about credentials: API tokens, the caller's session, the UI's logins.

use schemars::{JsonSchema, json_schema};
use serde::Serialize;
use time::OffsetDateTime;

use pps_schema::RobotId;

use super::{contract, stamp};
use crate::identity::Role;
use crate::store::tokens::{MintedToken, TokenRecord};
use crate::store::users::UserRecord;

written_schema!(
    /// A credential's role: one of [`Role::ALL`].
    RoleName,
    "role",
    inline: false,
    json_schema!({ "enum": Role::ALL.map(Role::as_str) })
);

written_schema!(
    /// The role of a login of the UI: any but `robot`.
    UserRole,
    "user_role",
    inline: true,
    json_schema!({
        "enum": Role::ALL.into_iter().filter(|r| *r != Role::Robot).map(Role::as_str).collect::<Vec<_>>()
    })
);

/// A token as listed: everything but the secret, which is shown once at creation.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "token_record")]
pub struct TokenAnswer {
    /// The token's id, for revoking it (not its secret).
    pub id: String,
    /// Who holds it; for a robot token, the robot's id.
    pub name: String,
    #[schemars(with = "RoleName")]
    pub role: String,
    /// The robot a robot token is bound to.
    #[schemars(with = "Option<contract::RobotId>")]
    pub robot_id: Option<String>,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub created_at: OffsetDateTime,
    #[serde(with = "stamp::option")]
    #[schemars(with = "Option<stamp::DateTime>")]
    pub expires_at: Option<OffsetDateTime>,
    #[serde(with = "stamp::option")]
    #[schemars(with = "Option<stamp::DateTime>")]
    pub revoked_at: Option<OffsetDateTime>,
}

impl From<TokenRecord> for TokenAnswer {
    fn from(record: TokenRecord) -> Self {
        Self {
            created_at: record.created_at,
            expires_at: record.expires_at,
            revoked_at: record.revoked_at,
            id: record.id,
            name: record.name,
            role: record.role,
            robot_id: record.robot_id,
        }
    }
}

/// A token just minted: the record and the secret, shown only in this answer.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "minted_token")]
pub struct MintedTokenAnswer {
    #[serde(flatten)]
    pub record: TokenAnswer,
    /// The secret, shown only in this answer.
    pub token: String,
}

impl From<MintedToken> for MintedTokenAnswer {
    fn from(minted: MintedToken) -> Self {
        Self { record: minted.record.into(), token: minted.token }
    }
}

/// A token revoked.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "revoked_token")]
pub struct RevokedToken {
    pub id: String,
    #[schemars(extend("const" = true))]
    pub revoked: bool,
}

impl RevokedToken {
    pub fn new(id: String) -> Self {
        Self { id, revoked: true }
    }
}

/// Who the credential belongs to; for a browser session also its expiry and the anti-forgery
/// token unsafe requests must send in X-CSRF-Token.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "session")]
pub struct SessionAnswer {
    pub name: String,
    #[schemars(with = "RoleName")]
    pub role: String,
    #[serde(flatten)]
    pub credential: Credential,
}

/// The kind of credential, and what only that kind has.
#[derive(Debug, Serialize, JsonSchema)]
#[serde(tag = "credential", rename_all = "lowercase")]
pub enum Credential {
    /// A browser session (the cookie).
    Session {
        #[serde(with = "stamp")]
        #[schemars(with = "stamp::DateTime")]
        expires_at: OffsetDateTime,
        /// What unsafe requests made with the cookie send in X-CSRF-Token.
        csrf_token: String,
    },
    /// An API token.
    Token {
        /// The robot a robot token is bound to.
        #[schemars(with = "Option<contract::RobotId>")]
        robot: Option<RobotId>,
    },
}

/// A login of the UI, without its password hash.
#[derive(Debug, Serialize, JsonSchema)]
#[schemars(rename = "user")]
pub struct UserAnswer {
    pub name: String,
    #[schemars(with = "UserRole")]
    pub role: String,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub created_at: OffsetDateTime,
    #[serde(with = "stamp")]
    #[schemars(with = "stamp::DateTime")]
    pub password_changed_at: OffsetDateTime,
}

impl From<&UserRecord> for UserAnswer {
    fn from(record: &UserRecord) -> Self {
        Self {
            name: record.name.clone(),
            role: record.role.clone(),
            created_at: record.created_at,
            password_changed_at: record.password_changed_at,
        }
    }
}
