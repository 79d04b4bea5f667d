//! The flags by which `pps-robot run` and `pps-trials` reach the registry as one robot.

use std::path::PathBuf;

use clap::Args;
use pps_schema::RobotId;

use crate::registry::RegistryClient;

#[derive(Debug, Args)]
pub struct RegistryArgs {
    /// The registry's base URL, e.g. http://127.0.0.1:8080.
    #[arg(long)]
    pub server: String,
    /// The robot's API token.
    #[arg(long, env = "PPS_TOKEN", hide_env_values = true)]
    pub token: String,
    /// A CA certificate (PEM) to trust for an HTTPS registry with its own certificate.
    #[arg(long, env = "PPS_CA_CERT")]
    pub ca_cert: Option<PathBuf>,
    /// The robot's id in the registry, e.g. el-e-1.
    #[arg(long)]
    pub robot: String,
    /// Where the robot keeps its entry cache and trial outbox; default `pps-robot/<ROBOT>` in
    /// the system's temporary directory.
    #[arg(long)]
    pub state: Option<PathBuf>,
}

impl RegistryArgs {
    /// The state directory: `--state`, or one per robot in the system's temporary directory.
    pub fn state_dir(&self) -> PathBuf {
        self.state
            .clone()
            .unwrap_or_else(|| std::env::temp_dir().join("pps-robot").join(&self.robot))
    }

    /// The registry client for this robot, trusting `--ca-cert` when one is given.
    pub fn connect(&self) -> anyhow::Result<RegistryClient> {
        let robot = RobotId::parse(&self.robot).map_err(|e| anyhow::anyhow!("--robot: {e}"))?;
        let client = RegistryClient::new(&self.server, &self.token, robot, &self.state_dir())?;
        Ok(match &self.ca_cert {
            Some(path) => {
                let pem = std::fs::read(path).map_err(|e| {
                    anyhow::anyhow!("cannot read --ca-cert {}: {e}", path.display())
                })?;
                client.with_ca_certificate(&pem)?
            }
            None => client,
        })
    }
}
