//! The tag routes of DESIGN §4 through real HTTP: reads, conditional writes, history, errors.

use pps_test_kit::*;
use reqwest::{Method, StatusCode};
use serde_json::{Value, json};

#[tokio::test]
async fn seeded_registry_lists_the_papers_five_devices() {
    let server = TestServer::start().await;
    let page = server.get_json("/api/v1/tags").await;
    let items = page["items"].as_array().unwrap();
    assert_eq!(items.len(), 5);
    assert_eq!(page["next_cursor"], Value::Null);
    let types: Vec<&str> =
        items.iter().map(|t| t["properties"]["type"].as_str().unwrap()).collect();
    for expected in ["light switch", "ada light switch", "lamp", "drawer", "trash can"] {
        assert!(types.contains(&expected), "{expected} missing from {types:?}");
    }
    let lamps = server.get_json("/api/v1/tags?type=lamp").await;
    assert_eq!(lamps["items"].as_array().unwrap().len(), 1);
    let found = server.get_json("/api/v1/tags?q=a%20d%20a").await;
    assert_eq!(found["items"][0]["epc"], ADA_SWITCH);
    let none = server.get_json("/api/v1/tags?q=%25").await;
    assert_eq!(none["items"].as_array().unwrap().len(), 0, "% is searched literally");
}

#[tokio::test]
async fn get_returns_read_only_fields_etag_and_304() {
    let server = TestServer::start().await;
    let response =
        server.get(&format!("/api/v1/tags/{}", ADA_SWITCH.to_lowercase()), &server.admin).await;
    assert_eq!(response.status(), StatusCode::OK);
    let etag = response.headers()["etag"].to_str().unwrap().to_owned();
    let entry: Value = response.json().await.unwrap();
    assert_eq!(entry["epc"], ADA_SWITCH);
    assert_eq!(entry["epc_uri"], "urn:epc:id:gid:95100000.2.1");
    assert_eq!(entry["revision"], 1);
    assert_eq!(entry["archived"], false);
    assert_eq!(entry["updated_by"], "seed");
    assert_eq!(entry["actions"], json!({ "on": "push_top", "off": "push_bottom" }));
    assert_eq!(entry["behaviors"]["push_top"]["force_threshold"], 3.0);
    assert_eq!(entry["behaviors"]["push_bottom"]["height_offset"], -0.02);

    let cached = server
        .request(Method::GET, &format!("/api/v1/tags/{ADA_SWITCH}"), Some(&server.admin))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(cached.status(), StatusCode::NOT_MODIFIED);
    assert_eq!(cached.headers()["etag"].to_str().unwrap(), etag);

    let by_uri = server.get("/api/v1/tags/urn:epc:tag:gid-96:95100000.2.1", &server.admin).await;
    assert_eq!(by_uri.status(), StatusCode::OK, "a tag URI names the same tag");
}

