//! `{"mesh": {"obj": FILE}, ...}`: a Wavefront OBJ model in the stream
//! ([`super::obj`] reads the file). Its faces become ordinary polygon
//! records, so every tool already knows them:
//!
//! - at the top level, the mesh is an object of its faces (named `mesh N`
//!   after its element) placed by an instance carrying the record's
//!   `"transform"` (static or animated) and its other fields, so instancing,
//!   transforms, culling and animation apply as to any object, and
//!   `polyfill3` partitions the faces once and passes the instance on;
//! - inside an object definition, its faces are records of that object.
//!
//! Each face is drawn as a fan of triangles from its first corner, as GL
//! draws a `GL_POLYGON` (an exporter's concave faces must be triangulated
//! first); a triangle with no area is left out. A face's colour is its
//! material's `Kd` (linear reflectance, encoded to sRGB), else the
//! record's `"color"`, else white. Its texture: the record's own
//! `"pattern"` if it gives one (texel coordinates from `vt` when its mode is
//! `"uv"`), else the material's `map_Kd`, as an image texture in `"uv"` mode
//! composed by `"modulate"` (OBJ's diffuse is `Kd` times the map), `vt`
//! scaled to texels of the image (`v` up, as the image's bottom row is
//! texel row 0). `vn` normals become the faces' `"normals"` (smooth
//! lighting); the record's `"shade"` is copied to every face.

use super::fields::Fields;
use super::obj::{Face, Mesh};
use super::objects::{Instance, Item, ObjectDef};
use super::record::{field_err, short, Record};
use super::StreamError;
use crate::geom::transform::Transform;
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};

pub use super::obj::{MAX_MESH_TRIANGLES, MAX_MESH_VERTICES};

/// The keys of a record's `"mesh"` object.
pub const KEYS: [&str; 1] = ["obj"];

/// The keys of a mesh record that its faces take; the others go to the
/// instance that places it.
const FACE_KEYS: [&str; 3] = ["color", "pattern", "shade"];

/// Keys a mesh record may not have besides its geometry, "uv" and
/// "normals": what another kind of element is made of, and a stripe.
const NOT_MESH_KEYS: [&str; 5] = ["stripe", "instance", "object", "records", "light"];

/// A top-level mesh element: the object of its faces and the instance that
/// places it.
pub fn top_level(index: usize, fields: Fields, base: &Path) -> Result<[Item; 2], StreamError> {
    let name = format!("mesh {index}");
    let mut files = Vec::new();
    let items = faces(index, &fields, base, &mut files)?;
    let def = ObjectDef {
        index,
        name: name.clone(),
        items,
        files,
        fields: Fields::from(Map::from_iter([
            ("object".to_string(), json!(name)),
            ("records".to_string(), json!([])),
        ])),
    };
    let transform = fields
        .get("transform")
        .map(Transform::from_json)
        .transpose()
        .map_err(|e| field_err(index, format!("mesh: {e}")))?
        .unwrap_or_default();
    let mut inst = Fields::new();
    inst.insert("instance", json!(name));
    for (k, v) in fields.iter() {
        if k != "mesh" && !FACE_KEYS.contains(&k) {
            inst.insert(k, v.clone());
        }
    }
    Ok([
        Item::Object(def),
        Item::Instance(Instance {
            index,
            object: name,
            transform,
            fields: inst,
        }),
    ])
}

