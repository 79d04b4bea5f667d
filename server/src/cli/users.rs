//! `pps-server user`: logins of the web UI, with their passwords read without echo.

use anyhow::{Context, bail};

use super::UserCommand;
use crate::identity::password;
use crate::identity::{Role, UserName};
use crate::store::db::Db;
use crate::store::users;

/// A person's role: caretaker or admin; robots use tokens.
pub(super) fn user_role(text: &str) -> Result<Role, String> {
    match Role::parse(text) {
        Some(role @ (Role::Caretaker | Role::Admin)) => Ok(role),
        Some(Role::Robot) => Err("people are caretakers or admins; a robot uses a token \
             (`pps-server token create --role robot --name ROBOT-ID`)"
            .into()),
        None => Err(format!("{text:?} is not a role; one of caretaker, admin")),
    }
}

pub(super) async fn user(db: &Db, command: UserCommand) -> anyhow::Result<()> {
    let UserCommand::Add { name, role, password_stdin } = command;
    let name = UserName::parse(&name).map_err(|e| anyhow::anyhow!("{e}"))?;
    let password = if password_stdin { first_line_of_stdin()? } else { prompt_password(&name)? };
    if let Some(problem) = password::problem(&password) {
        bail!("{problem}");
    }
    let hash = password::hash(&password)?;
    match users::create(db, &name, role, &hash).await {
        Ok(user) => {
            eprintln!(
                "user {} ({}) created; they can log in at the registry's web page",
                user.name, user.role
            );
            Ok(())
        }
        Err(error) if crate::error::is_unique_violation(&error) => {
            bail!("there is already a user named {name}")
        }
        Err(error) => Err(error.into()),
    }
}

/// The password as a script pipes it in: the first line, without its line ending.
fn first_line_of_stdin() -> anyhow::Result<String> {
    let mut line = String::new();
    std::io::stdin().read_line(&mut line).context("cannot read the password from stdin")?;
    let line = line.strip_suffix('\n').unwrap_or(&line);
    Ok(line.strip_suffix('\r').unwrap_or(line).to_owned())
}

/// Asks twice on the terminal, without echo.
fn prompt_password(name: &UserName) -> anyhow::Result<String> {
    let first = rpassword::prompt_password(format!("Password for {name}: "))
        .context("cannot read a password from the terminal (use --password-stdin in scripts)")?;
    let again = rpassword::prompt_password("The same password again: ")?;
    if first != again {
        bail!("the two passwords differ; nothing was changed");
    }
    Ok(first)
}
