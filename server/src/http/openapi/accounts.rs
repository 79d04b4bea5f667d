//! The documentation of the account routes: browser sessions (`/api/v1/session`) and the UI's
//! logins (`/api/v1/users`).

use super::doc::{Body, Doc, Header, Param, ParamType, Reply};

const USER_NAME: Param = Param::path(
    "name",
    ParamType::Schema("user_name"),
    "A user name: letters a-z, digits, '.', '_' and '-', starting with a letter or digit",
)
.example("admin");

pub const LOGIN: Doc = Doc::new("login", "Log in with a password; sets the session cookie")
    .describe(
        "Wrong passwords slow further attempts for the user name and the client address (429 \
         with Retry-After). The answer carries the csrf_token that unsafe requests made with \
         the cookie must send in X-CSRF-Token.",
    )
    .body(Body::json("login", "The user name and password"))
    .replies(&[
        Reply::json(200, "Logged in", "session")
            .headers(&[Header::SetCookie, Header::CacheControl]),
        Reply::problem(401, "Wrong user name or password"),
        Reply::problem(429, "Too many wrong passwords; wait").headers(&[Header::RetryAfter]),
    ]);

pub const CURRENT_SESSION: Doc =
    Doc::new("getSession", "Who the credential belongs to (and a session's csrf_token)")
        .replies(&[Reply::json(200, "The caller", "session").headers(&[Header::CacheControl])]);

pub const LOGOUT: Doc = Doc::new("logout", "End this browser session and clear its cookie")
    .replies(&[
        Reply::empty(204, "Logged out").headers(&[Header::SetCookie, Header::CacheControl]),
        Reply::problem(400, "The request has no browser session (an API token is revoked instead)"),
    ]);

pub const USERS: Doc = Doc::new("listUsers", "List the UI's logins, without password hashes")
    .params(&[Param::LIMIT, Param::CURSOR])
    .replies(&[Reply::page("A page of users, by name", "user")]);

pub const CREATE_USER: Doc = Doc::new("createUser", "Make a login for the UI")
    .body(Body::json("new_user", "The new user: name, role (caretaker or admin) and password"))
    .replies(&[
        Reply::json(201, "Created", "user").headers(&[Header::Location]),
        Reply::problem(409, "There is already a user with this name"),
        Reply::INVALID,
    ]);

pub const DELETE_USER: Doc =
    Doc::new("deleteUser", "Remove a login and end its sessions").params(&[USER_NAME]).replies(&[
        Reply::empty(204, "Removed"),
        Reply::problem(404, "There is no user with this name"),
    ]);

pub const SET_PASSWORD: Doc = Doc::new("setPassword", "Change a password")
    .describe(
        "One's own with the current password, or anyone's as an admin. The user's other \
         sessions end; the session that made the change stays.",
    )
    .params(&[USER_NAME])
    .body(Body::json("password_change", "The new password (and the current one, unless admin)"))
    .replies(&[
        Reply::empty(204, "Changed"),
        Reply::problem(404, "There is no user with this name"),
        Reply::INVALID,
        Reply::problem(429, "Too many wrong current passwords; wait")
            .headers(&[Header::RetryAfter]),
    ]);
