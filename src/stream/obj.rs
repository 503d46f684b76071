//! Wavefront OBJ meshes and their MTL materials, read for the stream's
//! `{"mesh": {"obj": FILE}}` records ([`super::mesh`]).
//!
//! What is read: `v` (positions; a fourth `w` only as 1, and vertex
//! colours `x y z r g b` checked and not drawn: `position`), `vt` (texture
//! coordinates, `u v`, a third ignored), `vn` (normals), `f` (faces of any
//! number of vertices, each `v`, `v/vt`, `v//vn` or `v/vt/vn`, indices from
//! 1 or negative from the end), `mtllib` (one file whose name may hold
//! spaces, or several) and `usemtl`; from a `.mtl`, `newmtl`, `Kd` and
//! `map_Kd` (its options, then its file: `texture_file`). Every other
//! statement (`o`, `g`, `s`, `l`, `Ka`, `Ks`, `Ns`, `illum`, ...) is
//! skipped, as OBJ readers do. Errors
//! name the file and the line. The file is read whole but bounded
//! ([`crate::io::read_path`]: a regular file of at most
//! [`crate::io::MAX_NAMED_FILE_BYTES`]), and everything kept is a fixed
//! size per statement read, so memory is bounded by the file's size.

use crate::text::{BOM, BOM_NAMED};
use glam::DVec3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One corner of a face: 0-based indices into the mesh's arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Corner {
    /// Into [`Mesh::positions`].
    pub v: usize,
    /// Into [`Mesh::texcoords`].
    pub vt: Option<usize>,
    /// Into [`Mesh::normals`].
    pub vn: Option<usize>,
}

/// A face: its corners in order (counter-clockwise seen from its front, as
/// OBJ has them) and the material in effect.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// At least three corners.
    pub corners: Vec<Corner>,
    /// Into [`Mesh::materials`], from the last `usemtl`.
    pub material: Option<usize>,
    /// The line the face is on, for messages.
    pub line: usize,
}

/// The most triangles one mesh may make. Each becomes a record kept until
/// the scene is read, then a drawable polygon: measured 2.1 KB of peak
/// memory per triangle (`scene-render` on a 180,000-triangle grid mesh:
/// 390 MB on 2026-11-27, 438 MB before the scene's parts shrank), so the
/// limit keeps one model near 2.1 GB. Checked as the `f` lines are
/// read, so a file of more stops there: a 64 MiB file of 8 million
/// triangles took 1.8 GB and 11.5 s to be refused after reading it whole.
pub const MAX_MESH_TRIANGLES: u64 = 1_000_000;

/// The most `v`, `vt` or `vn` statements one mesh may have: three per
/// triangle of [`MAX_MESH_TRIANGLES`], as many as its faces can use.
pub const MAX_MESH_VERTICES: usize = 3_000_000;

/// A material of an `.mtl` file.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Material {
    /// Its `newmtl` name.
    pub name: String,
    /// `Kd r g b`: the diffuse colour, linear reflectance 0..1.
    pub kd: Option<[f64; 3]>,
    /// `map_Kd [OPTIONS] FILE`: the diffuse texture, resolved against the
    /// `.mtl`'s directory (`texture_file`).
    pub map_kd: Option<PathBuf>,
    /// Where that `map_Kd` is: its `.mtl` file and line, which an error
    /// reading the texture names (it named the first face using it).
    pub map_kd_at: Option<(PathBuf, usize)>,
}

/// An OBJ file read.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    /// `v` statements.
    pub positions: Vec<DVec3>,
    /// `vt` statements, `[u, v]`, v up.
    pub texcoords: Vec<[f64; 2]>,
    /// `vn` statements.
    pub normals: Vec<DVec3>,
    /// `f` statements.
    pub faces: Vec<Face>,
    /// The materials of its `mtllib` files, in the order defined.
    pub materials: Vec<Material>,
    /// The files read to make it: the OBJ file ([`Mesh::read_file`]'s) and
    /// its `mtllib` files, resolved, in the order read. A tool that writes
    /// must not replace them, and a make rule depends on them.
    pub files: Vec<PathBuf>,
}

/// Why an OBJ or MTL file cannot be used: the file, the line (0 for the file
/// as a whole) and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {message}", file.display(), if *line > 0 { format!(":{line}") } else { String::new() })]
pub struct ObjError {
    /// The file, as resolved.
    pub file: PathBuf,
    /// 1-based line, or 0.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl ObjError {
    /// The error `message` at `line` of `file`: OBJ and MTL reading both
    /// name the place this way.
    fn at(file: &Path, line: usize, message: String) -> ObjError {
        ObjError {
            file: file.to_path_buf(),
            line,
            message,
        }
    }
}

