//! An in-process registry for the robot's own tests: `el-e-1` registered, and the clients its
//! robots use.

use std::ops::{Deref, DerefMut};
use std::path::Path;

use pps_robot::registry::RegistryClient;
use pps_schema::RobotId;
use pps_server::identity::Role;
use pps_server::store::robots;
use serde_json::json;

use crate::api::ALL;
use crate::in_process::{Config, TestServer};

/// The robot the robot-side tests drive: an EL-E that can run every behaviour.
pub const EL_E: &str = "el-e-1";

/// A seeded registry with [`EL_E`] registered (at most 15 N), and its robot token.
#[derive(Debug)]
pub struct RobotRegistry {
    server: TestServer,
    pub robot_token: String,
}

impl RobotRegistry {
    pub async fn start() -> Self {
        Self::start_with(Config::default()).await
    }

    /// [`Self::start`] as `config` says (TLS, say).
    pub async fn start_with(config: Config) -> Self {
        let server = TestServer::start_with(config).await;
        let el_e = json!({ "id": EL_E, "class": "el-e", "name": "EL-E", "capabilities": ALL,
            "limits": { "max_force": 15.0 } });
        robots::put(&server.db, &RobotId::parse(EL_E).unwrap(), &el_e, "test").await.unwrap();
        let robot_token = server.token(Role::Robot, EL_E).await;
        Self { server, robot_token }
    }

    /// [`EL_E`]'s client, keeping its state under `dir`.
    pub fn client(&self, dir: &Path) -> RegistryClient {
        let robot = RobotId::parse(EL_E).unwrap();
        RegistryClient::new(&self.url, &self.robot_token, robot, &dir.join("robot-state")).unwrap()
    }

    /// Registers another robot and returns its client, keeping its state under `dir`.
    pub async fn add_robot(
        &self,
        id: &str,
        class: &str,
        capabilities: &[&str],
        dir: &Path,
    ) -> RegistryClient {
        let robot = json!({ "id": id, "class": class, "name": id, "capabilities": capabilities });
        let id = RobotId::parse(id).unwrap();
        robots::put(&self.db, &id, &robot, "test").await.unwrap();
        let token = self.token(Role::Robot, id.as_str()).await;
        RegistryClient::new(&self.url, &token, id.clone(), &dir.join(id.as_str())).unwrap()
    }
}

impl Deref for RobotRegistry {
    type Target = TestServer;

    fn deref(&self) -> &TestServer {
        &self.server
    }
}

impl DerefMut for RobotRegistry {
    fn deref_mut(&mut self) -> &mut TestServer {
        &mut self.server
    }
}
