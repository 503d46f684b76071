//! The polygon stream reader never panics: every input is records or an error
//! naming the record, and every record it yields has finite vertices.
#![no_main]
use libfuzzer_sys::fuzz_target;
use patkit::geom::Shape;
use patkit::stream::{for_each_record, StreamError};

fuzz_target!(|data: &[u8]| {
    let _: Result<(), StreamError> = for_each_record(data, "fuzz.json", |r| {
        if let Shape::Polygon(v) = &r.shape {
            assert!(v.len() >= 3);
            assert!(v.iter().all(|p| p.is_finite()));
        }
        let outline = patkit::geom::outline(&r.shape, 0.5);
        assert!(outline.iter().all(|p| p.is_finite()));
        Ok(())
    });
});