/// `bytes` of an OBJ or MTL file (`format`) as text: UTF-8.
fn text_of<'a>(bytes: &'a [u8], path: &Path, format: &str) -> Result<&'a str, ObjError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        ObjError::at(
            path,
            0,
            format!("not UTF-8 text ({e}): not an {format} file"),
        )
    })?;
    Ok(text)
}

/// An error if the statement at `line` begins with a byte-order mark,
/// which made its keyword `\u{feff}v` and so skipped it as an unknown
/// statement: at the start of a file, or of one joined after another (a
/// hostile-input review, then a review of its fix).
fn no_mark(path: &Path, line: usize, key: &str, format: &str) -> Result<(), ObjError> {
    if key.starts_with(BOM) {
        return Err(ObjError::at(
            path,
            line,
            format!("{BOM_NAMED} begins the line: save the {format} file without one"),
        ));
    }
    Ok(())
}

/// The statements of OBJ or MTL text, one a line that has one: its line
/// number (from 1), the line without its comment, its keyword and the
/// words after it. The two formats share this syntax.
fn statements(text: &str) -> impl Iterator<Item = (usize, &str, &str, Vec<&str>)> {
    crate::text::lines(text).enumerate().filter_map(|(i, raw)| {
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let key = words.next()?;
        Some((i + 1, line, key, words.collect()))
    })
}

impl Mesh {
    /// Reads the OBJ file at `path` and the `.mtl` files it names (resolved
    /// against its directory).
    pub fn read_file(path: &Path) -> Result<Mesh, ObjError> {
        let bytes = crate::io::read_path(path).map_err(|e| ObjError::at(path, 0, e.to_string()))?;
        let mut mesh = Mesh::parse(&bytes, path, &mut |p| crate::io::read_path(p))?;
        mesh.files.insert(0, path.to_path_buf());
        Ok(mesh)
    }

    /// Parses OBJ text `bytes` of file `path`; `read` reads an `.mtl` (an
    /// error of kind [`std::io::ErrorKind::NotFound`] says there is no such
    /// file, which `mtllib` takes as a sign of several names).
    pub fn parse(
        bytes: &[u8],
        path: &Path,
        read: &mut dyn FnMut(&Path) -> std::io::Result<Vec<u8>>,
    ) -> Result<Mesh, ObjError> {
        let err = |line: usize, message: String| ObjError::at(path, line, message);
        let text = text_of(bytes, path, "OBJ")?;
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut mesh = Mesh::default();
        let mut by_name: HashMap<String, usize> = HashMap::new();
        let mut current = None;
        let mut triangles = 0u64;
        for (n, line, key, rest) in statements(text) {
            no_mark(path, n, key, "OBJ")?;
            let most = || {
                mesh.positions
                    .len()
                    .max(mesh.texcoords.len())
                    .max(mesh.normals.len())
            };
            if matches!(key, "v" | "vt" | "vn") && most() >= MAX_MESH_VERTICES {
                return Err(err(
                    n,
                    format!("{key}: more than {MAX_MESH_VERTICES} of one kind, over what a mesh of {MAX_MESH_TRIANGLES} triangles can use"),
                ));
            }
            match key {
                "v" => {
                    mesh.positions.push(position(&rest).map_err(|m| err(n, m))?);
                }
                "vt" => {
                    if !(1..=3).contains(&rest.len()) {
                        return Err(err(
                            n,
                            format!("vt: expected u v, found {} numbers", rest.len()),
                        ));
                    }
                    let mut uv = [0.0; 2];
                    for (o, w) in uv.iter_mut().zip(&rest) {
                        *o = number(w, "vt").map_err(|m| err(n, m))?;
                    }
                    mesh.texcoords.push(uv);
                }
                "vn" => {
                    if rest.len() != 3 {
                        return Err(err(
                            n,
                            format!("vn: expected x y z, found {} numbers", rest.len()),
                        ));
                    }
                    let v = DVec3::from_array(numbers::<3>(&rest, "vn").map_err(|m| err(n, m))?);
                    if v.length() == 0.0 {
                        return Err(err(n, "vn: a normal of length 0".into()));
                    }
                    mesh.normals.push(v);
                }
                "f" => {
                    if rest.len() < 3 {
                        return Err(err(
                            n,
                            format!("f: a face needs at least 3 vertices, found {}", rest.len()),
                        ));
                    }
                    let corners = rest
                        .iter()
                        .map(|w| corner(w, &mesh))
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(|m| err(n, m))?;
                    triangles += corners.len() as u64 - 2;
                    if triangles > MAX_MESH_TRIANGLES {
                        return Err(err(
                            n,
                            format!("f: more than {MAX_MESH_TRIANGLES} triangles, over the most one mesh may have"),
                        ));
                    }
                    mesh.faces.push(Face {
                        corners,
                        material: current,
                        line: n,
                    });
                }
                "mtllib" => {
                    if rest.is_empty() {
                        return Err(err(n, "mtllib: expected a file name".into()));
                    }
                    // One file whose name holds spaces (as some exporters
                    // write) if the whole rest of the line names a file;
                    // else the format's several files, one a word, read in
                    // turn. `mtllib a.mtl b.mtl` was one name, "no such file".
                    let whole = line["mtllib".len()..].trim();
                    let whole_path = dir.join(whole);
                    let (paths, mut first) = match read(&whole_path) {
                        Err(e) if rest.len() > 1 && e.kind() == std::io::ErrorKind::NotFound => {
                            (rest.iter().map(|w| dir.join(w)).collect(), None)
                        }
                        r => (vec![whole_path.clone()], Some(r)),
                    };
                    let several = first.is_none();
                    for mtl in paths {
                        let bytes = first.take().unwrap_or_else(|| read(&mtl)).map_err(|m| {
                            let why = if several {
                                format!(
                                    " (one of {} names on the line; no file {} either)",
                                    rest.len(),
                                    whole_path.display()
                                )
                            } else {
                                String::new()
                            };
                            err(n, format!("mtllib {whole}: {}: {m}{why}", mtl.display()))
                        })?;
                        if !mesh.files.contains(&mtl) {
                            mesh.files.push(mtl.clone());
                        }
                        let start = mesh.materials.len();
                        parse_mtl(&bytes, &mtl, &mut mesh.materials)?;
                        for (k, m) in mesh.materials.iter().enumerate().skip(start) {
                            by_name.insert(m.name.clone(), k);
                        }
                    }
                }
                "usemtl" => {
                    let name = line["usemtl".len()..].trim();
                    current = Some(*by_name.get(name).ok_or_else(|| {
                        err(n, format!("usemtl {name}: no material of that name in the mtllib files read so far"))
                    })?);
                }
                _ => {}
            }
        }
        if mesh.faces.is_empty() {
            return Err(err(0, "no faces (\"f\" lines): nothing to draw".into()));
        }
        Ok(mesh)
    }
}

