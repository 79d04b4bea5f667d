//! The `pps-server` command line (DESIGN §6): the tree of subcommands and their flags, and
//! which module runs each.

mod backup;
mod durations;
mod serve;
mod tags;
mod tokens;
mod trials;
mod users;

use std::net::SocketAddr;
use std::path::PathBuf;

use anyhow::bail;
use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::identity::Role;
use crate::store::db::{Db, Location};
use crate::{transport, trial_history::retention};

#[derive(Debug, Parser)]
#[command(name = "pps-server", version, about = "The PPS-tag registry for mobile robots")]
pub struct Cli {
    /// The database: a SQLite file, or postgres://USER[:PASSWORD]@HOST[:PORT]/DB for one shared
    /// by several replicas. Only `serve` and `migrate` create it; other commands refuse a
    /// missing one.
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
    /// Work with tag entries without a database.
    #[command(subcommand)]
    Tags(TagsCommand),
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
    /// Seconds (1 to 3600) a client has to send a request's headers (and to finish the TLS
    /// handshake); idle connections close after this too.
    #[arg(long, env = "PPS_HEADER_TIMEOUT", value_name = "SECONDS",
          default_value_t = transport::DEFAULT_HEADER_READ_TIMEOUT.as_secs(),
          value_parser = durations::timeout_seconds)]
    header_timeout: u64,
    /// Connections one client address may hold at once (at most --max-connections); more are
    /// closed as they come.
    #[arg(long, env = "PPS_MAX_CONNECTIONS_PER_ADDRESS", value_name = "N",
          default_value_t = transport::DEFAULT_MAX_CONNECTIONS_PER_ADDRESS,
          value_parser = clap::value_parser!(u32).range(1..))]
    max_connections_per_address: u32,
    /// Seconds (1 to 3600) a client has to send a request's body once its headers are in;
    /// then 408.
    #[arg(long, env = "PPS_BODY_TIMEOUT", value_name = "SECONDS",
          default_value_t = transport::DEFAULT_BODY_READ_TIMEOUT.as_secs(),
          value_parser = durations::timeout_seconds)]
    body_timeout: u64,
    /// Seconds (1 to 3600) a client may leave a response untaken, from the first write it
    /// refuses until it has taken all of it; then its connection closes.
    #[arg(long, env = "PPS_WRITE_TIMEOUT", value_name = "SECONDS",
          default_value_t = transport::DEFAULT_WRITE_TIMEOUT.as_secs(),
          value_parser = durations::timeout_seconds)]
    write_timeout: u64,
    /// Seconds (1 to 3600) a write waits for the database while another process (a backup, a
    /// command) holds its write lock; then it is answered 503 with Retry-After.
    #[arg(long, env = "PPS_LOCK_TIMEOUT", value_name = "SECONDS",
          default_value_t = crate::store::db::DEFAULT_LOCK_TIMEOUT.as_secs(),
          value_parser = durations::timeout_seconds)]
    lock_timeout: u64,
    /// Once a day, thin the force samples of trials received more than DAYS ago.
    #[arg(long, env = "PPS_THIN_FORCES_AFTER_DAYS", value_name = "DAYS",
          value_parser = clap::value_parser!(u32).range(..=retention::MAX_AGE_DAYS as i64))]
    thin_forces_after: Option<u32>,
    /// Seconds (0.5 to 3600) a robot's claim on a task lasts without a heartbeat; then the task goes back to
    /// the queue for another robot.
    #[arg(long, env = "PPS_TASK_LEASE", value_name = "SECONDS",
          default_value_t = crate::robots::waiting_line::DEFAULT_LEASE.as_secs_f64(),
          value_parser = durations::lease_seconds)]
    task_lease: f64,
    /// Tasks one robot may hold at once; its next claim is refused (409) until it finishes or
    /// declines one.
    #[arg(long, env = "PPS_MAX_TASKS_PER_ROBOT", value_name = "N",
          default_value_t = crate::robots::waiting_line::DEFAULT_MAX_TASKS_PER_ROBOT as u32,
          value_parser = clap::value_parser!(u32).range(1..=1000))]
    max_tasks_per_robot: u32,
    /// Trial pictures kept per tag; a new picture removes the oldest beyond this (the trials
    /// stay).
    #[arg(long, env = "PPS_PICTURES_PER_TAG", value_name = "N",
          default_value_t = crate::trials::picture::DEFAULT_PICTURES_PER_TAG,
          value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pictures_per_tag: u32,
    /// Show the tags in Home Assistant: the MQTT broker its MQTT integration uses,
    /// mqtt://[USER:PASS@]HOST[:PORT], or mqtts:// for TLS (port 8883 unless given). Off when
    /// not given.
    #[arg(long, env = "PPS_MQTT", value_name = "URL")]
    mqtt: Option<crate::home_assistant::Broker>,
    /// For an mqtts:// broker: trust only the CA certificate(s) in this PEM file, instead of
    /// the CAs this system trusts (home brokers mostly sign with a CA of their own).
    #[arg(long, env = "PPS_MQTT_CA", value_name = "PEM")]
    mqtt_ca: Option<PathBuf>,
    /// Home Assistant's MQTT discovery prefix.
    #[arg(long, env = "PPS_MQTT_PREFIX", value_name = "PREFIX",
          default_value = crate::home_assistant::DEFAULT_PREFIX,
          value_parser = crate::home_assistant::parse_prefix)]
    mqtt_prefix: String,
    /// The bridge's MQTT client id (a random one when not given).
    #[arg(long, env = "PPS_MQTT_CLIENT_ID", value_name = "ID",
          value_parser = crate::home_assistant::parse_client_id)]
    mqtt_client_id: Option<String>,
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
    /// Only trials made for this purpose: use, experiment or test.
    #[arg(long)]
    purpose: Option<String>,
    /// Write to this file instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write each trial's picture into this directory (made if missing) as
    /// `<trial id>.png` or `.jpg`, and name that file in the export (`picture_file`).
    #[arg(long, value_name = "DIR")]
    pictures: Option<PathBuf>,
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
        #[arg(long, value_parser = tokens::parse_duration)]
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
enum TagsCommand {
    /// Print a tag entry, ready to PUT, for a device kind of the paper: light switch, ada light
    /// switch, lamp, drawer or trash can.
    Template {
        /// The device kind (`light-switch` and `light_switch` spell `light switch` too).
        kind: String,
        /// The EPC of the new tag (hex or EPC tag URI); without it, the seed's own.
        #[arg(long)]
        epc: Option<String>,
        /// The name people see; without it, the seed's own.
        #[arg(long)]
        name: Option<String>,
    },
}

