//! Unknown keys inside a record's `"pattern"` and `"stripe"` objects: a
//! misspelt `"boundry"` would otherwise be ignored without a word (issue 19).
//! They warn rather than fail, as a record's own unknown fields pass through
//! (another tool's keys are welcome); and they warn once per distinct key
//! and object per run, not per record, so a stream of a million records with
//! one stray key gives one line.

use crate::stream::{Fields, PATTERN_KEYS};
use serde_json::Value;
use std::collections::HashSet;

/// The objects whose keys are checked, their known keys (two lists for
/// "pattern", one for "stripe") and the keys still read under an old
/// spelling, as `(old, new)`, which warn naming the new one instead of as
/// unknown: static, so a record whose keys are all known costs a few string
/// comparisons and no allocation.
type Checked = (
    &'static str,
    [&'static [&'static str]; 2],
    &'static [(&'static str, &'static str)],
);
const CHECKED: [Checked; 2] = [
    (
        "pattern",
        [&PATTERN_KEYS, &crate::texture::state::KEYS],
        &[],
    ),
    (
        "stripe",
        [&crate::stripe::record::KEYS, &[]],
        &crate::stripe::record::OLD_KEYS,
    ),
];

/// The keys already warned about in this run, per checked object.
#[derive(Debug, Default)]
pub struct UnknownKeys {
    seen: [HashSet<String>; CHECKED.len()],
}

impl UnknownKeys {
    /// A warning for every unknown key of record `index`'s `"pattern"` and
    /// `"stripe"` not warned about before, in the form `record N: unknown key
    /// "boundry" in "pattern" (known: file, mode, ...)`.
    pub fn check(&mut self, index: usize, fields: &Fields, mut warn: impl FnMut(String)) {
        for ((object, known, renamed), seen) in CHECKED.iter().zip(&mut self.seen) {
            let Some(Value::Object(obj)) = fields.get(object) else {
                continue;
            };
            for k in obj.keys() {
                if known.iter().any(|list| list.contains(&k.as_str())) {
                    continue;
                }
                if let Some((_, new)) = renamed.iter().find(|(old, _)| old == k) {
                    if !seen.contains(k.as_str()) {
                        seen.insert(k.clone());
                        warn(format!(
                            "record {index}: {} in \"{object}\" is the old spelling of {}: it is read, but write {}",
                            Value::String(k.clone()),
                            Value::String((*new).into()),
                            Value::String((*new).into()),
                        ));
                    }
                    continue;
                }
                // Looked up before inserting: a stray key on every record
                // of a long stream allocates nothing after the first.
                if seen.contains(k.as_str()) {
                    continue;
                }
                seen.insert(k.clone());
                warn(format!(
                    "record {index}: unknown key {} in \"{object}\" (known: {})",
                    Value::String(k.clone()),
                    known.concat().join(", ")
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

    #[test]
    fn an_old_spelling_warns_once_naming_the_new_one() {
        let mut keys = UnknownKeys::default();
        let mut said = Vec::new();
        let rec = fields(r#"{"stripe": {"map": "m", "colours": "t.ct"}}"#);
        for i in 0..3 {
            keys.check(i, &rec, |w| said.push(w));
        }
        assert_eq!(
            said,
            [
                r#"record 0: "colours" in "stripe" is the old spelling of "colors": it is read, but write "colors""#
            ]
        );
    }
}