/// One face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` against the arrays read so far.
fn corner(word: &str, mesh: &Mesh) -> Result<Corner, String> {
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!("f: `{word}` is not v, v/vt, v//vn or v/vt/vn"));
    }
    let v = index(parts[0], mesh.positions.len(), ("vertex", "vertices"), word)?;
    let vt = match parts.get(1) {
        None | Some(&"") => None,
        Some(s) => Some(index(
            s,
            mesh.texcoords.len(),
            ("texture coordinate", "texture coordinates"),
            word,
        )?),
    };
    let vn = match parts.get(2) {
        None | Some(&"") => None,
        Some(s) => Some(index(s, mesh.normals.len(), ("normal", "normals"), word)?),
    };
    Ok(Corner { v, vt, vn })
}

/// An OBJ index (1-based, or negative from the end) into an array of `len`.
fn index(s: &str, len: usize, (what, many): (&str, &str), word: &str) -> Result<usize, String> {
    let i: i64 = s
        .parse()
        .map_err(|_| format!("f: `{word}`: `{s}` is not a whole number"))?;
    let k = if i > 0 {
        i - 1
    } else if i < 0 {
        len as i64 + i
    } else {
        return Err(format!("f: `{word}`: index 0: OBJ counts from 1"));
    };
    if k < 0 || k >= len as i64 {
        return Err(format!(
            "f: `{word}`: {what} index {i} out of range: {len} {many} defined before this line"
        ));
    }
    Ok(k as usize)
}

fn number(w: &str, what: &str) -> Result<f64, String> {
    match w.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{what}: `{w}` is not a finite number")),
    }
}

/// A `v` statement's position: `x y z`; `x y z w` with w = 1, the
/// default weight (another w weights a rational curve or surface, which a
/// polygon mesh has not: refused rather than guessed at); or `x y z r g b`,
/// the vertex colours MeshLab and Blender write, checked as numbers and not
/// drawn (a face takes its material's colour: docs/stream-format.md). Both
/// were refused as "expected x y z" (a hostile-input review).
fn position(rest: &[&str]) -> Result<DVec3, String> {
    if !matches!(rest.len(), 3 | 4 | 6) {
        return Err(format!(
            "v: expected x y z (or x y z w, or x y z r g b), found {} numbers",
            rest.len()
        ));
    }
    let mut x = [0.0; 6];
    for (o, w) in x.iter_mut().zip(rest) {
        *o = number(w, "v")?;
    }
    if rest.len() == 4 && x[3] != 1.0 {
        return Err(format!(
            "v: weight w `{}` is not 1: a rational weight belongs to curves and surfaces, \
             not to a polygon mesh",
            rest[3]
        ));
    }
    Ok(DVec3::new(x[0], x[1], x[2]))
}

