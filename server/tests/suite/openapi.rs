//! The OpenAPI document: every route of the table is an operation, the document holds together
//! (references resolve, path parameters are declared, operation ids are unique), and what the
//! registry really answers matches what the document says it answers.
//!
//! The document is also validated against the OpenAPI 3.1 meta-schema, and fuzzed against the
//! running server, by the Schemathesis step of `tests/run`.

use std::collections::{BTreeSet, HashSet};

use pps_server::RouteSpec;
use pps_server::http::Access;
use pps_server::identity::Role;
use pps_test_kit::*;
use reqwest::{Method, Response, StatusCode};
use serde_json::{Value, json};

async fn fetch_document(server: &TestServer) -> Value {
    let response = server.request(Method::GET, "/api/v1/openapi.json", None).send().await.unwrap();
    assert_eq!(response.status(), StatusCode::OK, "the document is open");
    assert_eq!(response.headers()["content-type"], "application/json");
    response.json().await.unwrap()
}

fn operation<'a>(document: &'a Value, route: &RouteSpec) -> &'a Value {
    &document["paths"][route.path][route.method.as_str().to_ascii_lowercase()]
}

fn operations(document: &Value) -> impl Iterator<Item = (&String, &String, &Value)> {
    document["paths"].as_object().unwrap().iter().flat_map(|(path, item)| {
        item.as_object().unwrap().iter().map(move |(method, op)| (path, method, op))
    })
}

fn documented_statuses(operation: &Value) -> BTreeSet<u16> {
    operation["responses"].as_object().unwrap().keys().map(|s| s.parse().unwrap()).collect()
}

#[tokio::test]
async fn every_route_of_the_table_is_an_operation_and_nothing_else_is() {
    let server = TestServer::start().await;
    let document = fetch_document(&server).await;
    assert_eq!(document["openapi"], "3.1.0");
    let routes = server.route_table();
    for route in &routes {
        let op = operation(&document, route);
        let name = format!("{} {}", route.method, route.path);
        assert!(op.is_object(), "{name} is not in the document");
        assert_eq!(op["operationId"], route.doc.operation_id, "{name}");
        assert!(op["summary"].as_str().is_some_and(|s| !s.is_empty()), "{name}");
        let open = route.access == Access::Open;
        assert_eq!(op["security"] == json!([]), open, "{name}: security");
        let roles: Vec<&str> = Role::ALL
            .into_iter()
            .filter(|role| route.access.admits(*role))
            .map(Role::as_str)
            .chain(open.then_some("anonymous"))
            .collect();
        let documented: HashSet<&str> =
            op["x-roles"].as_array().unwrap().iter().map(|r| r.as_str().unwrap()).collect();
        assert_eq!(documented, roles.into_iter().collect(), "{name}: x-roles");
        let statuses = documented_statuses(op);
        assert!(statuses.iter().any(|s| (200..300).contains(s)), "{name}: no success answer");
        if !open {
            assert!(statuses.contains(&401) && statuses.contains(&403), "{name}: {statuses:?}");
        }
    }
    assert_eq!(operations(&document).count(), routes.len(), "operations without a route");
    let ids: HashSet<&str> = routes.iter().map(|r| r.doc.operation_id).collect();
    assert_eq!(ids.len(), routes.len(), "operation ids are unique");
    println!("{} routes, {} operations", routes.len(), operations(&document).count());
}

/// Every `$ref` in `value`, with where it was found.
fn references<'a>(value: &'a Value, at: String, found: &mut Vec<(String, &'a str)>) {
    match value {
        Value::Object(object) => {
            for (key, child) in object {
                match (key.as_str(), child) {
                    ("$ref", Value::String(reference)) => found.push((at.clone(), reference)),
                    _ => references(child, format!("{at}/{key}"), found),
                }
            }
        }
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                references(item, format!("{at}/{i}"), found);
            }
        }
        _ => {}
    }
}