/// The face records of a mesh record (`fields`, element `index`), the OBJ
/// file resolved against `base`; the OBJ and MTL files read are added to
/// `files` (once each).
pub fn faces(
    index: usize,
    fields: &Fields,
    base: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<Vec<Item>, StreamError> {
    let e = |m: String| field_err(index, m);
    let spec = fields["mesh"].as_object().ok_or_else(|| {
        e(format!(
            "mesh: expected {{\"obj\": FILE}}, found {}",
            short(&fields["mesh"])
        ))
    })?;
    if let Some(k) = spec.keys().find(|k| !KEYS.contains(&k.as_str())) {
        return Err(e(format!("mesh.{k}: unknown key: expected obj")));
    }
    let file = spec
        .get("obj")
        .and_then(Value::as_str)
        .ok_or_else(|| e("mesh.obj: expected the path of a Wavefront OBJ file".into()))?;
    if let Some(k) = super::record::GEOMETRY_KEYS
        .iter()
        .find(|k| fields.contains_key(k))
    {
        return Err(e(format!(
            "mesh: a mesh is its own geometry, found \"{k}\" beside it"
        )));
    }
    if fields.contains_key("uv") || fields.contains_key("normals") {
        return Err(e(
            "mesh: \"uv\" and \"normals\" come from the OBJ file's vt and vn".into(),
        ));
    }
    // Kept as unknown fields, these did nothing (a stripe map named there
    // was never opened), and a mesh's "instance" replaced the instance
    // polyfill3 writes for it: the two tools drew different scenes (a
    // review of the hostile-input fixes).
    if let Some(k) = NOT_MESH_KEYS.iter().find(|k| fields.contains_key(k)) {
        return Err(e(format!(
            "mesh: a mesh takes no \"{k}\": it would be dropped (its faces take \"color\", \
             \"pattern\" and \"shade\", and a top-level mesh \"transform\")"
        )));
    }
    let path = super::resolve(base, file);
    let mesh = Mesh::read_file(&path).map_err(|o| e(format!("mesh.obj: {o}")))?;
    for f in &mesh.files {
        if !files.contains(f) {
            files.push(f.clone());
        }
    }
    let own_pattern = fields.get("pattern").cloned();
    // The record's pattern's size, for "uv" mode: read once.
    let own_size = match &own_pattern {
        Some(p) if p.get("mode").and_then(Value::as_str) == Some("uv") => {
            let f = p
                .get("file")
                .and_then(Value::as_str)
                .ok_or_else(|| e("mesh: pattern.file is missing".into()))?;
            Some(
                texture_size(&super::resolve(base, f))
                    .map_err(|m| e(format!("pattern.file: {m}")))?,
            )
        }
        _ => None,
    };
    let record_colour = fields.get("color").cloned();
    let shade = fields.get("shade").cloned();
    let mut sizes: Vec<Option<(u32, u32)>> = vec![None; mesh.materials.len()];
    let mut out = Vec::new();
    for face in &mesh.faces {
        let material = face.material.map(|m| &mesh.materials[m]);
        let mut colour = match material.and_then(|m| m.kd) {
            Some(kd) => json!(crate::color::Rgb8::from_linear(kd.map(|c| c as f32)).0),
            None => record_colour.clone().unwrap_or(json!([255, 255, 255])),
        };
        // The texture and the size its texel coordinates scale to.
        let (pattern, size) = match (&own_pattern, material.and_then(|m| m.map_kd.as_ref())) {
            (Some(p), _) => (Some(p.clone()), own_size),
            (None, Some(map)) => {
                let k = face.material.expect("a material's map");
                if sizes[k].is_none() {
                    sizes[k] = Some(texture_size(map).map_err(|m| {
                        let face_at = format!("{}:{}", path.display(), face.line);
                        e(match material.and_then(|m| m.map_kd_at.as_ref()) {
                            Some((mtl, line)) => format!(
                                "mesh.obj: {}:{line}: map_Kd: {m} (for the face at {face_at})",
                                mtl.display()
                            ),
                            // A material made by hand, not read from an .mtl.
                            None => format!("mesh.obj: {face_at}: map_Kd: {m}"),
                        })
                    })?);
                }
                let file = absolute(map);
                if material.and_then(|m| m.kd).is_none() {
                    colour = json!([255, 255, 255]);
                }
                (
                    Some(json!({"file": file, "mode": "uv", "compose": "modulate"})),
                    sizes[k],
                )
            }
            (None, None) => (None, None),
        };
        for tri in fan(face, &mesh) {
            let mut f = Fields::new();
            let p = |i: usize| mesh.positions[face.corners[i].v];
            f.insert(
                "vertices",
                json!(tri.iter().map(|&i| p(i).to_array()).collect::<Vec<_>>()),
            );
            f.insert("color", colour.clone());
            if let Some(pat) = &pattern {
                f.insert("pattern", pat.clone());
                if let Some((w, h)) = size {
                    let uv: Option<Vec<[f64; 2]>> = tri
                        .iter()
                        .map(|&i| {
                            face.corners[i].vt.map(|t| {
                                let [u, v] = mesh.texcoords[t];
                                [u * w as f64, v * h as f64]
                            })
                        })
                        .collect();
                    // Said of the vt the user wrote, before the texels it
                    // scales to overflow (1e306 x 1024 was "null").
                    let far = tri.iter().find_map(|&i| {
                        let t = face.corners[i].vt?;
                        let [u, v] = mesh.texcoords[t];
                        let texels = (u * w as f64).abs().max((v * h as f64).abs());
                        (texels.is_nan() || texels > super::record::MAX_UV).then_some([u, v])
                    });
                    if let Some([u, v]) = far {
                        return Err(e(format!(
                            "mesh.obj: {}:{}: f: vt {u} {v}, times the texture's {w}x{h} \
                             texels, is beyond ±{:e} texels (the texture map's arithmetic \
                             would overflow)",
                            path.display(),
                            face.line,
                            super::record::MAX_UV
                        )));
                    }
                    if let Some(uv) = uv {
                        f.insert("uv", json!(uv));
                    }
                }
            }
            let normals: Option<Vec<[f64; 3]>> = tri
                .iter()
                .map(|&i| face.corners[i].vn.map(|n| mesh.normals[n].to_array()))
                .collect();
            if let Some(n) = normals {
                f.insert("normals", json!(n));
            }
            if let Some(s) = &shade {
                f.insert("shade", s.clone());
            }
            let rec = Record::from_fields(index, f).map_err(|err| {
                e(format!(
                    "mesh.obj: {}:{}: {}",
                    path.display(),
                    face.line,
                    err.message
                ))
            })?;
            out.push(Item::Record(rec));
        }
    }
    Ok(out)
}

/// The triangles of a face's fan from its first corner (indices into its
/// corners), those with no area left out.
fn fan(face: &Face, mesh: &Mesh) -> Vec<[usize; 3]> {
    let p = |i: usize| mesh.positions[face.corners[i].v];
    (1..face.corners.len() - 1)
        .map(|i| [0, i, i + 1])
        .filter(|&[a, b, c]| (p(b) - p(a)).cross(p(c) - p(a)).length() > 0.0)
        .collect()
}

/// The width and height of the texture at `path`: an image's from its
/// header, a `.pat`'s side.
fn texture_size(path: &Path) -> Result<(u32, u32), String> {
    let name = path.display().to_string();
    let opened = crate::io::open_path(path).map_err(|err| format!("{name}: {err}"))?;
    if crate::io::is_image(&opened.start) {
        let bytes = opened.read_all().map_err(|err| format!("{name}: {err}"))?;
        crate::io::texture_size(&bytes, &name).map_err(|err| err.to_string())
    } else {
        // Read as a stream: a pattern may be larger than a file read whole.
        let p = crate::pat::Pattern::read_from(&mut opened.into_reader(), &name)
            .map_err(|err| err.to_string())?;
        Ok((p.size(), p.size()))
    }
}

/// A texture path as a record carries it: absolute, since the faces may be
/// read elsewhere than the OBJ's directory (polyfill3's output).
fn absolute(p: &Path) -> String {
    std::path::absolute(p)
        .unwrap_or_else(|_| PathBuf::from(p))
        .display()
        .to_string()
}
