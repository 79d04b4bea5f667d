//! What a caretaker sees of a page, and the names only robot engineers know, so tests can check
//! that the default view speaks plainly.

use serde_json::Value;

use crate::Session;

/// The text of `main` a person sees: hidden elements and closed sections leave it out.
pub async fn visible_text(page: &Session) -> String {
    page.eval("return document.querySelector('main').innerText").await.as_str().unwrap().to_owned()
}

/// The names only robot engineers know in `tag` (as GET returns it): the EPC and its URI,
/// behaviour keys and behaviour names, the values of the properties with fixed choices, and
/// the robot classes and robots it has overrides for.
pub fn internal_identifiers(tag: &Value) -> Vec<String> {
    let mut names = vec![tag["epc"].as_str().unwrap().to_owned()];
    names.extend(tag["epc_uri"].as_str().map(str::to_owned));
    let properties = &tag["properties"];
    for key in ["pps_tag", "change", "direction"] {
        names.extend(properties[key].as_str().map(str::to_owned));
    }
    let overrides = |robots: &Value| -> Vec<String> {
        robots.as_object().map(|o| o.keys().cloned().collect()).unwrap_or_default()
    };
    names.extend(overrides(&properties["robots"]));
    for (key, spec) in tag["behaviors"].as_object().unwrap() {
        names.push(key.clone());
        names.push(spec["behavior"].as_str().unwrap().to_owned());
        names.extend(overrides(&spec["robots"]));
    }
    names
        .extend(["color_segmentation", "hue_deg", "properties ›", "/properties"].map(String::from));
    names
}

/// Fails the test if the page's visible text holds any of `tag`'s internal identifiers.
pub async fn assert_plain(page: &Session, tag: &Value) {
    let shown = visible_text(page).await;
    let internal = internal_identifiers(tag);
    assert!(internal.len() > 8, "too few names to check: {internal:?}");
    for name in &internal {
        assert!(!shown.contains(name.as_str()), "{name:?} is shown by default:\n{shown}");
    }
}