fn numbers<const N: usize>(words: &[&str], what: &str) -> Result<[f64; N], String> {
    let mut out = [0.0; N];
    for (o, w) in out.iter_mut().zip(words) {
        *o = number(w, what)?;
    }
    Ok(out)
}

/// Adds the materials of MTL text `bytes` (file `path`) to `out`.
fn parse_mtl(bytes: &[u8], path: &Path, out: &mut Vec<Material>) -> Result<(), ObjError> {
    let err = |line: usize, message: String| ObjError::at(path, line, message);
    let text = text_of(bytes, path, "MTL")?;
    let dir = path.parent().unwrap_or(Path::new(""));
    for (n, line, key, rest) in statements(text) {
        no_mark(path, n, key, "MTL")?;
        let here = || err(n, format!("{key}: before any newmtl"));
        match key {
            "newmtl" => out.push(Material {
                name: line["newmtl".len()..].trim().to_string(),
                ..Material::default()
            }),
            "Kd" => {
                if rest.len() != 3 {
                    return Err(err(
                        n,
                        format!("Kd: expected r g b, found {} numbers", rest.len()),
                    ));
                }
                let kd = numbers::<3>(&rest, "Kd").map_err(|m| err(n, m))?;
                if kd.iter().any(|c| !(0.0..=1.0).contains(c)) {
                    return Err(err(
                        n,
                        format!(
                            "Kd: {} {} {}: expected reflectances 0 to 1",
                            kd[0], kd[1], kd[2]
                        ),
                    ));
                }
                out.last_mut().ok_or_else(here)?.kd = Some(kd);
            }
            "map_Kd" => {
                let file = texture_file(&line[key.len()..]).map_err(|m| err(n, m))?;
                let material = out.last_mut().ok_or_else(here)?;
                material.map_kd = Some(dir.join(file));
                material.map_kd_at = Some((path.to_path_buf(), n));
            }
            _ => {}
        }
    }
    Ok(())
}

/// The first word of `s` and what follows it, both without leading white
/// space (the white space [`str::split_whitespace`] splits on).
fn first_word(s: &str) -> (&str, &str) {
    let s = s.trim_start();
    let end = s.find(char::is_whitespace).unwrap_or(s.len());
    (&s[..end], s[end..].trim_start())
}

/// The next word of `*s`, moving past it, if `fits` takes it.
fn next_if<'a>(s: &mut &'a str, fits: fn(&str) -> bool) -> Option<&'a str> {
    let (w, rest) = first_word(s);
    if w.is_empty() || !fits(w) {
        return None;
    }
    *s = rest;
    Some(w)
}