#[tokio::test]
async fn every_reference_resolves_and_every_path_parameter_is_declared() {
    let server = TestServer::start().await;
    let document = fetch_document(&server).await;
    let mut found = Vec::new();
    references(&document, String::new(), &mut found);
    assert!(found.len() > 50, "the contract schemas and answers are referenced");
    for (at, reference) in found {
        let pointer = reference.strip_prefix('#').unwrap_or_else(|| panic!("{at}: {reference}"));
        assert!(document.pointer(pointer).is_some(), "{at}: {reference} does not resolve");
    }

    for (path, method, op) in operations(&document) {
        let in_path: BTreeSet<&str> = path
            .split('/')
            .filter_map(|s| s.strip_prefix('{').and_then(|s| s.strip_suffix('}')))
            .collect();
        let params = op["parameters"].as_array().unwrap();
        let declared: BTreeSet<&str> = params
            .iter()
            .filter(|p| p["in"] == "path")
            .map(|p| {
                assert_eq!(p["required"], true, "{method} {path}: {p}");
                p["name"].as_str().unwrap()
            })
            .collect();
        assert_eq!(declared, in_path, "{method} {path}");
        let unique: HashSet<(&str, &str)> = params
            .iter()
            .map(|p| (p["in"].as_str().unwrap(), p["name"].as_str().unwrap()))
            .collect();
        assert_eq!(unique.len(), params.len(), "{method} {path}: a parameter declared twice");
    }
}

