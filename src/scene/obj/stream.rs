//! The OBJ text as tobj reads it: each source line checked and handed on in a form tobj
//! cannot misread ([`ObjStream`]).

use super::ObjError;

/// The OBJ text as tobj reads it: every source line checked, then handed on in a form tobj
/// cannot misread or refuse without a line: `v x y z` (w divided out, vertex colours dropped),
/// `f` with absolute, checked vertex indices only, `mtllib`/`usemtl` with their names, and
/// nothing else (comments, texture coordinates, normals, groups, polylines, points and
/// free-form geometry are left out). A problem stops the stream with an I/O error and is kept
/// in `error`, with its file and line.
pub(super) struct ObjStream<'a> {
    name: &'a str,
    source: std::iter::Enumerate<std::str::Lines<'a>>,
    /// The current line as handed on, and how much of it tobj consumed.
    line: String,
    consumed: usize,
    /// The 1-based number of the source line last read.
    pub(super) line_number: usize,
    vertices: u64,
    texcoords: u64,
    normals: u64,
    /// The material names `usemtl` asked for, to warn about those no library defines.
    pub(super) used_materials: std::collections::BTreeSet<String>,
    /// The material libraries `mtllib` named so far.
    libraries: std::collections::HashSet<String>,
    /// The source line of each triangle handed on, in order (a polygon's fan repeats it).
    pub(super) face_lines: Vec<u32>,
    pub(super) error: Option<ObjError>,
}

impl<'a> ObjStream<'a> {
    pub(super) fn new(name: &'a str, text: &'a str) -> Self {
        Self {
            name,
            source: text.lines().enumerate(),
            line: String::new(),
            consumed: 0,
            line_number: 0,
            vertices: 0,
            texcoords: 0,
            normals: 0,
            used_materials: Default::default(),
            libraries: Default::default(),
            face_lines: Vec::new(),
            error: None,
        }
    }

    /// Writes the form tobj reads of one source line into `self.line` (nothing if tobj need
    /// not see it).
    fn translate(&mut self, source: &str) -> Result<(), String> {
        use std::fmt::Write;
        // `#` starts a comment wherever it is; TABs are whitespace like spaces.
        let statement = source.split('#').next().unwrap_or_default();
        // (The file's first one is skipped: one elsewhere would hide its line's keyword.)
        if statement.contains('\u{feff}') {
            return Err("a byte-order mark (U+FEFF) past the file's start".into());
        }
        let mut words = statement.split_whitespace();
        let Some(keyword) = words.next() else {
            return Ok(());
        };
        let out = &mut self.line;
        let (vertices, texcoords, normals) = (self.vertices, self.texcoords, self.normals);
        match keyword {
            "v" => {
                let numbers: Vec<&str> = words.collect();
                let p = vertex(&numbers)?;
                self.vertices += 1;
                if numbers.len() == 4 {
                    let _ = writeln!(out, "v {} {} {}", p[0], p[1], p[2]);
                } else {
                    // The words as written: tobj reads them as f32 just as `vertex` did.
                    let _ = writeln!(out, "v {} {} {}", numbers[0], numbers[1], numbers[2]);
                }
            }
            "vt" => self.texcoords += 1,
            "vn" => self.normals += 1,
            "f" => {
                let refs: Vec<&str> = words.collect();
                if refs.len() < 3 {
                    return Err(format!(
                        "face needs at least 3 vertices, found {}",
                        refs.len()
                    ));
                }
                let line = u32::try_from(self.line_number).unwrap_or(u32::MAX);
                self.face_lines
                    .extend(std::iter::repeat_n(line, refs.len() - 2));
                out.push('f');
                for r in refs {
                    let v = face_vertex(r, vertices, texcoords, normals)
                        .map_err(|m| format!("face '{r}': {m}"))?;
                    let _ = write!(out, " {v}");
                }
                out.push('\n');
            }
            "mtllib" | "usemtl" => {
                let rest = statement.trim_start()[keyword.len()..].trim();
                if rest.is_empty() {
                    return Err(format!("{keyword} needs a name"));
                }
                // A library named again would add its materials again: it is passed on once.
                if keyword == "mtllib" && !self.libraries.insert(rest.to_string()) {
                    return Ok(());
                }
                let _ = writeln!(out, "{keyword} {rest}");
                if keyword == "usemtl" && !self.used_materials.contains(rest) {
                    self.used_materials.insert(rest.to_string());
                }
            }
            _ => {}
        }
        Ok(())
    }
}

