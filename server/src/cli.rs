//! The `pps-server` command line (DESIGN §6).

use std::io::{Read, Write};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::auth::{Role, UserName, password};
use crate::db::{Db, Location};
use crate::export::TrialFormat;
use crate::retention::Age;
use crate::state::AppState;
use crate::store::trials::TrialFilter;
use crate::store::{tokens, users};
use crate::transport::{self, TlsIdentity, Transport};
use crate::{ServeOptions, backup, clock, export, retention, seed};

#[derive(Debug, Parser)]
#[command(name = "pps-server", version, about = "The PPS-tag registry for mobile robots")]
pub struct Cli {
    /// The database: a SQLite file (created and migrated when missing), or
    /// postgres://USER[:PASSWORD]@HOST[:PORT]/DB for one shared by several replicas.
    #[arg(long, global = true, env = "PPS_DB", default_value = "pps.db")]
    db: Location,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Serve the registry over HTTP (seeding an empty registry first).
    Serve(ServeArgs),
    /// Create or migrate the database, then exit.
    Migrate,
    /// Load the paper's five devices again (creating missing ones, restoring changed ones).
    Seed,
    /// Print every tag as one JSON array.
    Export {
        /// Write to this file instead of stdout.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Load tags from a JSON array (as `export` prints it); all or nothing.
    Import {
        /// Read this file instead of stdin.
        file: Option<PathBuf>,
    },
    /// Copy the database consistently, also while a server is writing to it.
    Backup {
        /// The file to write the copy to.
        #[arg(long)]
        to: PathBuf,
        /// Replace the file if it exists.
        #[arg(long)]
        force: bool,
    },
    /// Print trials as JSON lines or CSV, with the filters of GET /api/v1/trials.
    ExportTrials(ExportTrialsArgs),
    /// Replace the force samples of old trials by their summary (the trials stay).
    ThinForces {
        /// Thin trials received more than this many days ago (at most a century).
        #[arg(long, value_name = "DAYS", value_parser = clap::value_parser!(u32).range(..=retention::MAX_AGE_DAYS as i64))]
        older_than: u32,
    },
    /// Manage API tokens.
    #[command(subcommand)]
    Token(TokenCommand),
    /// Manage the logins of the web UI.
    #[command(subcommand)]
    User(UserCommand),
}

#[derive(Debug, Args)]
struct ServeArgs {
    /// Address to listen on.
    #[arg(long, env = "PPS_LISTEN", default_value = "127.0.0.1:8080")]
    listen: SocketAddr,
    /// Serve HTTPS with this PEM certificate (chain); needs --tls-key.
    #[arg(long, env = "PPS_TLS_CERT", value_name = "PEM")]
    tls_cert: Option<PathBuf>,
    /// The PEM private key of --tls-cert.
    #[arg(long, env = "PPS_TLS_KEY", value_name = "PEM")]
    tls_key: Option<PathBuf>,
    /// Connections served at once; more wait until one closes.
    #[arg(long, env = "PPS_MAX_CONNECTIONS", value_name = "N", default_value_t = transport::DEFAULT_MAX_CONNECTIONS,
          value_parser = clap::value_parser!(u32).range(1..))]
    max_connections: u32,
    /// Seconds a client has to send a request's headers (and to finish the TLS handshake);
    /// idle connections close after this too.
    #[arg(long, env = "PPS_HEADER_TIMEOUT", value_name = "SECONDS",
          default_value_t = transport::DEFAULT_HEADER_READ_TIMEOUT.as_secs(),
          value_parser = clap::value_parser!(u64).range(1..))]
    header_timeout: u64,
    /// Connections one client address may hold at once (at most --max-connections).
    #[arg(long, env = "PPS_MAX_CONNECTIONS_PER_ADDRESS", value_name = "N",
          default_value_t = transport::DEFAULT_MAX_CONNECTIONS_PER_ADDRESS,
          value_parser = clap::value_parser!(u32).range(1..))]
    max_connections_per_address: u32,
    /// Seconds a client has to send a request's body once its headers are in; then 408.
    #[arg(long, env = "PPS_BODY_TIMEOUT", value_name = "SECONDS",
          default_value_t = transport::DEFAULT_BODY_READ_TIMEOUT.as_secs(),
          value_parser = clap::value_parser!(u64).range(1..))]
    body_timeout: u64,
    /// Once a day, thin the force samples of trials received more than DAYS ago.
    #[arg(long, env = "PPS_THIN_FORCES_AFTER_DAYS", value_name = "DAYS",
          value_parser = clap::value_parser!(u32).range(..=retention::MAX_AGE_DAYS as i64))]
    thin_forces_after: Option<u32>,
    /// Seconds a robot's claim on a task lasts without a heartbeat; then the task goes back to
    /// the queue for another robot.
    #[arg(long, env = "PPS_TASK_LEASE", value_name = "SECONDS",
          default_value_t = crate::task_board::DEFAULT_LEASE.as_secs_f64(),
          value_parser = parse_lease)]
    task_lease: f64,
}

