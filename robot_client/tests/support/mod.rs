//! An in-process registry for the robot's end-to-end tests: seeded, with the robots
//! registered, on 127.0.0.1 and a fresh database file.

#![allow(dead_code)]

use std::net::SocketAddr;
use std::path::Path;

use pps_robot::registry::RegistryClient;
use pps_schema::RobotId;
use pps_server::identity::Role;
use pps_server::store::{robots, tokens};
use pps_server::{AppState, Db};
use serde_json::json;
use tokio::sync::oneshot;

pub struct Registry {
    pub address: SocketAddr,
    db_path: std::path::PathBuf,
    pub admin: String,
    pub robot_token: String,
    stop: Option<(oneshot::Sender<()>, tokio::task::JoinHandle<std::io::Result<()>>)>,
}

impl Registry {
    /// A seeded registry with `el-e-1` (class `el-e`) registered, running.
    pub async fn start(dir: &Path) -> Self {
        let db_path = dir.join("registry.db");
        let db = Db::open_file(&db_path).await.unwrap();
        pps_server::tags::seed::seed_if_empty(&db).await.unwrap();
        let robot = json!({ "id": "el-e-1", "class": "el-e", "name": "EL-E", "capabilities": ["light_switch", "pull_back", "push", "pull_lamp", "drop"], "limits": { "max_force": 15.0 } });
        robots::put(&db, &pps_schema::RobotId::parse("el-e-1").unwrap(), &robot, "test")
            .await
            .unwrap();
        let admin = tokens::create(&db, Role::Admin, "admin", None).await.unwrap().token;
        let robot_token = tokens::create(&db, Role::Robot, "el-e-1", None).await.unwrap().token;
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let address = listener.local_addr().unwrap();
        let mut registry = Self { address, db_path, admin, robot_token, stop: None };
        registry.serve(listener, db);
        registry
    }

    fn serve(&mut self, listener: tokio::net::TcpListener, db: Db) {
        let (stop, stopped) = oneshot::channel::<()>();
        let task = tokio::spawn(pps_server::serve(listener, AppState::new(db), async move {
            let _ = stopped.await;
        }));
        self.stop = Some((stop, task));
    }

    /// Starts the stopped registry again, on the same address and database.
    pub async fn restart(&mut self) {
        let db = Db::open_file(&self.db_path).await.unwrap();
        let listener = tokio::net::TcpListener::bind(self.address).await.unwrap();
        self.serve(listener, db);
    }

    pub fn db_path(&self) -> &Path {
        &self.db_path
    }

    pub fn url(&self) -> String {
        format!("http://{}", self.address)
    }

    /// Registers another robot and returns its client, keeping its state under `dir`.
    pub async fn add_robot(
        &self,
        id: &str,
        class: &str,
        capabilities: &[&str],
        dir: &Path,
    ) -> RegistryClient {
        let db = Db::open_file(&self.db_path).await.unwrap();
        let robot = json!({ "id": id, "class": class, "name": id, "capabilities": capabilities });
        robots::put(&db, &pps_schema::RobotId::parse(id).unwrap(), &robot, "test").await.unwrap();
        let token = tokens::create(&db, Role::Robot, id, None).await.unwrap().token;
        RegistryClient::new(&self.url(), &token, RobotId::parse(id).unwrap(), &dir.join(id))
            .unwrap()
    }

    /// The robot's client, keeping its state under `dir`.
    pub fn client(&self, dir: &Path) -> RegistryClient {
        RegistryClient::new(
            &self.url(),
            &self.robot_token,
            RobotId::parse("el-e-1").unwrap(),
            &dir.join("robot-state"),
        )
        .unwrap()
    }

    /// Every trial the registry holds, as JSON.
    pub async fn trials(&self) -> Vec<serde_json::Value> {
        let page: serde_json::Value = reqwest::Client::new()
            .get(format!("{}/api/v1/trials?include=forces&limit=500", self.url()))
            .bearer_auth(&self.admin)
            .send()
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
        page["items"].as_array().unwrap().clone()
    }

    /// A tag's success statistics, as the tag page asks for them (`include`: `experiment,test`).
    pub async fn stats(&self, epc: &str, include: Option<&str>) -> serde_json::Value {
        let include = include.map(|purposes| format!("?include={purposes}")).unwrap_or_default();
        let response = reqwest::Client::new()
            .get(format!("{}/api/v1/tags/{epc}/stats{include}", self.url()))
            .bearer_auth(&self.admin)
            .send()
            .await
            .unwrap();
        assert_eq!(response.status(), 200);
        response.json().await.unwrap()
    }

    /// The picture at `path` (a trial's `picture`), read as a caretaker's browser would.
    pub async fn picture(&self, path: &str) -> Vec<u8> {
        let response = reqwest::Client::new()
            .get(format!("{}{path}", self.url()))
            .bearer_auth(&self.admin)
            .send()
            .await
            .unwrap();
        assert_eq!(response.status(), reqwest::StatusCode::OK, "GET {path}");
        assert_eq!(response.headers()["content-type"], "image/png");
        response.bytes().await.unwrap().to_vec()
    }

    /// Changes a tag's entry as a caretaker would: read it, edit it, save it over that revision.
    pub async fn edit_tag(&self, epc: &str, edit: impl FnOnce(&mut serde_json::Value)) {
        let http = reqwest::Client::new();
        let url = format!("{}/api/v1/tags/{epc}", self.url());
        let response = http.get(&url).bearer_auth(&self.admin).send().await.unwrap();
        let etag = response.headers()["etag"].to_str().unwrap().to_owned();
        let mut entry: serde_json::Value = response.json().await.unwrap();
        edit(&mut entry);
        let saved = http
            .put(&url)
            .bearer_auth(&self.admin)
            .header("if-match", etag)
            .json(&entry)
            .send()
            .await
            .unwrap();
        assert_eq!(saved.status(), 200, "{}", saved.text().await.unwrap());
    }

    /// Archives a tag as a caretaker would.
    pub async fn archive_tag(&self, epc: &str) {
        let http = reqwest::Client::new();
        let url = format!("{}/api/v1/tags/{epc}", self.url());
        let response = http.get(&url).bearer_auth(&self.admin).send().await.unwrap();
        let etag = response.headers()["etag"].to_str().unwrap().to_owned();
        let archived =
            http.delete(&url).bearer_auth(&self.admin).header("if-match", etag).send().await;
        assert_eq!(archived.unwrap().status(), 200);
    }

    pub async fn stop(&mut self) {
        if let Some((stop, task)) = self.stop.take() {
            let _ = stop.send(());
            task.await.unwrap().unwrap();
        }
    }
}
