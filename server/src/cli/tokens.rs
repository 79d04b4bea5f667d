//! `pps-server token`: minting, listing and revoking API tokens.

use std::io::Write;

use anyhow::bail;

use super::TokenCommand;
use crate::clock;
use crate::store::db::Db;
use crate::store::tokens;

/// Parses `30d`, `12h`, `90m`, `3600s` or `2w`.
pub(super) fn parse_duration(text: &str) -> Result<time::Duration, String> {
    let text = text.trim();
    let split = text.find(|c: char| !c.is_ascii_digit()).unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let number: i64 = number
        .parse()
        .map_err(|_| format!("{text:?} is not a duration; write e.g. 30d, 12h, 90m or 3600s"))?;
    let seconds = match unit {
        "s" | "" => 1,
        "m" => 60,
        "h" => 3600,
        "d" => 86_400,
        "w" => 604_800,
        other => return Err(format!("unknown unit {other:?}; use s, m, h, d or w")),
    };
    if number <= 0 {
        return Err("a lifetime must be positive".into());
    }
    number
        .checked_mul(seconds)
        .map(time::Duration::seconds)
        .ok_or_else(|| format!("{text:?} is too long"))
}

pub(super) async fn token(db: &Db, command: TokenCommand) -> anyhow::Result<()> {
    match command {
        TokenCommand::Create { role, name, expires_in } => {
            if let Some(problem) = tokens::name_problem(role, &name) {
                bail!("--name: {problem}");
            }
            let expires_at = expires_in
                .map(|lifetime| {
                    time::OffsetDateTime::now_utc().checked_add(lifetime).ok_or_else(|| {
                        anyhow::anyhow!(
                            "--expires-in reaches beyond the year 9999; give a shorter lifetime"
                        )
                    })
                })
                .transpose()?;
            let minted = tokens::create(db, role, &name, expires_at).await?;
            eprintln!("token {} for {} ({}) created", minted.record.id, name, role);
            println!("{}", minted.token);
        }
        TokenCommand::List { json } => {
            let all = tokens::list(db.reader()).await?;
            if json {
                println!("{}", serde_json::to_string_pretty(&all)?);
            } else {
                let mut out = std::io::stdout().lock();
                writeln!(
                    out,
                    "{:<13} {:<10} {:<24} {:<25} {:<25} revoked",
                    "id", "role", "name", "created", "expires"
                )?;
                for t in all {
                    writeln!(
                        out,
                        "{:<13} {:<10} {:<24} {:<25} {:<25} {}",
                        t.id,
                        t.role,
                        // Names from before control characters were refused print escaped.
                        t.name.escape_debug().to_string(),
                        clock::format(t.created_at),
                        t.expires_at.map_or_else(|| "never".into(), clock::format),
                        t.revoked_at.map_or_else(|| "-".into(), clock::format)
                    )?;
                }
            }
        }
        TokenCommand::Revoke { id } => {
            if !tokens::revoke(db, &id).await? {
                bail!("no live token has the id {id:?} (see `pps-server token list`)");
            }
            eprintln!("token {id} revoked");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("30d").unwrap(), time::Duration::days(30));
        assert_eq!(parse_duration("90m").unwrap(), time::Duration::minutes(90));
        assert!(parse_duration("0s").is_err());
        assert!(parse_duration("3 fortnights").is_err());
        assert!(parse_duration("h").is_err());
    }
}
