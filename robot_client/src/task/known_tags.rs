//! What a robot knows of its home's tags before it reads one (issue 34): the colour to look for
//! and how large a tag may be, from the registry's entries as its cache holds them (so also
//! offline). `run`, `work` and `pps-ros2` look for tags with these settings. Once a tag's EPC is
//! read, its own entry narrows them: its own learned colour and its own registered size.

use pps_schema::{EffectiveEntry, LearnedColor, TagSize};

use crate::perception::{HsvThresholds, TagSearchParams, covering_colour, describe_colour};

/// Whether the colour to look for comes from the home's tags or stays as given (a person's
/// `--hsv`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourSource {
    KnownTags,
    AsGiven,
}

/// `params` for the tags `known`, with what was chosen and why, in words.
pub fn search_for_known_tags(
    params: &TagSearchParams,
    known: &[EffectiveEntry],
    colour: ColourSource,
) -> (TagSearchParams, Vec<String>) {
    let mut notes = Vec::new();
    let mut params = params.clone();
    if colour == ColourSource::KnownTags {
        params.thresholds = known_colour(params.thresholds, known, &mut notes).0;
    }
    (bounded_by_known_sizes(&params, known, &mut notes), notes)
}

/// The search for one tag whose EPC has been read: `used` (the search that found it before the
/// read) with the tag's own learned colour, else what `search_for_known_tags` takes from its
/// entry (the household's), and the tag's own registered size, else the bound `used` had.
pub fn search_for_this_tag(
    used: &TagSearchParams,
    entry: &EffectiveEntry,
    colour: ColourSource,
) -> ThisTagSearch {
    let mut notes = Vec::new();
    let mut params = used.clone();
    let properties = &entry.entry.properties;
    let own = properties.learned_color().and_then(|learned| {
        HsvThresholds::new(&learned.segmentation).ok().map(|thresholds| (learned, thresholds))
    });
    let colour_from = match (colour, own) {
        (ColourSource::AsGiven, _) => "the colour given",
        (ColourSource::KnownTags, Some((learned, thresholds))) => {
            notes.push(format!(
                "looking for {} (this tag's own, learned from {} confirmed reads of it)",
                describe_colour(&learned.segmentation),
                learned.trials
            ));
            params.thresholds = thresholds;
            "this tag's own colour"
        }
        (ColourSource::KnownTags, None) => {
            let entry = std::slice::from_ref(entry);
            // The household's colour again only if the tag was found in it: one that saw
            // nothing of this tag before the read ([`search_in_the_registered_colour`]) would
            // see nothing of it now.
            let (thresholds, from) = match households_colour(entry) {
                Some((_, household)) if household != used.thresholds => {
                    registered_colour(used.thresholds, entry, &mut notes)
                }
                _ => known_colour(used.thresholds, entry, &mut notes),
            };
            params.thresholds = thresholds;
            from
        }
    };
    let size_from = match properties.tag_size {
        Some(size) => {
            params = params.for_home_tags([size]);
            notes.push(format!(
                "no red region reaching more than {:.0} cm from its middle is taken for it (its \
                 registered size, {})",
                params.max_tag_radius * 100.0,
                describe_size(&size)
            ));
            format!("its own size ({})", describe_size(&size))
        }
        None => format!(
            "the size bound used before ({:.0} cm from its middle; it has no registered size)",
            params.max_tag_radius * 100.0
        ),
    };
    let with = format!("{colour_from} and {size_from}");
    ThisTagSearch { differs: params != *used, params, with, notes }
}

/// The search [`search_for_this_tag`] chose, and what it rests on in words.
#[derive(Debug, Clone, PartialEq)]
pub struct ThisTagSearch {
    pub params: TagSearchParams,
    /// Whether it differs from the search before the read: otherwise a second look with it
    /// finds what the first found.
    pub differs: bool,
    /// What the colour and the size bound come from, e.g. "this tag's own colour and its own
    /// size (5 × 8 cm)".
    pub with: String,
    pub notes: Vec<String>,
}