#[tokio::test]
async fn create_replace_and_their_preconditions() {
    let server = TestServer::start().await;
    let epc = "E20034120000000000001001";
    let path = format!("/api/v1/tags/{epc}");
    let entry = new_entry(epc, "hall switch");

    let missing = server.put(&path, &server.admin, &entry, None).await;
    let body = problem(missing, StatusCode::PRECONDITION_REQUIRED).await;
    assert!(body["detail"].as_str().unwrap().contains("If-None-Match"));

    let created = server.put(&path, &server.admin, &entry, Some(("if-none-match", "*"))).await;
    assert_eq!(created.status(), StatusCode::CREATED);
    assert_eq!(created.headers()["location"], path.as_str());
    let etag = created.headers()["etag"].to_str().unwrap().to_owned();
    let stored: Value = created.json().await.unwrap();
    assert_eq!(stored["revision"], 1);
    assert_eq!(stored["epc_uri"], Value::Null, "an E2 header has no GS1 URI");
    assert!(stored.get("epc_uri").is_none());

    let again = server.put(&path, &server.admin, &entry, Some(("if-none-match", "*"))).await;
    problem(again, StatusCode::PRECONDITION_FAILED).await;

    // GET → edit → PUT round-trips with the read-only fields left in.
    let mut edited = stored.clone();
    edited["properties"]["location"]["room"] = "kitchen".into();
    let replaced = server.put(&path, &server.admin, &edited, Some(("if-match", &etag))).await;
    assert_eq!(replaced.status(), StatusCode::OK);
    let replaced: Value = replaced.json().await.unwrap();
    assert_eq!(replaced["revision"], 2);
    assert_eq!(replaced["properties"]["location"]["room"], "kitchen");

    let stale = server.put(&path, &server.admin, &edited, Some(("if-match", &etag))).await;
    let body = problem(stale, StatusCode::PRECONDITION_FAILED).await;
    assert!(body["detail"].as_str().unwrap().contains("revision 2"), "{body}");

    let nothing_there = server
        .put(
            "/api/v1/tags/E2003412000000000000FFFF",
            &server.admin,
            &new_entry("E2003412000000000000FFFF", "x"),
            Some(("if-match", "\"r1\"")),
        )
        .await;
    problem(nothing_there, StatusCode::PRECONDITION_FAILED).await;
}