#[tokio::test]
async fn conditional_requests_and_the_feed_are_documented() {
    let server = TestServer::start().await;
    let document = fetch_document(&server).await;
    let op = |method: &str, path: &str| document["paths"][path][method].clone();
    let header_params = |op: &Value| -> BTreeSet<String> {
        op["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["in"] == "header")
            .map(|p| p["name"].as_str().unwrap().to_owned())
            .collect()
    };
    for (method, path) in
        [("get", "/api/v1/tags/{epc}"), ("get", "/api/v1/robots/{robot}/tags/{epc}")]
    {
        let read = op(method, path);
        assert!(header_params(&read).contains("If-None-Match"), "{path}");
        assert!(documented_statuses(&read).contains(&304), "{path}");
        assert!(read["responses"]["200"]["headers"]["ETag"].is_object(), "{path}");
    }
    let put = op("put", "/api/v1/tags/{epc}");
    assert_eq!(header_params(&put), ["If-Match", "If-None-Match"].map(String::from).into());
    assert!(documented_statuses(&put).is_superset(&[201, 412, 422, 428].into()));
    let archive = op("delete", "/api/v1/tags/{epc}");
    assert!(documented_statuses(&archive).is_superset(&[412, 428].into()));
    let feed = op("get", "/api/v1/events");
    assert!(header_params(&feed).contains("Last-Event-ID"));
    assert!(feed["responses"]["200"]["content"]["text/event-stream"].is_object());
    assert!(documented_statuses(&feed).contains(&503));

    let schemes = &document["components"]["securitySchemes"];
    assert_eq!(schemes["bearer"]["scheme"], "bearer");
    assert_eq!(schemes["session"]["in"], "cookie");
    assert_eq!(schemes["session"]["name"], pps_server::auth::session::COOKIE_NAME);
}

/// A validator of `schema`, a schema of the document, resolving references in the document.
fn validator(document: &Value, schema: &Value) -> jsonschema::Validator {
    let root = json!({ "allOf": [schema], "components": document["components"] });
    jsonschema::draft202012::options()
        .should_validate_formats(true)
        .build(&root)
        .unwrap_or_else(|e| panic!("{schema} does not compile: {e}"))
}

fn component(document: &Value, name: &str) -> jsonschema::Validator {
    validator(document, &json!({ "$ref": format!("#/components/schemas/{name}") }))
}

fn errors(validator: &jsonschema::Validator, instance: &Value) -> Vec<String> {
    validator.iter_errors(instance).map(|e| format!("{}: {e}", e.instance_path())).collect()
}

#[tokio::test]
async fn the_contract_schemas_keep_their_rules_inside_the_document() {
    let server = TestServer::start().await;
    let document = fetch_document(&server).await;
    for name in document["components"]["schemas"].as_object().unwrap().keys() {
        component(&document, name);
    }
    let tag = component(&document, "tag");
    for seed in pps_server::tags::seed::seed_entries().unwrap() {
        assert_eq!(errors(&tag, &seed), Vec::<String>::new(), "{}", seed["epc"]);
    }
    let mut unsafe_entry = new_entry("E20034120000000000004242", "too strong");
    unsafe_entry["behaviors"]["push_top"]["force_threshold"] = 500.0.into();
    unsafe_entry["colour"] = "red".into();
    assert_eq!(errors(&tag, &unsafe_entry).len(), 2, "bounds and unknown keys still hold");
}

/// Checks `response` against what the document says `method path` answers with its status.
async fn assert_documented(document: &Value, method: &str, path: &str, response: Response) {
    let status = response.status();
    let media = response.headers()["content-type"].to_str().unwrap().to_owned();
    let body: Value = response.json().await.unwrap();
    let pointer = format!(
        "/paths/{}/{method}/responses/{}/content/{}/schema",
        path.replace('~', "~0").replace('/', "~1"),
        status.as_u16(),
        media.replace('/', "~1")
    );
    let schema = document.pointer(&pointer);
    let schema = schema.unwrap_or_else(|| panic!("{method} {path}: {status} {media} undocumented"));
    let validator = validator(document, schema);
    assert_eq!(errors(&validator, &body), Vec::<String>::new(), "{method} {path}: {body}");
}

#[tokio::test]
async fn what_the_registry_answers_is_what_the_document_says() {
    let server = TestServer::start().await;
    let document = fetch_document(&server).await;
    register_robot(&server, "el-e-1", "el-e", &["light_switch", "push", "drop"], 15.0).await;
    let robot = server.token(Role::Robot, "el-e-1").await;
    let trial_id = "0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10";
    let recorded = server
        .put(
            &format!("/api/v1/trials/{trial_id}"),
            &robot,
            &trial(trial_id, ADA_SWITCH, "el-e-1", "on", "push_top", "success"),
            None,
        )
        .await;
    assert_documented(&document, "put", "/api/v1/trials/{id}", recorded).await;
    let verdict = server
        .request(Method::PATCH, &format!("/api/v1/trials/{trial_id}"), Some(&server.admin))
        .json(&json!({ "confirmed": true }))
        .send()
        .await
        .unwrap();
    assert_documented(&document, "patch", "/api/v1/trials/{id}", verdict).await;
    let unknown = server.get("/api/v1/robots/el-e-1/tags/E20034120000000000009999", &robot).await;
    assert_documented(&document, "get", "/api/v1/robots/{robot}/tags/{epc}", unknown).await;

    let reads = [
        ("/healthz", "/healthz"),
        ("/readyz", "/readyz"),
        ("/api/v1/schema/{name}", "/api/v1/schema/light_switch"),
        ("/api/v1/tags", "/api/v1/tags?limit=2"),
        ("/api/v1/tags/{epc}", &format!("/api/v1/tags/{ADA_SWITCH}")),
        ("/api/v1/tags/{epc}/revisions", &format!("/api/v1/tags/{ADA_SWITCH}/revisions")),
        ("/api/v1/tags/{epc}/stats", &format!("/api/v1/tags/{ADA_SWITCH}/stats")),
        ("/api/v1/robots", "/api/v1/robots"),
        ("/api/v1/robots/{robot}", "/api/v1/robots/el-e-1"),
        ("/api/v1/robots/{robot}/tags/{epc}", &format!("/api/v1/robots/el-e-1/tags/{ADA_SWITCH}")),
        ("/api/v1/inbox", "/api/v1/inbox"),
        ("/api/v1/trials", "/api/v1/trials"),
        ("/api/v1/trials/{id}", &format!("/api/v1/trials/{trial_id}")),
        ("/api/v1/tokens", "/api/v1/tokens"),
        ("/api/v1/session", "/api/v1/session"),
        ("/api/v1/users", "/api/v1/users"),
        ("/api/v1/tags/{epc}", "/api/v1/tags/E20034120000000000009999"),
        ("/api/v1/tags/{epc}", "/api/v1/tags/XYZ"),
    ];
    for (template, path) in reads {
        assert_documented(&document, "get", template, server.get(path, &server.admin).await).await;
    }

    let mut invalid = new_entry("E20034120000000000004242", "too strong");
    invalid["behaviors"]["push_top"]["force_threshold"] = 500.0.into();
    let rejected = server
        .request(Method::POST, "/api/v1/validate/tag", Some(&server.admin))
        .json(&invalid)
        .send()
        .await
        .unwrap();
    assert_eq!(rejected.status(), StatusCode::UNPROCESSABLE_ENTITY);
    assert_documented(&document, "post", "/api/v1/validate/tag", rejected).await;
    let minted = server
        .request(Method::POST, "/api/v1/tokens", Some(&server.admin))
        .json(&json!({ "role": "caretaker", "name": "nurse", "expires_in_days": 1 }))
        .send()
        .await
        .unwrap();
    assert_documented(&document, "post", "/api/v1/tokens", minted).await;
    let anonymous = server.request(Method::GET, "/api/v1/tags", None).send().await.unwrap();
    assert_documented(&document, "get", "/api/v1/tags", anonymous).await;
}
