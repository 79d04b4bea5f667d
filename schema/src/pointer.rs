//! RFC 6901 JSON pointers: how validation errors, provenance and learned values name a field.

/// `parent` followed by the segment `key`, escaped.
pub fn join(parent: &str, key: &str) -> String {
    format!("{parent}/{}", escape(key))
}

/// Escapes one reference token (`~` and `/`).
pub fn escape(segment: &str) -> String {
    segment.replace('~', "~0").replace('/', "~1")
}

/// How a message names the field at `pointer`: its key, `hue_deg[0]` for an array item, or
/// "the document" for the root.
pub fn field_name(pointer: &str) -> String {
    let mut segments = pointer.rsplit('/').map(unescape);
    match (segments.next(), segments.next()) {
        (None, _) | (Some(_), None) => "the document".to_owned(),
        (Some(last), parent) if last.parse::<usize>().is_ok() => match parent {
            Some(parent) if !parent.is_empty() => format!("{parent}[{last}]"),
            _ => format!("item {last}"),
        },
        (Some(last), _) => last,
    }
}

/// Undoes [`escape`].
pub fn unescape(segment: &str) -> String {
    segment.replace("~1", "/").replace("~0", "~")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_and_names() {
        assert_eq!(join("/actions", "a/b~c"), "/actions/a~1b~0c");
        assert_eq!(field_name(""), "the document");
        assert_eq!(field_name("/epc"), "epc");
        assert_eq!(field_name("/actions/a~1b~0c"), "a/b~c");
        assert_eq!(
            field_name("/properties/robots/el-e/color_segmentation/hue_deg/0"),
            "hue_deg[0]"
        );
        assert_eq!(field_name("/forces/3"), "forces[3]");
    }
}