/// `r1` without its quotes means `"r1"`: the answer says so instead of claiming the tag changed.
#[tokio::test]
async fn an_unquoted_etag_is_a_bad_request_that_shows_the_quoted_form() {
    let server = TestServer::start().await;
    let path = format!("/api/v1/tags/{DRAWER}");
    let entry = server.get_json(&path).await;
    let mut edited = entry.clone();
    edited["properties"]["location"]["room"] = "attic".into();

    let unquoted = server.put(&path, &server.admin, &edited, Some(("if-match", "r1"))).await;
    let body = problem(unquoted, StatusCode::BAD_REQUEST).await;
    assert!(body["detail"].as_str().unwrap().contains(r#"If-Match: "r1""#), "{body}");
    let archive = server
        .request(Method::DELETE, &path, Some(&server.admin))
        .header("if-match", "r1")
        .send()
        .await
        .unwrap();
    problem(archive, StatusCode::BAD_REQUEST).await;
    assert_eq!(server.get_json(&path).await, entry, "a failed request changes nothing");

    let read = server
        .request(Method::GET, &path, Some(&server.admin))
        .header("if-none-match", "r1")
        .send()
        .await
        .unwrap();
    let body = problem(read, StatusCode::BAD_REQUEST).await;
    assert!(body["detail"].as_str().unwrap().contains(r#"If-None-Match: "r1""#), "{body}");
    let robot = server.token(pps_server::identity::Role::Robot, "el-e-1").await;
    let effective = server
        .request(Method::GET, &format!("/api/v1/robots/el-e-1/tags/{DRAWER}"), Some(&robot))
        .header("if-none-match", "r1")
        .send()
        .await
        .unwrap();
    problem(effective, StatusCode::BAD_REQUEST).await;

    let quoted = server.put(&path, &server.admin, &edited, Some(("if-match", "\"r1\""))).await;
    assert_eq!(quoted.status(), StatusCode::OK);
}

#[tokio::test]
async fn two_caretakers_saving_the_same_revision_one_wins() {
    let server = TestServer::start().await;
    let path = format!("/api/v1/tags/{DRAWER}");
    let entry = server.get_json(&path).await;
    let mut racing = tokio::task::JoinSet::new();
    for n in 0..8 {
        let mut edit = entry.clone();
        edit["properties"]["location"]["room"] = format!("room {n}").into();
        let request = server
            .request(Method::PUT, &path, Some(&server.admin))
            .header("if-match", "\"r1\"")
            .json(&edit);
        racing.spawn(async move { request.send().await.unwrap().status() });
    }
    let statuses = racing.join_all().await;
    assert_eq!(statuses.iter().filter(|s| **s == StatusCode::OK).count(), 1, "{statuses:?}");
    assert_eq!(statuses.iter().filter(|s| **s == StatusCode::PRECONDITION_FAILED).count(), 7);
    assert_eq!(server.get_json(&path).await["revision"], 2);
}

#[tokio::test]
async fn invalid_entry_lists_every_error_and_changes_nothing() {
    let server = TestServer::start().await;
    let path = format!("/api/v1/tags/{ADA_SWITCH}");
    let mut entry = server.get_json(&path).await;
    entry["behaviors"]["push_top"]["force_threshold"] = 500.0.into();
    entry["actions"]["dim"] = "dim_slowly".into();
    entry["colour"] = "red".into();
    entry["properties"].as_object_mut().unwrap().remove("name");
    let response = server.put(&path, &server.admin, &entry, Some(("if-match", "\"r1\""))).await;
    let body = problem(response, StatusCode::UNPROCESSABLE_ENTITY).await;
    let listed = pointers(&body);
    for expected in
        ["/behaviors/push_top/force_threshold", "/actions/dim", "/colour", "/properties/name"]
    {
        assert!(listed.iter().any(|p| p == expected), "{expected:?} not in {listed:?}");
    }
    assert!(listed.len() >= 4, "{body}");
    let after = server.get_json(&path).await;
    assert_eq!(after["revision"], 1, "a failed request changes nothing");
    assert_eq!(
        server.get_json(&format!("{path}/revisions")).await["items"].as_array().unwrap().len(),
        1
    );

    let wrong_epc = server
        .put(&path, &server.admin, &new_entry(DRAWER, "x"), Some(("if-match", "\"r1\"")))
        .await;
    let body = problem(wrong_epc, StatusCode::UNPROCESSABLE_ENTITY).await;
    assert_eq!(pointers(&body), vec!["/epc"]);
}

#[tokio::test]
async fn archive_keeps_history_and_restore_needs_the_archived_etag() {
    let server = TestServer::start().await;
    let path = format!("/api/v1/tags/{DRAWER}");
    let no_condition =
        server.request(Method::DELETE, &path, Some(&server.admin)).send().await.unwrap();
    problem(no_condition, StatusCode::PRECONDITION_REQUIRED).await;
    let archived = server
        .request(Method::DELETE, &path, Some(&server.admin))
        .header("if-match", "\"r1\"")
        .send()
        .await
        .unwrap();
    assert_eq!(archived.status(), StatusCode::OK);
    let archived_etag = archived.headers()["etag"].to_str().unwrap().to_owned();
    let archived: Value = archived.json().await.unwrap();
    assert_eq!(archived["archived"], true);
    assert_eq!(archived["revision"], 2);

    let active = server.get_json("/api/v1/tags").await;
    assert_eq!(active["items"].as_array().unwrap().len(), 4);
    let listed = server.get_json("/api/v1/tags?archived=true").await;
    assert_eq!(listed["items"][0]["epc"], DRAWER);

    let restored =
        server.put(&path, &server.admin, &archived, Some(("if-match", &archived_etag))).await;
    assert_eq!(restored.status(), StatusCode::OK);
    let restored: Value = restored.json().await.unwrap();
    assert_eq!(restored["archived"], false);

    let history = server.get_json(&format!("{path}/revisions")).await;
    let changes: Vec<&str> = history["items"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["change"].as_str().unwrap())
        .collect();
    assert_eq!(changes, ["create", "archive", "restore"]);
    assert_eq!(history["items"][1]["changed_by"], "test admin");
    assert!(
        history["items"][0]["entry"]["behaviors"].is_object(),
        "each revision holds the full entry"
    );
}

#[tokio::test]
async fn lists_page_without_skipping_or_repeating() {
    let server = TestServer::start().await;
    for n in 0..12u32 {
        let epc = format!("E200341200000000{n:08X}");
        let response = server
            .put(
                &format!("/api/v1/tags/{epc}"),
                &server.admin,
                &new_entry(&epc, "switch"),
                Some(("if-none-match", "*")),
            )
            .await;
        assert_eq!(response.status(), StatusCode::CREATED);
    }
    let mut seen = Vec::new();
    let mut cursor: Option<String> = None;
    loop {
        let path = match &cursor {
            Some(c) => format!("/api/v1/tags?limit=5&cursor={c}"),
            None => "/api/v1/tags?limit=5".into(),
        };
        let page = server.get_json(&path).await;
        seen.extend(
            page["items"].as_array().unwrap().iter().map(|t| t["epc"].as_str().unwrap().to_owned()),
        );
        // A tag created mid-listing sorts before the cursor or after it, never twice.
        if seen.len() == 5 {
            let epc = "E2003412000000000000FFFE";
            server
                .put(
                    &format!("/api/v1/tags/{epc}"),
                    &server.admin,
                    &new_entry(epc, "late"),
                    Some(("if-none-match", "*")),
                )
                .await;
        }
        match page["next_cursor"].as_str() {
            Some(next) => cursor = Some(next.to_owned()),
            None => break,
        }
    }
    let mut unique = seen.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), seen.len(), "no tag repeated");
    assert_eq!(seen.len(), 18, "5 seeds + 12 + the late one");

    let too_many = server.get("/api/v1/tags?limit=501", &server.admin).await;
    let body = problem(too_many, StatusCode::BAD_REQUEST).await;
    assert!(body["detail"].as_str().unwrap().contains("500"));
    assert_eq!(server.get("/api/v1/tags?limit=500", &server.admin).await.status(), StatusCode::OK);
    problem(server.get("/api/v1/tags?cursor=***", &server.admin).await, StatusCode::BAD_REQUEST)
        .await;
    problem(server.get("/api/v1/tags?limit=ten", &server.admin).await, StatusCode::BAD_REQUEST)
        .await;
}

#[tokio::test]
async fn validate_endpoint_stores_nothing() {
    let server = TestServer::start().await;
    let entry = new_entry("E20034120000000000009999", "test");
    let ok = server
        .request(Method::POST, "/api/v1/validate/tag", Some(&server.admin))
        .json(&entry)
        .send()
        .await
        .unwrap();
    assert_eq!(ok.status(), StatusCode::OK);
    assert_eq!(ok.json::<Value>().await.unwrap()["valid"], true);
    let mut bad = entry.clone();
    bad["behaviors"]["push_top"]["height_offset"] = "high".into();
    let response = server
        .request(Method::POST, "/api/v1/validate/tag", Some(&server.admin))
        .json(&bad)
        .send()
        .await
        .unwrap();
    let body = problem(response, StatusCode::UNPROCESSABLE_ENTITY).await;
    assert_eq!(pointers(&body), vec!["/behaviors/push_top/height_offset"]);
    problem(
        server.get("/api/v1/tags/E20034120000000000009999", &server.admin).await,
        StatusCode::NOT_FOUND,
    )
    .await;
}

#[tokio::test]
async fn schemas_are_served_openly() {
    let server = TestServer::start().await;
    for name in ["tag", "trial", "robot", "light_switch", "pull_back", "push", "pull_lamp", "drop"]
    {
        let response = server
            .request(Method::GET, &format!("/api/v1/schema/{name}"), None)
            .send()
            .await
            .unwrap();
        assert_eq!(response.status(), StatusCode::OK, "{name}");
        let schema: Value = response.json().await.unwrap();
        assert_eq!(schema["$schema"], "https://json-schema.org/draft/2020-12/schema");
    }
    problem(
        server.request(Method::GET, "/api/v1/schema/nope", None).send().await.unwrap(),
        StatusCode::NOT_FOUND,
    )
    .await;
    let health = server.request(Method::GET, "/healthz", None).send().await.unwrap();
    assert_eq!(health.status(), StatusCode::OK);
}
