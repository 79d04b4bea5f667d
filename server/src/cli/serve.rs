//! `pps-server serve`: start-up of the registry: transport from the flags, seeding, the
//! first admin's token, serving until a signal, draining.

use anyhow::{Context, bail};

use super::ServeArgs;
use crate::state::AppState;
use crate::store::db::{Db, Location};
use crate::store::tokens;
use crate::transport::{TlsIdentity, Transport};
use crate::trial_history::retention::Age;
use crate::{ServeOptions, home_assistant, tags::seed};

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
        write_timeout: std::time::Duration::from_secs(args.write_timeout),
        tls,
    })
}

/// The Home Assistant bridge as the flags say, its CA file read; none without `--mqtt`.
fn home_assistant(args: &ServeArgs) -> anyhow::Result<Option<home_assistant::Config>> {
    let Some(broker) = args.mqtt.clone() else {
        if args.mqtt_ca.is_some() {
            bail!("--mqtt-ca (PPS_MQTT_CA) goes with --mqtt mqtts://HOST: give the broker too");
        }
        return Ok(None);
    };
    let config = home_assistant::Config::new(
        broker,
        args.mqtt_ca.as_deref(),
        args.mqtt_prefix.clone(),
        args.mqtt_client_id.clone(),
    )?;
    Ok(Some(config))
}

/// Serves the registry at `location`. The TLS files, the bridge's CA and the port come first:
/// a server that cannot start must leave no database behind, created or seeded.
pub(super) async fn serve(location: &Location, args: ServeArgs) -> anyhow::Result<()> {
    let transport = transport(&args)?;
    let home_assistant = home_assistant(&args)?;
    let listener = tokio::net::TcpListener::bind(args.listen)
        .await
        .with_context(|| format!("cannot listen on {}", args.listen))?;
    let lock_timeout = std::time::Duration::from_secs(args.lock_timeout);
    let db = Db::open_waiting(location, lock_timeout).await?;
    let seeded = seed::seed_if_empty(&db).await?;
    if seeded > 0 {
        tracing::info!(tags = seeded, "seeded an empty registry with the paper's devices");
    }
    let address = listener.local_addr()?;
    let url = format!("{}://{address}/", transport.scheme());
    if let Some(minted) = tokens::create_first_admin(&db, time::OffsetDateTime::now_utc()).await? {
        print_first_admin_banner(&url, &minted.token);
    }
    tracing::info!(%url, "serving the PPS-tag registry");
    let options = ServeOptions {
        transport,
        thin_forces_after: args.thin_forces_after.map(|days| Age { days }),
        home_assistant,
    };
    let state = AppState::new(db.clone())
        .with_task_lease(std::time::Duration::from_secs_f64(args.task_lease))
        .with_max_tasks_per_robot(args.max_tasks_per_robot as usize)
        .with_pictures_per_tag(args.pictures_per_tag);
    let served = crate::serve_with(listener, state, options, shutdown_signal()).await;
    db.close().await;
    served?;
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