impl std::io::Read for ObjStream<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        use std::io::BufRead;
        let available = self.fill_buf()?;
        let n = available.len().min(out.len());
        out[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl std::io::BufRead for ObjStream<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        while self.consumed == self.line.len() {
            self.line.clear();
            self.consumed = 0;
            let Some((i, source)) = self.source.next() else {
                break;
            };
            self.line_number = i + 1;
            if let Err(message) = self.translate(source) {
                self.error = Some(ObjError::Line {
                    file: self.name.to_string(),
                    line: self.line_number,
                    message,
                });
                self.line.clear();
                return Err(std::io::Error::other("OBJ line refused"));
            }
        }
        Ok(&self.line.as_bytes()[self.consumed..])
    }

    fn consume(&mut self, n: usize) {
        self.consumed = (self.consumed + n).min(self.line.len());
    }
}

/// A `v` statement's position: `x y z` (read straight in f32, correctly rounded), `x y z w`
/// (divided by w in f64, then rounded once to f32) or `x y z r g b` (the colour is not used).
/// Every result is a finite f32.
fn vertex(numbers: &[&str]) -> Result<[f32; 3], String> {
    fn number<T: std::str::FromStr + Into<f64> + Copy>(w: &str) -> Result<T, String> {
        match w.parse::<T>() {
            Ok(x) if x.into().is_finite() => Ok(x),
            Ok(_) => Err(format!("coordinate '{w}' is not a finite f32")),
            Err(_) => Err(format!("coordinate '{w}' is not a number")),
        }
    }
    let mut p = [0f32; 3];
    match numbers.len() {
        3 | 6 => {
            for (c, w) in p.iter_mut().zip(numbers) {
                *c = number::<f32>(w)?;
            }
            if let Some(w) = numbers[3..].iter().find(|w| w.parse::<f32>().is_err()) {
                return Err(format!("colour component '{w}' is not a number"));
            }
        }
        4 => {
            let w = number::<f32>(numbers[3])? as f64;
            if w == 0.0 {
                // (`1e-300` is not 0, but rounds to it in f32: "w is 0" named no such w.)
                let digits = numbers[3].split(['e', 'E']).next().unwrap_or_default();
                let zero = match digits.bytes().any(|b| (b'1'..=b'9').contains(&b)) {
                    true => format!("w = {} rounds to 0 in f32", numbers[3]),
                    false => "the weight w is 0".to_string(),
                };
                return Err(format!("{zero}: x/w, y/w, z/w are not defined"));
            }
            for (c, s) in p.iter_mut().zip(numbers) {
                let q = number::<f32>(s)? as f64 / w;
                *c = q as f32;
                if !c.is_finite() {
                    return Err(format!(
                        "coordinate {s} divided by w = {} is {q:e}, beyond f32",
                        numbers[3]
                    ));
                }
            }
        }
        n => {
            return Err(format!(
                "vertex takes 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b), found {n}"
            ))
        }
    }
    Ok(p)
}

/// The absolute 1-based vertex index of one face reference `v`, `v/vt`, `v//vn` or `v/vt/vn`,
/// every index in it checked against the counts defined so far.
fn face_vertex(word: &str, vertices: u64, texcoords: u64, normals: u64) -> Result<u64, String> {
    let mut parts = word.split('/');
    let mut vertex = 0;
    for (k, count, what) in [
        (0, vertices, ("vertex", "vertices")),
        (1, texcoords, ("texture", "texture coordinates")),
        (2, normals, ("normal", "normals")),
    ] {
        let Some(part) = parts.next() else { break };
        if part.is_empty() && k > 0 {
            continue;
        }
        let index = resolve_index(part, count, what)?;
        if k == 0 {
            vertex = index;
        }
    }
    if parts.next().is_some() {
        return Err("more than 3 '/'-separated indices".into());
    }
    Ok(vertex)
}

/// An OBJ index (1-based, or negative counting back from the last of `count` defined so far)
/// as an absolute 1-based index; any integer is handled without overflow.
fn resolve_index(word: &str, count: u64, (what, plural): (&str, &str)) -> Result<u64, String> {
    let digits = word.strip_prefix(['-', '+']).unwrap_or(word);
    let idx: i64 = match word.parse() {
        Ok(idx) => idx,
        // Beyond i64 is beyond any count.
        Err(_) if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) => 0,
        Err(_) => return Err(format!("{what} index '{word}' is not an integer")),
    };
    let back = idx.unsigned_abs();
    match idx {
        1.. if back <= count => Ok(back),
        ..=-1 if back <= count => Ok(count - back + 1),
        _ => Err(format!(
            "{what} index {word} is out of range ({count} {plural} defined so far; OBJ indices \
             start at 1)"
        )),
    }
}
