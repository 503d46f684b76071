//! The camera parser never panics and never yields a non-finite matrix.
#![no_main]
use libfuzzer_sys::fuzz_target;
use patkit::camera::Camera;

fuzz_target!(|data: &[u8]| {
    let Ok(value) = serde_json::from_slice::<serde_json::Value>(data) else {
        return;
    };
    if let Ok(cam) = Camera::from_json(&value, "fuzz.json") {
        let m = cam.world_to_clip();
        assert!(m.to_cols_array().iter().all(|x| x.is_finite()));
        assert!(cam.near < cam.far);
    }
});