/// The file of a `map_Kd` statement whose text after the keyword is
/// `after`: the rest of the line once the MTL options are read, spaces
/// inside kept and the ends trimmed (`map_Kd my tex.png` is `my tex.png`;
/// the last word was taken, so a file `tex.png` was drawn instead). Each
/// option is read with its arity: `-blendu`, `-blendv`, `-clamp`, `-cc` on
/// or off; `-o`, `-s`, `-t` one to three numbers; `-mm` two; `-boost`,
/// `-bm`, `-texres` one; `-imfchan` r, g, b, m, l or z; `-type` a word.
/// Those that leave this renderer's picture as it is are accepted:
/// `-blendu`, `-blendv`, `-clamp off`, `-cc off`, and `-o`, `-s`, `-t` and
/// `-mm` at their identity (`-o 0 0`, `-s 1 1`, `-t 0 0`, `-mm 0 1`; a
/// third number is a 3D texture's depth, which an image has not). Any other
/// is refused, naming the option and its values: they were skipped, so the
/// texture was drawn unshifted, unscaled, unclamped with status 0. `-o` and
/// `-s` are not applied to the `vt` because the format does not pin their
/// direction: its text shifts the map's origin and expands the pattern
/// (`uv - o`, `uv / s`), common readers such as three.js's multiply and add
/// (`uv * s + o`). An unknown option is refused, as is a missing file. The
/// error is the message, without the file and line.
fn texture_file(after: &str) -> Result<&str, String> {
    fn number_word(w: &str) -> bool {
        w.parse::<f64>().is_ok()
    }
    let mut s = after.trim_start();
    loop {
        let (option, rest) = first_word(s);
        if !option.starts_with('-') {
            break;
        }
        s = rest;
        // What the option takes: how many words, which, and whether numbers.
        struct Takes {
            fewest: usize,
            most: usize,
            fits: fn(&str) -> bool,
            what: &'static str,
            numeric: bool,
        }
        let word = |fits: fn(&str) -> bool, what| Takes {
            fewest: 1,
            most: 1,
            fits,
            what,
            numeric: false,
        };
        let of_numbers = |fewest, most, what| Takes {
            fewest,
            most,
            fits: number_word,
            what,
            numeric: true,
        };
        let Takes {
            fewest,
            most,
            fits,
            what,
            numeric,
        } = match option {
            "-blendu" | "-blendv" | "-clamp" | "-cc" => {
                word(|w| matches!(w, "on" | "off"), "on or off")
            }
            "-imfchan" => word(
                |w| matches!(w, "r" | "g" | "b" | "m" | "l" | "z"),
                "r, g, b, m, l or z",
            ),
            "-type" => word(|w| !w.starts_with('-'), "a type"),
            "-boost" | "-bm" | "-texres" => of_numbers(1, 1, "a number"),
            "-mm" => of_numbers(2, 2, "two numbers, base and gain"),
            "-o" | "-s" | "-t" => of_numbers(1, 3, "1 to 3 numbers"),
            _ => {
                return Err(format!(
                    "map_Kd: unknown option `{option}` (the options are -blendu, -blendv, \
                     -boost, -mm, -o, -s, -t, -texres, -clamp, -cc, -bm, -imfchan and \
                     -type; a file name may not begin with -)"
                ))
            }
        };
        let mut values = Vec::new();
        while values.len() < most {
            match next_if(&mut s, fits) {
                Some(w) => values.push(w),
                None => break,
            }
        }
        if values.len() < fewest {
            let found = match first_word(s).0 {
                "" => "the end of the line".to_string(),
                w => format!("`{w}`"),
            };
            return Err(format!("map_Kd: {option}: expected {what}, found {found}"));
        }
        let numbers = if numeric {
            values
                .iter()
                .map(|w| number(w, &format!("map_Kd: {option}")))
                .collect::<Result<Vec<f64>, String>>()?
        } else {
            Vec::new()
        };
        let not_both = |identity: f64| numbers.iter().take(2).any(|&x| x != identity);
        let refused = match option {
            "-blendu" | "-blendv" => None,
            "-clamp" => (values[0] == "on")
                .then_some("clamping (one copy of the texture, where it would repeat)"),
            "-cc" => (values[0] == "on").then_some("colour correction"),
            "-imfchan" => Some("taking one channel of the image"),
            "-type" => Some("a reflection map's type"),
            "-boost" => Some("sharpening the texture's mipmaps"),
            "-bm" => Some("a bump multiplier"),
            "-texres" => Some("resizing the texture"),
            "-mm" => (numbers != [0.0, 1.0]).then_some("a range of values (base and gain)"),
            "-o" => not_both(0.0)
                .then_some("offsetting the texture (apply the offset to the vt coordinates)"),
            "-s" => not_both(1.0)
                .then_some("scaling the texture (apply the scale to the vt coordinates)"),
            _ => not_both(0.0).then_some("turbulence"),
        };
        if let Some(what) = refused {
            return Err(format!(
                "map_Kd: {option} {}: {what} is not implemented, and the texture drawn \
                 without it would not be the picture the file describes",
                values.join(" ")
            ));
        }
    }
    match s.trim() {
        "" => Err("map_Kd: expected a file name".into()),
        file => Ok(file),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn not_found() -> std::io::Error {
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "No such file or directory (os error 2)",
        )
    }

    /// `obj` as `m/x.obj`, beside the `.mtl` files `files` (name, text).
    fn parse_with(obj: &str, files: &[(&str, &str)]) -> Result<Mesh, String> {
        Mesh::parse(obj.as_bytes(), Path::new("m/x.obj"), &mut |p| {
            files
                .iter()
                .find(|(name, _)| p == Path::new("m").join(name))
                .map(|(_, text)| text.as_bytes().to_vec())
                .ok_or_else(not_found)
        })
        .map_err(|e| e.to_string())
    }

    fn parse(obj: &str, mtl: &str) -> Result<Mesh, String> {
        parse_with(obj, &[("x.mtl", mtl)])
    }

    /// The file a `map_Kd` line names, read from `m/x.mtl`.
    fn map_kd(line: &str) -> Result<PathBuf, String> {
        let m = parse(
            "mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            &format!("newmtl t\n{line}\n"),
        )?;
        Ok(m.materials[0].map_kd.clone().unwrap())
    }

    /// The file is the rest of the line after the options, spaces inside
    /// kept: `map_Kd my tex.png` drew `tex.png`, a file of that name being
    /// there (a hostile-input review).
    #[test]
    fn map_kd_names_the_rest_of_the_line_after_its_options() {
        for (line, file) in [
            ("map_Kd my tex.png", "m/my tex.png"),
            ("map_Kd   my  tex.png  ", "m/my  tex.png"),
            ("map_Kd\tsub/a b\tc.png", "m/sub/a b\tc.png"),
            ("map_Kd -s 1 1 1 wall.png", "m/wall.png"),
            (
                "map_Kd -blendu off -blendv on -o 0 0 0.5 -s 1 1 -t 0 0 0 -mm 0 1 \
                 -clamp off -cc off my tex.png",
                "m/my tex.png",
            ),
            ("map_Kd -o -0 my tex.png", "m/my tex.png"),
            ("map_Kd -s 1 1 1 2.5x.png", "m/2.5x.png"),
        ] {
            assert_eq!(map_kd(line), Ok(PathBuf::from(file)), "{line:?}");
        }
    }

    /// Options that would change the picture were skipped: `-o 0.5 0.5 0
    /// -s 0.5 0.5 1` drew the texture unshifted and unscaled, status 0.
    #[test]
    fn map_kd_options_not_drawn_are_refused_with_their_values() {
        let not = "is not implemented, and the texture drawn without it would not be the \
                   picture the file describes";
        for (line, needle) in [
            (
                "map_Kd -o 0.5 0.5 0 -s 0.5 0.5 1 x.png",
                format!("m/x.mtl:2: map_Kd: -o 0.5 0.5 0: offsetting the texture (apply the offset to the vt coordinates) {not}"),
            ),
            (
                "map_Kd -s 1 1 1 -s 0.5 0.5 1 my x.png",
                "m/x.mtl:2: map_Kd: -s 0.5 0.5 1: scaling the texture".into(),
            ),
            ("map_Kd -s 2 x.png", "map_Kd: -s 2: scaling".into()),
            ("map_Kd -t 0.1 0 0 x.png", "map_Kd: -t 0.1 0 0: turbulence".into()),
            ("map_Kd -mm 0.2 0.8 x.png", "map_Kd: -mm 0.2 0.8: a range of values".into()),
            ("map_Kd -clamp on x.png", "map_Kd: -clamp on: clamping".into()),
            ("map_Kd -cc on x.png", "map_Kd: -cc on: colour correction".into()),
            ("map_Kd -imfchan l x.png", "map_Kd: -imfchan l: taking one channel".into()),
            ("map_Kd -type sphere x.png", "map_Kd: -type sphere: a reflection map's type".into()),
            ("map_Kd -boost 2 x.png", "map_Kd: -boost 2: sharpening".into()),
            ("map_Kd -bm 1 x.png", "map_Kd: -bm 1: a bump multiplier".into()),
            ("map_Kd -texres 512 x.png", "map_Kd: -texres 512: resizing the texture".into()),
            ("map_Kd -halo x.png", "m/x.mtl:2: map_Kd: unknown option `-halo`".into()),
            ("map_Kd -o x.png", "map_Kd: -o: expected 1 to 3 numbers, found `x.png`".into()),
            ("map_Kd -s", "map_Kd: -s: expected 1 to 3 numbers, found the end of the line".into()),
            ("map_Kd -mm 0 x.png", "map_Kd: -mm: expected two numbers, base and gain, found `x.png`".into()),
            ("map_Kd -blendu yes x.png", "map_Kd: -blendu: expected on or off, found `yes`".into()),
            ("map_Kd -imfchan q x.png", "map_Kd: -imfchan: expected r, g, b, m, l or z".into()),
            ("map_Kd -o inf x.png", "map_Kd: -o: `inf` is not a finite number".into()),
            ("map_Kd -s 1 1 1", "m/x.mtl:2: map_Kd: expected a file name".into()),
            ("map_Kd -clamp off   ", "m/x.mtl:2: map_Kd: expected a file name".into()),
        ] {
            let e = map_kd(line).unwrap_err();
            assert!(e.contains(&needle), "{line:?}: {e}");
        }
    }

    /// `mtllib a.mtl b.mtl` names two files (the format allows several); it
    /// was read as one name, "./a.mtl b.mtl: No such file".
    #[test]
    fn mtllib_reads_each_file_it_names_unless_the_line_names_one() {
        let obj = "mtllib a.mtl  b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
                   usemtl red\nf 1 2 3\nusemtl blue\nf 1 2 3\n";
        let a = ("a.mtl", "newmtl red\nKd 1 0 0\n");
        let b = ("b.mtl", "newmtl blue\nKd 0 0 1\n");
        let m = parse_with(obj, &[a, b]).unwrap();
        assert_eq!(m.materials.len(), 2);
        assert_eq!(m.faces[0].material, Some(0));
        assert_eq!(m.faces[1].material, Some(1));
        assert_eq!(m.materials[1].kd, Some([0.0, 0.0, 1.0]));
        assert_eq!(
            m.files,
            [PathBuf::from("m/a.mtl"), PathBuf::from("m/b.mtl")]
        );
        // A file named by the whole line is that one file, even with files
        // named by its words beside it.
        let both = (
            "a.mtl  b.mtl",
            "newmtl red\nKd 0 1 0\nnewmtl blue\nKd 0 1 0\n",
        );
        let m = parse_with(obj, &[a, b, both]).unwrap();
        assert_eq!(m.materials.len(), 2);
        assert_eq!(m.materials[0].kd, Some([0.0, 1.0, 0.0]));
        assert_eq!(m.files, [PathBuf::from("m/a.mtl  b.mtl")]);
        // One of the words naming no file: that one is named.
        let e = parse_with(obj, &[a]).unwrap_err();
        assert_eq!(
            e,
            "m/x.obj:1: mtllib a.mtl  b.mtl: m/b.mtl: No such file or directory (os error 2) \
             (one of 2 names on the line; no file m/a.mtl  b.mtl either)"
        );
        // The whole line's file there but unreadable: its error, not the words'.
        let e = Mesh::parse(b"mtllib a b\n", Path::new("x.obj"), &mut |p| {
            if p == Path::new("a b") {
                Err(std::io::Error::other("is not a regular file"))
            } else {
                Ok(Vec::new())
            }
        })
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.obj:1: mtllib a b: a b: is not a regular file"
        );
    }

    /// Lines ended by a bare CR (classic Mac OS) are lines: the file was
    /// one line, its first comment hid the rest, and errors said line 1.
    #[test]
    fn a_bare_cr_ends_a_statement() {
        let m = parse(
            "# made on a Mac\rmtllib x.mtl\rv 0 0 0\rv 1 0 0\r\nv 0 1 0\rusemtl red\rf 1 2 3\r",
            "newmtl red\rKd 1 0 0\r",
        )
        .unwrap();
        assert_eq!((m.positions.len(), m.faces.len()), (3, 1));
        assert_eq!(m.materials.len(), 1);
        let e = parse("v 0 0 0\rv 1 0 0\r\rf 1 2 9\r", "").unwrap_err();
        assert!(e.starts_with("m/x.obj:4:"), "{e}");
    }

    #[test]
    fn every_face_form_and_negative_indices() {
        let m = parse(
            "# a quad and a triangle\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n\
             o thing\ng part\ns 1\nusemtl red\nf 1 2 3 4\nusemtl tex\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf -4/-3/-1 -3/-2/-1 -2/-1/-1\n",
            "newmtl red\nKd 1 0 0\nnewmtl tex\nmap_Kd -s 1 1 1 wall.png\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.faces.len(), 4);
        assert_eq!(m.faces[0].corners.len(), 4);
        assert_eq!(m.faces[0].material, Some(0));
        assert_eq!(
            m.faces[1].corners[2],
            Corner {
                v: 2,
                vt: Some(2),
                vn: None
            }
        );
        assert_eq!(
            m.faces[2].corners[0],
            Corner {
                v: 0,
                vt: None,
                vn: Some(0)
            }
        );
        assert_eq!(
            m.faces[3].corners[0],
            Corner {
                v: 0,
                vt: Some(0),
                vn: Some(0)
            }
        );
        assert_eq!(m.materials[0].kd, Some([1.0, 0.0, 0.0]));
        assert_eq!(
            m.materials[1].map_kd.as_deref(),
            Some(Path::new("m/wall.png"))
        );
        assert_eq!(m.faces[3].line, 19);
    }

    #[test]
    fn a_unit_weight_and_vertex_colours_are_read_as_plain_positions() {
        let faces = "f 1 2 3\n";
        let plain = parse(&format!("v 0 0 0\nv 1 0 0\nv 0 1 2.5\n{faces}"), "").unwrap();
        for extra in [
            "v 0 0 0 1\nv 1 0 0 1.0\nv 0 1 2.5 1e0\n",
            "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 2.5 0.2 0.4 0.6\n",
        ] {
            let m = parse(&format!("{extra}{faces}"), "").unwrap();
            assert_eq!(m.positions, plain.positions, "{extra}");
            assert_eq!(m.faces, plain.faces, "{extra}");
        }
    }

    #[test]
    fn bad_input_names_the_file_and_line() {
        for (obj, needle) in [
            (
                "v 0 0 0\nv 1 0 0\nf 1 2 3\n",
                "m/x.obj:3: f: `3`: vertex index 3 out of range: 2 vertices defined",
            ),
            (
                "v 0 0\n",
                "m/x.obj:1: v: expected x y z (or x y z w, or x y z r g b), found 2 numbers",
            ),
            (
                "v 0 0 0 0.5\n",
                "m/x.obj:1: v: weight w `0.5` is not 1: a rational weight belongs to curves \
                 and surfaces, not to a polygon mesh",
            ),
            ("v 0 0 0 1 2\n", "found 5 numbers"),
            (
                "v 0 0 0 1 nan 1\n",
                "m/x.obj:1: v: `nan` is not a finite number",
            ),
            ("v 0 0 NaN\n", "m/x.obj:1: v: `NaN` is not a finite number"),
            (
                "v 0 0 1e999\n",
                "m/x.obj:1: v: `1e999` is not a finite number",
            ),
            (
                "v 0 0 0\nf 1 1\n",
                "m/x.obj:2: f: a face needs at least 3 vertices, found 2",
            ),
            (
                "v 0 0 0\nf 0 1 1\n",
                "m/x.obj:2: f: `0`: index 0: OBJ counts from 1",
            ),
            (
                "v 0 0 0\nf 1 1 99999999999999999999\n",
                "is not a whole number",
            ),
            (
                "v 0 0 0\nf 1/x 1 1\n",
                "m/x.obj:2: f: `1/x`: `x` is not a whole number",
            ),
            ("v 0 0 0\nf -2 1 1\n", "vertex index -2 out of range"),
            (
                "v 0 0 0\nvt 0 0\nf 1/2 1/1 1/1\n",
                "texture coordinate index 2 out of range",
            ),
            ("vn 0 0 0\n", "m/x.obj:1: vn: a normal of length 0"),
            ("v 0 0 0\n", "m/x.obj: no faces"),
            (
                "mtllib other.mtl\n",
                "m/x.obj:1: mtllib other.mtl: m/other.mtl: No such file",
            ),
            (
                "mtllib x.mtl\nusemtl blue\n",
                "m/x.obj:2: usemtl blue: no material of that name",
            ),
            ("f 1/2/3/4 1 1\n", "is not v, v/vt, v//vn or v/vt/vn"),
        ] {
            let e = parse(obj, "newmtl red\nKd 1 0 0\n").unwrap_err();
            assert!(e.contains(needle), "{obj:?}: {e}");
        }
        for (mtl, needle) in [
            ("Kd 1 0 0\n", "m/x.mtl:1: Kd: before any newmtl"),
            (
                "newmtl a\nKd 2 0 0\n",
                "m/x.mtl:2: Kd: 2 0 0: expected reflectances 0 to 1",
            ),
            (
                "newmtl a\nmap_Kd\n",
                "m/x.mtl:2: map_Kd: expected a file name",
            ),
        ] {
            let e = parse("mtllib x.mtl\n", mtl).unwrap_err();
            assert!(e.contains(needle), "{mtl:?}: {e}");
        }
        let e =
            Mesh::parse(&[0xff, 0xfe], Path::new("b.obj"), &mut |_| Err(not_found())).unwrap_err();
        assert!(e.to_string().starts_with("b.obj: not UTF-8 text"), "{e}");
    }

    #[test]
    fn a_byte_order_mark_is_refused_not_read_as_a_statement() {
        // It made the first `v` the unknown statement `\u{feff}v`, so the
        // face below was drawn from the other three vertices.
        let obj = "\u{feff}v 5 5 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let e = parse(obj, "").unwrap_err();
        assert!(
            e.contains("m/x.obj:1: a UTF-8 byte-order mark (bytes EF BB BF) begins the line: save the OBJ file without one"),
            "{e}"
        );
        let e = parse("mtllib x.mtl\n", "\u{feff}newmtl a\nKd 1 0 0\n").unwrap_err();
        assert!(e.contains("m/x.mtl:1: a UTF-8 byte-order mark"), "{e}");
        // Files joined after another: the mark begins a later line.
        let joined = "# exported\n\u{feff}v 5 5 0\nv 0 0 0\nv 10 0 0\nv 0 10 0\nf 1 2 3\n";
        assert!(parse(joined, "")
            .unwrap_err()
            .contains("m/x.obj:2: a UTF-8 byte-order mark"));
        let e = parse(
            "mtllib x.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "newmtl a\n\u{feff}Kd 1 0 0\n",
        )
        .unwrap_err();
        assert!(e.contains("m/x.mtl:2: a UTF-8 byte-order mark"), "{e}");
        // Elsewhere in a line U+FEFF is only an unknown word.
        assert!(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 # \u{feff}\n", "").is_ok());
    }
}
