//! Unknown keys inside a record's `"pattern"` and `"stripe"` objects: a
//! misspelt `"boundry"` would otherwise be ignored without a word (issue 19).
//! They warn rather than fail, as a record's own unknown fields pass through
//! (another tool's keys are welcome); and they warn once per distinct key
//! and object per run, not per record, so a stream of a million records with
//! one stray key gives one line.

use crate::stream::{Fields, PATTERN_KEYS};
use serde_json::Value;
use std::collections::HashSet;

/// The keys a `"pattern"` object may have: its placement and its texture
/// state.
pub fn pattern_keys() -> impl Iterator<Item = &'static str> + Clone {
    PATTERN_KEYS.into_iter().chain(crate::texture::state::KEYS)
}

/// The known keys of the objects checked, by the record key that holds them.
fn known(object: &str) -> Option<Vec<&'static str>> {
    match object {
        "pattern" => Some(pattern_keys().collect()),
        "stripe" => Some(crate::stripe::record::KEYS.to_vec()),
        _ => None,
    }
}

/// The objects whose keys are checked.
const CHECKED: [&str; 2] = ["pattern", "stripe"];

/// The keys already warned about in this run.
#[derive(Debug, Default)]
pub struct UnknownKeys {
    seen: HashSet<(&'static str, String)>,
}

impl UnknownKeys {
    /// A warning for every unknown key of record `index`'s `"pattern"` and
    /// `"stripe"` not warned about before, in the form `record N: unknown key
    /// "boundry" in "pattern" (known: file, mode, ...)`. Costs a few string
    /// comparisons per key when every key is known.
    pub fn check(&mut self, index: usize, fields: &Fields, mut warn: impl FnMut(String)) {
        for object in CHECKED {
            let Some(Value::Object(obj)) = fields.get(object) else {
                continue;
            };
            let known = known(object).expect("a checked object");
            for k in obj.keys() {
                if known.contains(&k.as_str()) || self.seen.contains(&(object, k.clone())) {
                    continue;
                }
                self.seen.insert((object, k.clone()));
                warn(format!(
                    "record {index}: unknown key {} in \"{object}\" (known: {})",
                    Value::String(k.clone()),
                    known.join(", ")
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fields(s: &str) -> Fields {
        serde_json::from_str::<serde_json::Map<String, Value>>(s)
            .unwrap()
            .into()
    }

    #[test]
    fn each_unknown_key_warns_once_per_run() {
        let mut keys = UnknownKeys::default();
        let mut said = Vec::new();
        let rec = fields(
            r#"{"pattern": {"file": "a.pat", "boundry": "clamp", "filter": "point"}, "extra": 1}"#,
        );
        for i in 0..3 {
            keys.check(i, &rec, |w| said.push(w));
        }
        keys.check(
            7,
            &fields(r#"{"stripe": {"map": "m", "boundry": 1}}"#),
            |w| said.push(w),
        );
        assert_eq!(said.len(), 2, "{said:?}");
        assert!(said[0].starts_with(
            r#"record 0: unknown key "boundry" in "pattern" (known: file, mode, incr, rotate, horz, vert, filter,"#
        ));
        assert!(said[1].starts_with(r#"record 7: unknown key "boundry" in "stripe" (known: map,"#));
    }
}