/// A tag's size as a person reads it: "5 × 8 cm".
fn describe_size(size: &TagSize) -> String {
    format!("{:.0} × {:.0} cm", size.width * 100.0, size.height * 100.0)
}

/// The colour this robot's class has learned its household's tags to have (their confirmed
/// reads' colours, the registry's household model in any entry), or else the colours this
/// robot's camera sees the registry's tags in (their entries' `color_segmentation`, merged for
/// this robot), or `fallback` when those cannot be used; with where it came from, in words.
fn known_colour(
    fallback: HsvThresholds,
    known: &[EffectiveEntry],
    notes: &mut Vec<String>,
) -> (HsvThresholds, &'static str) {
    if let Some((learned, thresholds)) = households_colour(known) {
        notes.push(format!(
            "looking for {} (learned from {} confirmed reads of this household's tags)",
            describe_colour(&learned.segmentation),
            learned.trials
        ));
        return (thresholds, "the household's learned colour");
    }
    registered_colour(fallback, known, notes)
}

/// The colour this robot's class has learned its household's tags to have, from the entry
/// whose model rests on the most confirmed reads; `None` before three.
fn households_colour(known: &[EffectiveEntry]) -> Option<(LearnedColor, HsvThresholds)> {
    let learned = known
        .iter()
        .filter_map(|e| e.entry.properties.household_color())
        .max_by_key(|learned| learned.trials)?;
    let thresholds = HsvThresholds::new(&learned.segmentation).ok()?;
    Some((learned, thresholds))
}

/// `params` (from [`search_for_known_tags`]) looking for the colours the registry's entries
/// give instead of the household's learned colour, when that is what they look for, with what
/// it does in words; `None` otherwise. A colour learned from the household's tags holds the
/// reds they were seen in: a tag of another red hung since (an orange-red towel), or a light
/// the looks never had, shows nothing of it, and the robot looks again for the broader
/// registered colour before it asks the person to point at the tag itself.
pub fn search_in_the_registered_colour(
    params: &TagSearchParams,
    known: &[EffectiveEntry],
) -> Option<(TagSearchParams, String)> {
    let (learned, thresholds) = households_colour(known)?;
    if thresholds != params.thresholds {
        return None;
    }
    let mut notes = Vec::new();
    let (registered, _) = registered_colour(params.thresholds, known, &mut notes);
    let note = format!(
        "nothing of the household's learned colour ({}) near the pointed location: a tag of \
         another red, or a light its looks never had; {}",
        describe_colour(&learned.segmentation),
        notes.join("; ")
    );
    Some((TagSearchParams { thresholds: registered, ..params.clone() }, note))
}

/// The colours this robot's camera sees the registry's tags in (their entries'
/// `color_segmentation`, merged for this robot), or `fallback` when those cannot be used.
fn registered_colour(
    fallback: HsvThresholds,
    known: &[EffectiveEntry],
    notes: &mut Vec<String>,
) -> (HsvThresholds, &'static str) {
    let colours = known.iter().filter_map(|e| e.entry.properties.color_segmentation());
    let colour = covering_colour(colours.clone());
    match HsvThresholds::new(&colour) {
        Ok(thresholds) => {
            let from = match colours.count() {
                0 => format!("the paper's red: none of {} known tags gives a colour", known.len()),
                n => format!("the colours of {n} of {} known tags", known.len()),
            };
            notes.push(format!("looking for {} ({from})", describe_colour(&colour)));
            (thresholds, "the registered colour")
        }
        Err(error) => {
            notes.push(format!(
                "the entries' colours cannot be used ({error}); looking for the default red"
            ));
            (fallback, "the default red")
        }
    }
}