#[derive(Debug, Subcommand)]
enum UserCommand {
    /// Make a login for the web UI (the password is stored only as an argon2id hash).
    Add {
        /// The login name: letters a-z, digits, '.', '_' and '-'.
        name: String,
        /// caretaker or admin.
        #[arg(long, value_parser = users::user_role)]
        role: Role,
        /// Read the password from the first line of stdin instead of prompting for it.
        #[arg(long)]
        password_stdin: bool,
    },
}

impl Cli {
    pub async fn run(self) -> anyhow::Result<()> {
        let command = match self.command {
            // Serve opens (and may create) the database itself, once it holds its port.
            Command::Serve(args) => return serve::serve(&self.db, args).await,
            Command::Tags(TagsCommand::Template { kind, epc, name }) => {
                return tags::template(&kind, epc.as_deref(), name.as_deref());
            }
            command => command,
        };
        if matches!(command, Command::Backup { .. }) && self.db.file().is_none() {
            bail!("{}", crate::ops::backup::NOT_ON_POSTGRES);
        }
        let db = match command {
            Command::Migrate => Db::open(&self.db).await?,
            _ => Db::open_existing(&self.db).await?,
        };
        let result = match command {
            Command::Serve(_) | Command::Tags(_) => unreachable!("run before the database opens"),
            Command::Migrate => {
                eprintln!("database {} is migrated", self.db);
                Ok(())
            }
            Command::Seed => tags::seed(&db).await,
            Command::Export { out } => tags::export(&db, out).await,
            Command::Import { file } => tags::import(&db, file).await,
            Command::Backup { to, force } => backup::backup(&db, &to, force).await,
            Command::ExportTrials(args) => trials::export_trials(&db, args).await,
            Command::ThinForces { older_than } => trials::thin_forces(&db, older_than).await,
            Command::Token(command) => tokens::token(&db, command).await,
            Command::User(command) => users::user(&db, command).await,
        };
        db.close().await;
        result
    }
}
