//! `frep serve`: the web server (HTTP API, sessions, the studio).
//!
//! The configuration is read once: defaults, then `--config FILE` (JSON),
//! then the environment (`FREP_*`), then these flags. Logs go to standard
//! error through `tracing-subscriber`, filtered by `RUST_LOG` (default
//! `info`). Ctrl-C or SIGTERM starts a graceful shutdown: no new
//! connections, requests in flight answered, artefact jobs finished or
//! cancelled, the store closed.

use std::io::IsTerminal;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use frep_server::Config;

/// Options of `frep serve`.
#[derive(clap::Args)]
#[command(args_override_self = true)]
pub struct ServeArgs {
    /// Address to listen on (default 127.0.0.1:8080; env FREP_ADDR).
    #[arg(long)]
    addr: Option<SocketAddr>,
    /// Folder of the database and the artefact cache, created on first
    /// start (default ./frep-data; env FREP_DATA).
    #[arg(long)]
    data: Option<PathBuf>,
    /// A JSON configuration file (every key optional: addr, data_dir,
    /// open_access, static_dir, shutdown_grace_ms, limits.{…}).
    #[arg(long)]
    config: Option<PathBuf>,
    /// The built studio to serve at / (default web/dist; env
    /// FREP_STATIC_DIR).
    #[arg(long = "static")]
    static_dir: Option<PathBuf>,
    /// Writes need the model's owner (default: anyone may edit).
    #[arg(long)]
    owners_only: bool,
}

/// Runs the server until Ctrl-C or SIGTERM.
pub fn run(args: ServeArgs) -> anyhow::Result<ExitCode> {
    init_logs();
    let mut config = Config::load(args.config.as_deref()).context("configuration")?;
    if let Some(addr) = args.addr {
        config.addr = addr;
    }
    if let Some(data) = args.data {
        config.data_dir = data;
    }
    if let Some(dir) = args.static_dir {
        config.static_dir = Some(dir);
    }
    if args.owners_only {
        config.open_access = false;
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(config.addr)
            .await
            .with_context(|| format!("cannot listen on {}", config.addr))?;
        let local = listener.local_addr()?;
        tracing::info!(
            "frep serve: http://{local} (data {})",
            config.data_dir.display()
        );
        frep_server::run(listener, config, shutdown_signal())
            .await
            .context("server")
    })?;
    Ok(ExitCode::SUCCESS)
}

/// Logs to standard error, `RUST_LOG` filtering (default `info`).
fn init_logs() {
    use tracing_subscriber::EnvFilter;
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info"));
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_ansi(std::io::stderr().is_terminal())
        .with_writer(std::io::stderr)
        .try_init();
}

/// Completes on Ctrl-C or (Unix) SIGTERM.
async fn shutdown_signal() {
    let ctrl_c = async {
        if let Err(e) = tokio::signal::ctrl_c().await {
            tracing::error!("cannot wait for Ctrl-C: {e}");
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    let term = async {
        use tokio::signal::unix::{signal, SignalKind};
        match signal(SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(e) => {
                tracing::error!("cannot wait for SIGTERM: {e}");
                std::future::pending::<()>().await;
            }
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => tracing::info!("Ctrl-C: shutting down"),
        _ = term => tracing::info!("SIGTERM: shutting down"),
    }
}
