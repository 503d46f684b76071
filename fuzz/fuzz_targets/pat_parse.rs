//! The `.pat` parser never panics, and whatever it accepts round-trips:
//! the canonical text parses back to the same pattern and is a fixed point.
#![no_main]
use libfuzzer_sys::fuzz_target;
use patkit::Pattern;

fuzz_target!(|data: &[u8]| {
    if let Ok(p) = Pattern::parse(data, "fuzz.pat") {
        let text = p.to_canonical();
        let back = Pattern::parse(text.as_bytes(), "canonical.pat").expect("canonical text parses");
        assert_eq!(back, p);
        assert_eq!(back.to_canonical(), text);
    }
});
