//! `shotdamp explore FILE`: serves the live explorer page (docs/explore.md) until stopped.

use std::net::{IpAddr, Ipv4Addr};
use std::path::PathBuf;

use clap::Args;

use super::Cli;
use crate::explore::http::Listener;
use crate::explore::Session;

/// Options of `shotdamp explore`.
#[derive(Debug, Args)]
pub struct ExploreArgs {
    /// The experiment file (a sweep, a clearance study, a waveform...: its cases, models and
    /// band).
    file: PathBuf,
    /// Port (0: any free port; the address is printed).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// Address to listen on. Only 127.0.0.1 (this machine) unless given: another address lets
    /// other machines reach the page (the token still guards it).
    #[arg(long)]
    host: Option<IpAddr>,
    /// Open the page in the desktop's browser (`$BROWSER`, else `xdg-open`).
    #[arg(long)]
    open: bool,
}

/// Opens `file`, binds, prints the address and serves until the process is stopped.
pub(super) fn run(args: &ExploreArgs, cli: &Cli) -> anyhow::Result<bool> {
    let host = args.host.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    if !host.is_loopback() {
        eprintln!(
            "warning: listening on {host}: other machines that reach this address can open the page with its token"
        );
    }
    // The address first: a port in use is said before anything is computed.
    let listener = Listener::bind(host, args.port)?;
    eprintln!("explore: reading {} (and running the experiments whose values it uses)", args.file.display());
    let session = Session::open(&args.file, &cli.reference)?;
    let server = listener.serving(session);
    let url = server.url()?;
    say!("{url}");
    eprintln!("explore: serving {} on {url} (Ctrl-C stops it)", args.file.display());
    if args.open {
        open(&url);
    }
    server.serve()?;
    Ok(true)
}

/// Starts the desktop's browser on `url`; says so when there is none.
fn open(url: &str) {
    let browser = std::env::var("BROWSER").ok().filter(|b| !b.trim().is_empty());
    let program = browser.unwrap_or_else(|| "xdg-open".to_string());
    let started = std::process::Command::new(&program)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if let Err(e) = started {
        eprintln!("explore: could not start a browser ({program}: {e}); open the address above");
    }
}
