//! Writing the stream: records as NDJSON lines, the form every tool writes.
//! The reader is [`super::read`]; writing has its own file because it needs
//! none of the reader's machinery, only the record's kept JSON object.

use serde_json::{Map, Value};
use std::io::Write;

/// Writes one record as a line of NDJSON (the default output form).
pub fn write_ndjson<W: Write>(w: &mut W, fields: &Map<String, Value>) -> std::io::Result<()> {
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
}