/// `params` bounded by the largest tag of this household when every known tag has a registered
/// size; otherwise a tag may be as large as a towel.
fn bounded_by_known_sizes(
    params: &TagSearchParams,
    known: &[EffectiveEntry],
    notes: &mut Vec<String>,
) -> TagSearchParams {
    let sizes: Option<Vec<TagSize>> = known.iter().map(|e| e.entry.properties.tag_size).collect();
    match sizes {
        Some(sizes) if !sizes.is_empty() => {
            let bounded = params.for_home_tags(sizes.iter().copied());
            notes.push(format!(
                "no red region reaching more than {:.0} cm from its middle is taken for a tag \
                 (the largest of this household's {} tags, by their registered or learned sizes)",
                bounded.max_tag_radius * 100.0,
                sizes.len()
            ));
            bounded
        }
        _ => {
            let without_size =
                known.iter().filter(|e| e.entry.properties.tag_size.is_none()).count();
            if without_size > 0 {
                notes.push(format!(
                    "{without_size} of {} known tags have no registered size, so a tag may be as \
                     large as a towel",
                    known.len()
                ));
            }
            params.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{Value, json};

    fn known(epc: &str, properties: Value) -> EffectiveEntry {
        serde_json::from_value(json!({
            "epc": epc,
            "robot": "el-e-1",
            "revision": 1,
            "entry": {"epc": epc, "properties": properties, "actions": {}, "behaviors": {}},
            "provenance": {},
        }))
        .expect("an effective entry")
    }

    fn patch(epc: &str) -> EffectiveEntry {
        known(epc, json!({"name": "rocker", "tag_size": {"width": 0.05, "height": 0.08}}))
    }

    #[test]
    fn the_largest_registered_tag_bounds_the_search_once_every_tag_has_a_size() {
        let factory = TagSearchParams::default();
        let towel =
            known("E2000002", json!({"name": "drawer", "tag_size": {"width": 0.3, "height": 0.2}}));
        let (params, notes) =
            search_for_known_tags(&factory, &[patch("E2000001"), towel], ColourSource::AsGiven);
        let reach = 0.3f64.hypot(0.2) / 2.0 + factory.fragment_gap;
        assert!((params.max_tag_radius - reach).abs() < 1e-12, "{}", params.max_tag_radius);
        assert_eq!(params.thresholds, factory.thresholds, "the colour as given");
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("21 cm") && notes[0].contains("2 tags"), "{}", notes[0]);

        let unsized_lamp = known("E2000003", json!({"name": "lamp"}));
        let (params, notes) = search_for_known_tags(
            &factory,
            &[patch("E2000001"), unsized_lamp],
            ColourSource::AsGiven,
        );
        assert_eq!(params.max_tag_radius, factory.max_tag_radius);
        assert!(notes[0].starts_with("1 of 2 known tags have no registered size"), "{notes:?}");
    }

    #[test]
    fn the_households_learned_colour_is_looked_for_unless_one_is_given() {
        let factory = TagSearchParams::default();
        let learned = json!({
            "name": "rocker",
            "household_color_segmentation": {
                "hue_deg": [352.0, 8.0], "saturation": [0.65, 1.0], "value": [0.2, 1.0], "trials": 5
            }
        });
        let entries = [known("E2000001", learned)];
        let (params, notes) = search_for_known_tags(&factory, &entries, ColourSource::KnownTags);
        assert_ne!(params.thresholds, factory.thresholds);
        assert!(notes[0].contains("learned from 5 confirmed reads"), "{notes:?}");
        let (params, notes) = search_for_known_tags(&factory, &entries, ColourSource::AsGiven);
        assert_eq!(params.thresholds, factory.thresholds);
        assert!(notes.iter().all(|n| !n.contains("looking for")), "{notes:?}");
    }

    #[test]
    fn where_the_learned_colour_sees_nothing_the_registered_one_is_looked_for() {
        let factory = TagSearchParams::default();
        let rocker = known(
            "E2000001",
            json!({
                "name": "rocker",
                "color_segmentation": {
                    "hue_deg": [340.0, 20.0], "saturation": [0.5, 1.0], "value": [0.15, 1.0]
                },
                "household_color_segmentation": {
                    "hue_deg": [353.0, 357.0], "saturation": [0.6, 1.0], "value": [0.15, 1.0],
                    "trials": 3
                }
            }),
        );
        let entries = [rocker];
        let (learned, _) = search_for_known_tags(&factory, &entries, ColourSource::KnownTags);
        let (registered, note) =
            search_in_the_registered_colour(&learned, &entries).expect("looked for again");
        let expected = HsvThresholds::new(&pps_schema::ColorSegmentation {
            hue_deg: [340.0, 20.0],
            saturation: [0.5, 1.0],
            value: [0.15, 1.0],
        })
        .unwrap();
        assert_eq!(registered.thresholds, expected);
        assert_eq!(registered.max_tag_radius, learned.max_tag_radius, "only the colour changes");
        assert!(note.contains("hue 353..357°") && note.contains("hue 340..20°"), "{note}");
        // A search that was not for the learned colour (a colour given) is not looked for again,
        // nor is one in a household that has learned none.
        assert!(search_in_the_registered_colour(&factory, &entries).is_none());
        assert!(search_in_the_registered_colour(&factory, &[patch("E2000002")]).is_none());
        // After the read, the tag found in the registered colour is not looked for in the
        // household's again.
        let this = search_for_this_tag(&registered, &entries[0], ColourSource::KnownTags);
        assert_eq!(this.params.thresholds, expected, "{:?}", this.notes);
    }

    #[test]
    fn after_the_read_the_tag_is_looked_for_in_its_own_colour_and_at_its_own_size() {
        let household = json!({
            "hue_deg": [345.0, 28.0], "saturation": [0.5, 1.0], "value": [0.15, 1.0], "trials": 6
        });
        let own = json!({
            "hue_deg": [352.0, 8.0], "saturation": [0.6, 1.0], "value": [0.15, 1.0], "trials": 3
        });
        let rocker = known(
            "E2000001",
            json!({
                "name": "rocker",
                "tag_size": {"width": 0.05, "height": 0.08},
                "household_color_segmentation": household,
                "learned_color_segmentation": own,
            }),
        );
        let towel =
            known("E2000002", json!({"name": "drawer", "tag_size": {"width": 0.3, "height": 0.2}}));
        let known_tags = [rocker.clone(), towel];
        let factory = TagSearchParams::default();
        let (before, _) = search_for_known_tags(&factory, &known_tags, ColourSource::KnownTags);

        let after = search_for_this_tag(&before, &rocker, ColourSource::KnownTags);
        assert!(after.differs);
        let own =
            HsvThresholds::new(&rocker.entry.properties.learned_color().unwrap().segmentation);
        assert_eq!(after.params.thresholds, own.unwrap());
        let reach = 0.05f64.hypot(0.08) / 2.0 + factory.fragment_gap;
        assert!((after.params.max_tag_radius - reach).abs() < 1e-12);
        assert_eq!(after.with, "this tag's own colour and its own size (5 × 8 cm)");
        assert!(after.notes[0].contains("learned from 3 confirmed reads of it"), "{after:?}");

        // A tag the registry knows no more of than of the household's: the search as before.
        let plain =
            known("E2000003", json!({"name": "lamp", "household_color_segmentation": household}));
        let (before, _) =
            search_for_known_tags(&factory, std::slice::from_ref(&plain), ColourSource::KnownTags);
        let after = search_for_this_tag(&before, &plain, ColourSource::KnownTags);
        assert!(!after.differs, "{after:?}");
        assert!(after.with.starts_with("the household's learned colour and the size bound used"));
        let given = search_for_this_tag(&before, &rocker, ColourSource::AsGiven);
        assert_eq!(given.params.thresholds, before.thresholds);
        assert!(given.with.starts_with("the colour given and its own size"), "{given:?}");
    }
}
