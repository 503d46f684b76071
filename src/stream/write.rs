//! Writing the stream: records as NDJSON lines, the form every tool writes.
//! The reader is [`super::read`]; writing has its own file because it needs
//! none of the reader's machinery, only the record's kept JSON object.

use super::fields::Fields;
use std::io::Write;

/// Writes one record as a line of NDJSON (the default output form): unknown
/// fields as written, whitespace between their tokens removed; known fields
/// as serde_json writes them ([`Fields`]).
pub fn write_ndjson<W: Write>(w: &mut W, fields: &Fields) -> std::io::Result<()> {
    serde_json::to_writer(&mut *w, fields)?;
    w.write_all(b"\n")
}

#[cfg(test)]
mod tests {
    use super::super::testing::read_all;
    use super::*;

    #[test]
    fn ndjson_output_keeps_unknown_fields_in_order() {
        let r = read_all(r#"{"z":1,"rect":[0,0,1,1],"color":[0,0,0],"a":{"b":[1]}}"#).unwrap();
        let mut out = Vec::new();
        write_ndjson(&mut out, &r[0].fields).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "{\"z\":1,\"rect\":[0,0,1,1],\"color\":[0,0,0],\"a\":{\"b\":[1]}}\n"
        );
    }

    /// Every element of `text` (records, definitions, instances) written
    /// back as NDJSON.
    fn written(text: &str) -> String {
        let mut out = Vec::new();
        super::super::for_each_item(text.as_bytes(), "s.json", |item| {
            let fields = match &item {
                super::super::Item::Record(r) => &r.fields,
                super::super::Item::Object(d) => &d.fields,
                super::super::Item::Instance(i) => &i.fields,
                super::super::Item::Light(l) => &l.fields,
            };
            write_ndjson(&mut out, fields).map_err(|e| super::super::StreamError {
                source: String::new(),
                record: None,
                message: e.to_string(),
            })
        })
        .unwrap();
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn unknown_fields_are_written_as_they_were_read() {
        // Issue 16 (5): the 30-digit id came out as 1.2345678901234568e+29.
        let u_in = r#""id": 123456789012345678901234567890, "e": 1e2, "z": -0, "d": 1.50,
            "s": "\u00e9\/", "t": [ 1E+2, { "k" : "a b" } ]"#;
        let u = r#""id":123456789012345678901234567890,"e":1e2,"z":-0,"d":1.50,"s":"\u00e9\/","t":[1E+2,{"k":"a b"}]"#;
        let elements = [
            format!(r#"{{"vertices":[[0,0],[1,0],[0,1]],"color":[1,2,3],{u_in}}}"#),
            format!(r#"{{"rect":[0,0,1,1],"color":[1,2,3],{u_in}}}"#),
            format!(
                r#"{{"object":"o","records":[{{"rect":[0,0,1,1],"color":[1,2,3],{u_in}}}],{u_in}}}"#
            ),
            format!(r#"{{"instance":"o",{u_in}}}"#),
        ];
        let want = format!(
            "{{\"vertices\":[[0,0],[1,0],[0,1]],\"color\":[1,2,3],{u}}}\n\
             {{\"rect\":[0,0,1,1],\"color\":[1,2,3],{u}}}\n\
             {{\"object\":\"o\",\"records\":[{{\"rect\":[0,0,1,1],\"color\":[1,2,3],{u}}}],{u}}}\n\
             {{\"instance\":\"o\",{u}}}\n"
        );
        let ndjson: String = elements
            .iter()
            .map(|e| e.replace('\n', " ") + "\n")
            .collect();
        assert_eq!(written(&ndjson), want);
        let array = format!("[{}]", elements.join(",\n"));
        assert_eq!(written(&array), want);
    }

    /// A JSON value's text as written (whitespace between tokens) and as it
    /// must come out (none).
    fn json_text() -> impl proptest::strategy::Strategy<Value = (String, String)> {
        use proptest::prelude::*;
        let ws = || "[ \t\n\r]{0,2}";
        let number = "-?(0|[1-9][0-9]{0,30})(\\.[0-9]{1,4})?([eE][+-]?[0-9]{1,3})?";
        let string = proptest::collection::vec(
            prop_oneof![
                "[a-z é]",
                Just("\\\"".to_string()),
                Just("\\\\".to_string()),
                Just("\\/".to_string()),
                Just("\\t".to_string()),
                Just("\\u00e9".to_string()),
                Just("\\uD83D\\uDE00".to_string()),
            ],
            0..5,
        )
        .prop_map(|parts| format!("\"{}\"", parts.concat()));
        let leaf = prop_oneof![
            number.prop_map(|s| (s.clone(), s)),
            string.clone().prop_map(|s| (s.clone(), s)),
            prop_oneof![Just("true"), Just("false"), Just("null")]
                .prop_map(|s| (s.to_string(), s.to_string())),
        ];
        leaf.prop_recursive(4, 24, 4, move |inner| {
            let item = (ws(), inner, ws()).prop_map(|(a, (t, m), b)| (format!("{a}{t}{b}"), m));
            prop_oneof![
                proptest::collection::vec(item.clone(), 0..4).prop_map(|xs| {
                    let (t, m): (Vec<_>, Vec<_>) = xs.into_iter().unzip();
                    (format!("[{}]", t.join(",")), format!("[{}]", m.join(",")))
                }),
                proptest::collection::vec((ws(), string.clone(), ws(), item), 0..4).prop_map(
                    |xs| {
                        let t: Vec<String> = xs
                            .iter()
                            .map(|(a, k, b, (v, _))| format!("{a}{k}{b}:{v}"))
                            .collect();
                        let m: Vec<String> = xs
                            .iter()
                            .map(|(_, k, _, (_, v))| format!("{k}:{v}"))
                            .collect();
                        (
                            format!("{{{}}}", t.join(",")),
                            format!("{{{}}}", m.join(",")),
                        )
                    }
                ),
            ]
        })
    }

    proptest::proptest! {
        /// Any JSON value in an unknown field comes out as written, less
        /// the whitespace between its tokens, from either form of input.
        #[test]
        fn any_unknown_field_comes_out_as_written(
            (text, min) in json_text(),
            plain in proptest::bool::ANY,
        ) {
            let geometry = if plain {
                r#""vertices":[[0,0],[1,0],[0,1]]"#
            } else {
                r#""rect":[0,0,1,1]"#
            };
            let rec = format!(r#"{{{geometry},"color":[1,2,3],"x": {text} }}"#);
            let want = format!("{{{geometry},\"color\":[1,2,3],\"x\":{min}}}\n");
            proptest::prop_assert_eq!(written(&rec.replace(['\n', '\r'], " ")), want.clone());
            proptest::prop_assert_eq!(written(&format!("[{rec}]")), want);
        }
    }
}
