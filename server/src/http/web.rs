//! The caretakers' UI: static files from `web/`, embedded in the binary so nothing needs to be
//! installed or built to run it, plus the device templates built from the embedded seeds.
//!
//! Every file is served with `Cache-Control: no-cache` and a content-hash ETag: a browser
//! revalidates on each load and gets 304 while the binary is unchanged, so an upgraded server
//! never runs against yesterday's scripts. This module serves files; it never renders data.

use std::collections::HashMap;
use std::sync::LazyLock;

use axum::Router;
use axum::extract::Path;
use axum::http::header::{CACHE_CONTROL, CONTENT_TYPE, ETAG};
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use sha2::{Digest, Sha256};

use crate::error::ApiError;
use crate::http::precondition;
use crate::state::AppState;

/// One embedded file: `(path under /assets/, content)`; the media type follows the extension.
macro_rules! web_files {
    ($($path:literal),* $(,)?) => {
        [$(($path, include_bytes!(concat!("../../../web/", $path)) as &[u8])),*]
    };
}

const INDEX_HTML: &[u8] = include_bytes!("../../../web/index.html");

const FILES: [(&str, &[u8]); 38] = web_files![
    "app.css",
    "icon.svg",
    "js/advanced.js",
    "js/api.js",
    "js/app.js",
    "js/chart.js",
    "js/conflict.js",
    "js/dialog.js",
    "js/diff.js",
    "js/dom.js",
    "js/editor.js",
    "js/entry-form.js",
    "js/events.js",
    "js/format.js",
    "js/learned.js",
    "js/notice.js",
    "js/pages/account.js",
    "js/pages/admin.js",
    "js/pages/ask.js",
    "js/pages/login.js",
    "js/pages/register.js",
    "js/pages/robots.js",
    "js/pages/tag-engineering.js",
    "js/pages/tag-history.js",
    "js/pages/tag-rates.js",
    "js/pages/tag-robots.js",
    "js/pages/tag-trials.js",
    "js/pages/tag.js",
    "js/pages/tags.js",
    "js/pages/tasks.js",
    "js/picture.js",
    "js/pointer.js",
    "js/preference.js",
    "js/purpose.js",
    "js/schema-field.js",
    "js/schema.js",
    "js/session.js",
    "js/tasks.js",
];

/// The seed entries as starting points for a new tag, served as `templates.json`.
const TEMPLATES: &str = "templates.json";

struct Asset {
    body: Vec<u8>,
    content_type: &'static str,
    etag: String,
}

impl Asset {
    fn new(body: Vec<u8>, content_type: &'static str) -> Self {
        let digest = Sha256::digest(&body);
        let etag = format!("\"{}\"", hex::encode(&digest[..12]));
        Self { body, content_type, etag }
    }

    fn respond(&'static self, headers: &HeaderMap) -> Response {
        let cache = [(CACHE_CONTROL, "no-cache"), (ETAG, self.etag.as_str())];
        match precondition::not_modified(headers, &self.etag) {
            Ok(true) => return (StatusCode::NOT_MODIFIED, cache).into_response(),
            Ok(false) => {}
            Err(error) => return error.into_response(),
        }
        (cache, [(CONTENT_TYPE, self.content_type)], self.body.as_slice()).into_response()
    }
}

static INDEX: LazyLock<Asset> =
    LazyLock::new(|| Asset::new(INDEX_HTML.to_vec(), "text/html; charset=utf-8"));

static ASSETS: LazyLock<HashMap<&'static str, Asset>> = LazyLock::new(|| {
    let mut assets: HashMap<&'static str, Asset> = FILES
        .iter()
        .map(|(path, body)| (*path, Asset::new(body.to_vec(), content_type(path))))
        .collect();
    assets.insert(TEMPLATES, Asset::new(templates(), "application/json"));
    assets
});

/// The seed entries without their EPC and name, which a new tag must bring.
fn templates() -> Vec<u8> {
    let mut entries = crate::tags::seed::seed_entries().expect("the embedded seeds are JSON");
    for entry in &mut entries {
        if let Some(object) = entry.as_object_mut() {
            object.remove("epc");
        }
        if let Some(properties) = entry.get_mut("properties").and_then(|p| p.as_object_mut()) {
            properties.insert("name".into(), "".into());
        }
    }
    serde_json::to_vec(&entries).expect("JSON values serialise")
}

fn content_type(path: &str) -> &'static str {
    match path.rsplit_once('.').map(|(_, extension)| extension) {
        Some("js") => "text/javascript; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("svg") => "image/svg+xml",
        Some("json") => "application/json",
        _ => "application/octet-stream",
    }
}

pub fn router() -> Router<AppState> {
    Router::new().route("/", get(index)).route("/assets/{*path}", get(asset))
}

async fn index(headers: HeaderMap) -> Response {
    INDEX.respond(&headers)
}

async fn asset(Path(path): Path<String>, headers: HeaderMap) -> Response {
    match ASSETS.get(path.as_str()) {
        Some(asset) => asset.respond(&headers),
        None => ApiError::NotFound(format!("the UI has no file {path:?}")).into_response(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_in_web_is_embedded() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../web");
        let mut on_disk = Vec::new();
        let mut dirs = vec![root.clone()];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    dirs.push(path);
                } else {
                    on_disk.push(path.strip_prefix(&root).unwrap().to_string_lossy().into_owned());
                }
            }
        }
        on_disk.retain(|path| path != "index.html");
        on_disk.sort();
        let mut embedded: Vec<String> = FILES.iter().map(|(path, _)| (*path).to_owned()).collect();
        embedded.sort();
        assert_eq!(on_disk, embedded, "web/ and the embedded files differ");
    }

    #[test]
    fn every_file_has_a_media_type_and_templates_lack_keys() {
        for (path, _) in FILES {
            assert_ne!(content_type(path), "application/octet-stream", "{path}");
        }
        let templates: serde_json::Value = serde_json::from_slice(&templates()).unwrap();
        assert_eq!(templates.as_array().unwrap().len(), 5);
        assert!(templates[0].get("epc").is_none());
        assert_eq!(templates[0]["properties"]["name"], "");
    }
}