/// A lease long enough for one heartbeat round trip, and at most an hour.
fn parse_lease(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(seconds) if (0.5..=3600.0).contains(&seconds) => Ok(seconds),
        _ => Err(format!("{text:?} is not a lease of 0.5 to 3600 seconds")),
    }
}

#[derive(Debug, Args)]
struct ExportTrialsArgs {
    #[arg(long, value_enum)]
    format: FormatArg,
    /// Only trials on this tag (hex EPC or EPC tag URI).
    #[arg(long)]
    epc: Option<String>,
    /// Only this robot's trials.
    #[arg(long)]
    robot: Option<String>,
    /// Only trials of this action.
    #[arg(long)]
    action: Option<String>,
    /// Only this outcome: success, failure, aborted or error.
    #[arg(long)]
    outcome: Option<String>,
    /// Only trials that started at or after this RFC 3339 time.
    #[arg(long)]
    since: Option<String>,
    /// Write to this file instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum FormatArg {
    Jsonl,
    Csv,
}

#[derive(Debug, Subcommand)]
enum TokenCommand {
    /// Mint a token and print it alone on stdout (it is shown only this once).
    Create {
        #[arg(long, value_enum)]
        role: Role,
        /// Who or what holds it; for a robot token, the robot id it is bound to.
        #[arg(long)]
        name: String,
        /// Lifetime such as 30d, 12h, 90m or 3600s; without it the token does not expire.
        #[arg(long, value_parser = parse_duration)]
        expires_in: Option<time::Duration>,
    },
    /// List tokens (never their secrets).
    List {
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Revoke a token by its id; it stops working within seconds, also on a running server.
    Revoke { id: String },
}

#[derive(Debug, Subcommand)]
enum UserCommand {
    /// Make a login for the web UI (the password is stored only as an argon2id hash).
    Add {
        /// The login name: letters a-z, digits, '.', '_' and '-'.
        name: String,
        /// caretaker or admin.
        #[arg(long, value_parser = user_role)]
        role: Role,
        /// Read the password from the first line of stdin instead of prompting for it.
        #[arg(long)]
        password_stdin: bool,
    },
}

/// A person's role: caretaker or admin; robots use tokens.
fn user_role(text: &str) -> Result<Role, String> {
    match Role::parse(text) {
        Some(role @ (Role::Caretaker | Role::Admin)) => Ok(role),
        Some(Role::Robot) => Err("people are caretakers or admins; a robot uses a token \
             (`pps-server token create --role robot --name ROBOT-ID`)"
            .into()),
        None => Err(format!("{text:?} is not a role; one of caretaker, admin")),
    }
}

/// Parses `30d`, `12h`, `90m`, `3600s` or `2w`.
fn parse_duration(text: &str) -> Result<time::Duration, String> {
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

impl Cli {
    pub async fn run(self) -> anyhow::Result<()> {
        if matches!(self.command, Command::Backup { .. }) && self.db.file().is_none() {
            bail!("{}", backup::NOT_ON_POSTGRES);
        }
        let db = Db::open(&self.db).await?;
        let result = match self.command {
            Command::Serve(args) => serve(db.clone(), args).await,
            Command::Migrate => {
                eprintln!("database {} is migrated", self.db);
                Ok(())
            }
            Command::Seed => {
                let report = seed::reload(&db).await?;
                eprintln!(
                    "seeded: {} created, {} restored, {} unchanged",
                    report.created, report.replaced, report.unchanged
                );
                Ok(())
            }
            Command::Export { out } => {
                let text = serde_json::to_string_pretty(&seed::export(&db).await?)?;
                match out {
                    Some(path) => crate::private_file::options()
                        .create(true)
                        .truncate(true)
                        .open(&path)
                        .and_then(|mut file| file.write_all((text + "\n").as_bytes()))
                        .with_context(|| format!("cannot write {}", path.display())),
                    None => {
                        println!("{text}");
                        Ok(())
                    }
                }
            }
            Command::Import { file } => import(&db, file).await,
            Command::Backup { to, force } => backup(&db, &to, force).await,
            Command::ExportTrials(args) => export_trials(&db, args).await,
            Command::ThinForces { older_than } => thin_forces(&db, older_than).await,
            Command::Token(command) => token(&db, command).await,
            Command::User(command) => user(&db, command).await,
        };
        db.close().await;
        result
    }
}

async fn import(db: &Db, file: Option<PathBuf>) -> anyhow::Result<()> {
    let text = match &file {
        Some(path) => std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?,
        None => {
            let mut text = String::new();
            std::io::stdin().read_to_string(&mut text)?;
            text
        }
    };
    let value: serde_json::Value = serde_json::from_str(&text).context("the input is not JSON")?;
    let serde_json::Value::Array(entries) = value else {
        bail!("the input must be a JSON array of tag entries, as `pps-server export` prints");
    };
    let report = seed::import(db, entries, "import").await?;
    eprintln!(
        "imported: {} created, {} replaced, {} unchanged",
        report.created, report.replaced, report.unchanged
    );
    Ok(())
}

async fn backup(db: &Db, to: &Path, force: bool) -> anyhow::Result<()> {
    let report = backup::backup(db, to, force).await?;
    eprintln!(
        "backed up {} tags and {} trials to {} ({} bytes, integrity ok)",
        report.tags,
        report.trials,
        report.path.display(),
        report.bytes
    );
    Ok(())
}

async fn thin_forces(db: &Db, days: u32) -> anyhow::Result<()> {
    let report = retention::thin_forces(db, Age { days }).await?;
    eprintln!(
        "thinned {} trials received more than {days} days ago ({} force samples replaced by \
         their summary)",
        report.trials, report.samples
    );
    Ok(())
}

async fn export_trials(db: &Db, args: ExportTrialsArgs) -> anyhow::Result<()> {
    let filter = TrialFilter::parse(
        args.epc.as_deref(),
        args.robot,
        args.action,
        args.outcome,
        args.since.as_deref(),
    )
    .map_err(anyhow::Error::msg)?;
    let format = match args.format {
        FormatArg::Jsonl => TrialFormat::Jsonl,
        FormatArg::Csv => TrialFormat::Csv,
    };
    let written = match &args.out {
        Some(path) => {
            let file = crate::private_file::options()
                .create(true)
                .truncate(true)
                .open(path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            export::export_trials(db.reader(), &filter, format, std::io::BufWriter::new(file))
                .await?
        }
        None => {
            export::export_trials(db.reader(), &filter, format, std::io::stdout().lock()).await?
        }
    };
    eprintln!("exported {written} trials");
    Ok(())
}

async fn token(db: &Db, command: TokenCommand) -> anyhow::Result<()> {
    match command {
        TokenCommand::Create { role, name, expires_in } => {
            if let Some(problem) = tokens::name_problem(role, &name) {
                bail!("--name: {problem}");
            }
            let expires_at = expires_in
                .map(|lifetime| {
                    time::OffsetDateTime::now_utc()
                        .checked_add(lifetime)
                        .map(clock::format)
                        .ok_or_else(|| {
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
                        t.created_at,
                        t.expires_at.as_deref().unwrap_or("never"),
                        t.revoked_at.as_deref().unwrap_or("-")
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

async fn user(db: &Db, command: UserCommand) -> anyhow::Result<()> {
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

/// Connection limits and TLS as the serve flags say; TLS files are checked before anything.
fn transport(args: &ServeArgs) -> anyhow::Result<Transport> {
    let tls = match (&args.tls_cert, &args.tls_key) {
        (Some(cert), Some(key)) => Some(TlsIdentity::load(cert, key)?),
        (None, None) => None,
        _ => bail!(
            "--tls-cert and --tls-key (PPS_TLS_CERT and PPS_TLS_KEY) go together: give both to \
             serve HTTPS, or neither to serve plain HTTP"
        ),
    };
    Ok(Transport {
        header_read_timeout: std::time::Duration::from_secs(args.header_timeout),
        max_connections: args.max_connections as usize,
        max_connections_per_address: args.max_connections_per_address.min(args.max_connections)
            as usize,
        body_read_timeout: std::time::Duration::from_secs(args.body_timeout),
        tls,
    })
}

async fn serve(db: Db, args: ServeArgs) -> anyhow::Result<()> {
    let transport = transport(&args)?;
    let seeded = seed::seed_if_empty(&db).await?;
    if seeded > 0 {
        tracing::info!(tags = seeded, "seeded an empty registry with the paper's devices");
    }
    let listener = tokio::net::TcpListener::bind(args.listen)
        .await
        .with_context(|| format!("cannot listen on {}", args.listen))?;
    let address = listener.local_addr()?;
    let url = format!("{}://{address}/", transport.scheme());
    if let Some(minted) = tokens::create_first_admin(&db).await? {
        print_first_admin_banner(&url, &minted.token);
    }
    tracing::info!(%url, "serving the PPS-tag registry");
    let options = ServeOptions {
        transport,
        thin_forces_after: args.thin_forces_after.map(|days| Age { days }),
    };
    let state =
        AppState::new(db).with_task_lease(std::time::Duration::from_secs_f64(args.task_lease));
    crate::serve_with(listener, state, options, shutdown_signal()).await?;
    tracing::info!("stopped");
    Ok(())
}

/// The one time the first admin token is shown: on stderr, not through the log.
fn print_first_admin_banner(url: &str, token: &str) {
    let rule = "=".repeat(78);
    eprintln!(
        "\n{rule}\n  PPS-tag registry at {url}\n\n  No admin credential existed, so one was made. It is shown only now and\n  \
         stored only as a hash; keep it safe:\n\n    {token}\n\n  Try it:  curl -H \"Authorization: Bearer {token}\" {url}api/v1/tags\n\n  \
         For the web UI, make a login:  pps-server user add NAME --role admin\n{rule}\n"
    );
}

/// Completes on SIGINT or SIGTERM.
async fn shutdown_signal() {
    let interrupt = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(_) => std::future::pending().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        () = interrupt => {}
        () = terminate => {}
    }
    tracing::info!("shutting down: finishing open requests");
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
