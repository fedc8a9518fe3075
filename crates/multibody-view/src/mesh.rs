//! Triangle meshes read from files (ShapefileVisualizer): STL (ASCII and
//! binary), OBJ and Collada (`.dae`), parsed by the `mesh-loader` crate and
//! made ready to draw here: welded vertices, a normal per vertex, and the
//! bounds.
//!
//! Normals: STL facet normals, OBJ `vn` and Collada normals are used where
//! the file gives them (non-zero); elsewhere each corner gets the
//! area-weighted mean of the normals of the faces at its position that turn
//! less than [`CREASE_DEGREES`] from its own face: curved surfaces look
//! smooth, edges stay sharp.
//!
//! Collada: mesh-loader 0.1 reads the geometry, but composes `<unit meter>`
//! and nested node transforms in the wrong order (a node's translation is
//! not scaled by the unit nor turned by its parents), so we place it
//! ourselves: the unit, the transforms (`matrix`, `translate`, `rotate`,
//! `scale`) of the nodes of the visual scene that instance each geometry,
//! through `instance_node` too, once per instance; a geometry no node
//! instances is not drawn, unless the file has no visual scene at all.
//! `lookat` and `skew` are ignored, and so are materials and textures. A
//! file whose `<up_axis>` says `Y_UP` or `X_UP` is turned so that its up
//! axis becomes z (as ROS tools read robot meshes); `Z_UP`, or none, is
//! taken as written.

use multibody::files::{self, Fifo, OpenError};
use std::collections::HashMap;
use std::path::Path;

/// The most an OBJ file's material library is read of (it is not drawn).
#[cfg(feature = "meshes")]
const MATERIALS_MAX_BYTES: u64 = 16 << 20;

/// Faces that turn less than this from each other share their normals.
pub const CREASE_DEGREES: f64 = 30.0;

/// A mesh ready to draw: positions and normals per vertex, three indices
/// per triangle, in the file's coordinates (metres after Collada's unit).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<f32>,
    pub normals: Vec<f32>,
    pub indices: Vec<u32>,
    /// The corners of the box around the positions (zeros for no triangle).
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl MeshData {
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    pub fn vertices(&self) -> usize {
        self.positions.len() / 3
    }
}

/// The formats read, by the file's extension (any case).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Stl,
    Obj,
    Collada,
}

impl Format {
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(Format::Stl),
            "obj" => Some(Format::Obj),
            "dae" => Some(Format::Collada),
            _ => None,
        }
    }
}

/// Reads the mesh file at `path`; the error says why it cannot be drawn.
/// The file is opened through [`multibody::files`]: a FIFO, a device or a
/// folder is refused as not a regular file (reading a FIFO nobody writes
/// to blocked the page for ever, deaf to SIGTERM).
pub fn load(path: &Path) -> Result<MeshData, String> {
    load_within(path, usize::MAX).map_err(|e| match e {
        LoadError::Triangles(n) => format!("it has {n} triangles"),
        LoadError::Bytes(size) => format!("it holds {size} bytes"),
        LoadError::Unreadable(why) => why,
    })
}

/// Bytes a triangle takes at most in the files read, about: a binary STL
/// 50, an ASCII STL some 250 with long numbers, OBJ and Collada less (they
/// share vertices). A file larger than this many bytes a triangle allowed
/// is refused unread.
pub const MAX_BYTES_PER_TRIANGLE: u64 = 512;

/// Why a mesh file was not read.
#[derive(Clone, Debug, PartialEq)]
pub enum LoadError {
    /// A binary STL whose header gives more triangles than allowed.
    Triangles(usize),
    /// A file of more bytes than the triangles allowed take
    /// ([`MAX_BYTES_PER_TRIANGLE`] each).
    Bytes(u64),
    /// Any other reason, as the end of "the mesh ... is not drawn: ...".
    Unreadable(String),
}

/// Reads the mesh file at `path` if it can hold no more than
/// `most_triangles` triangles: a binary STL's header tells its count, any
/// file's size a bound (a 2 GB STL was read whole, 8.6 GB of memory,
/// before the triangle budget dropped it). Nothing more than the header is
/// read of a file refused.
pub fn load_within(path: &Path, most_triangles: usize) -> Result<MeshData, LoadError> {
    let Some(format) = Format::of(path) else {
        return Err(LoadError::Unreadable("not a mesh file this page reads: use .stl, .obj or .dae".into()));
    };
    let unreadable = |e: &OpenError| LoadError::Unreadable(unreadable(e));
    let opened = files::open(path, Fifo::Refuse).map_err(|e| unreadable(&e))?;
    let (mut file, size) = (opened.file, opened.size.unwrap_or(0));
    let io = |e: std::io::Error| LoadError::Unreadable(format!("cannot read it: {e}"));
    if format == Format::Stl {
        if let Some(count) = binary_stl_triangles(&mut file, size).map_err(io)? {
            if count > most_triangles as u64 {
                return Err(LoadError::Triangles(usize::try_from(count).unwrap_or(usize::MAX)));
            }
        }
    }
    if size > (most_triangles as u64).saturating_mul(MAX_BYTES_PER_TRIANGLE) {
        return Err(LoadError::Bytes(size));
    }
    use std::io::{Read, Seek};
    file.seek(std::io::SeekFrom::Start(0)).map_err(io)?;
    let mut bytes = Vec::with_capacity(size as usize);
    file.read_to_end(&mut bytes).map_err(io)?;
    parse(&bytes, path, format).map_err(LoadError::Unreadable)
}

/// The triangle count of a binary STL, read from its header: an 80-byte
/// title, the count (u32, little-endian), then 50 bytes a triangle; `None`
/// when the file's `size` does not match that layout (ASCII STL).
fn binary_stl_triangles(file: &mut std::fs::File, size: u64) -> std::io::Result<Option<u64>> {
    use std::io::Read;
    if size < 84 {
        return Ok(None);
    }
    let mut header = [0u8; 84];
    file.read_exact(&mut header)?;
    let count = u64::from(u32::from_le_bytes([header[80], header[81], header[82], header[83]]));
    Ok((84 + 50 * count == size).then_some(count))
}

/// Why a mesh file could not be read, as the end of "the mesh ... is not
/// drawn: ...".
fn unreadable(e: &OpenError) -> String {
    match e {
        OpenError::Io(e) if e.kind() == std::io::ErrorKind::NotFound => "no such file".to_string(),
        OpenError::Io(e) => format!("cannot read it: {e}"),
        OpenError::NotAFile(kind) => {
            format!("it is {}, not a regular file; give the path of a mesh file", kind.describe())
        }
        OpenError::NoWriter { waited } => format!("nothing wrote to it in {} s", waited.as_secs()),
        OpenError::TooLarge { limit, .. } => format!("it holds more than {limit} bytes"),
    }
}

/// Parses the bytes of a mesh file of `format`; `path` names it in errors
/// (and finds an OBJ file's material library, which is not needed).
pub fn parse(bytes: &[u8], path: &Path, format: Format) -> Result<MeshData, String> {
    let corners = read_corners(bytes, path, format)?;
    Ok(build(&corners))
}

/// Triangles as loose corners: three positions each, and a normal per
/// corner when the file gives one.
#[derive(Debug, Default)]
struct Corners {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
}

#[cfg(feature = "meshes")]
fn read_corners(bytes: &[u8], path: &Path, format: Format) -> Result<Corners, String> {
    use mesh_loader::Loader;
    // Collada: mesh-loader reads the geometry, placed here by our reading
    // of the units and node transforms (it composes them in the wrong order).
    let placed = match format {
        Format::Collada => Some(collada::place(bytes)?),
        _ => None,
    };
    let bytes = placed.as_ref().map_or(bytes, |p| &p.geometry_only);
    // The parser panics on some malformed files: a bad file is an error
    // about that file, not the end of the run.
    let parsed = std::panic::catch_unwind(|| {
        let loader = Loader::default();
        match format {
            Format::Stl => loader.load_stl_from_slice(bytes, path),
            Format::Collada => loader.load_collada_from_slice(bytes, path),
            // Materials are not drawn: a missing material library is no error.
            Format::Obj => loader.load_obj_from_slice_with_reader(bytes, path, |p: &Path| {
                // Through the safe open too: a FIFO named as the library would block.
                Ok::<_, std::io::Error>(files::read(p, Fifo::Refuse, MATERIALS_MAX_BYTES).unwrap_or_default())
            }),
        }
    });
    let scene = match parsed {
        Ok(Ok(scene)) => scene,
        Ok(Err(e)) => return Err(format!("cannot parse it: {e}")),
        Err(_) => return Err("cannot parse it: the file is malformed".into()),
    };
    let mut out = Corners::default();
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut all_normals = true;
    for mesh in &scene.meshes {
        let identity = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
        let placements: Vec<collada::M4> = match &placed {
            Some(p) => p.instances_of(&mesh.name),
            None => vec![identity],
        };
        let has_normals = mesh.normals.len() == mesh.vertices.len();
        all_normals &= has_normals || placements.is_empty();
        for m in placements {
            let normal_matrix = collada::normal_matrix(&m);
            for face in &mesh.faces {
                let Some(p) = face.iter().map(|&i| mesh.vertices.get(i as usize).copied()).collect::<Option<Vec<_>>>()
                else {
                    return Err("cannot parse it: a face refers to a vertex it does not have".into());
                };
                out.positions.extend(p.iter().map(|v| collada::apply(&m, *v)));
                if has_normals {
                    normals.extend(face.iter().map(|&i| collada::turn(&normal_matrix, mesh.normals[i as usize])));
                }
            }
        }
    }
    if all_normals && normals.len() == out.positions.len() {
        out.normals = Some(normals);
    }
    Ok(out)
}

/// Collada's placement of geometry: `<unit meter>`, `<up_axis>`, and the
/// transforms of the nodes of the visual scene that instance each geometry
/// (`matrix`, `translate`, `rotate`, `scale`, in the order written; nodes
/// reached through `instance_node` too). `lookat` and `skew` are ignored.
#[cfg(feature = "meshes")]
mod collada {
    use std::collections::HashMap;

    /// Row-major 4x4, acting on columns: `p' = M p`.
    pub type M4 = [[f64; 4]; 4];

    const IDENTITY: M4 = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
    const TRANSFORMS: [&str; 6] = ["matrix", "translate", "rotate", "scale", "lookat", "skew"];

    pub struct Placed {
        /// The file with the units and node transforms blanked out, so
        /// that mesh-loader gives each geometry as written.
        pub geometry_only: Vec<u8>,
        /// Geometry id and where an instance of it goes.
        instances: Vec<(String, M4)>,
        /// For a file without a visual scene: every geometry, placed so.
        outer: M4,
    }

    impl Placed {
        pub fn instances_of(&self, geometry: &str) -> Vec<M4> {
            if self.instances.is_empty() {
                return vec![self.outer];
            }
            self.instances.iter().filter(|(g, _)| g == geometry).map(|(_, m)| *m).collect()
        }
    }

    pub fn place(bytes: &[u8]) -> Result<Placed, String> {
        let text =
            std::str::from_utf8(bytes).map_err(|_| "cannot parse it: a Collada file is UTF-8 text".to_string())?;
        let doc = roxmltree::Document::parse(text).map_err(|e| format!("cannot parse it: {e}"))?;
        let root = doc.root_element();
        let mut blank = Vec::new();
        let (mut unit, mut up) = (1.0, String::new());
        if let Some(asset) = child(root, "asset") {
            if let Some(u) = child(asset, "unit") {
                unit = u.attribute("meter").and_then(|m| m.trim().parse::<f64>().ok()).unwrap_or(1.0);
                blank.push(u.range());
            }
            if let Some(a) = child(asset, "up_axis") {
                up = a.text().unwrap_or("").trim().to_ascii_uppercase();
            }
        }
        let turn = match up.as_str() {
            // y up to z up: a quarter turn about x (y -> z, z -> -y).
            "Y_UP" => [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]],
            // x up to z up: a quarter turn about y (x -> z, z -> -x).
            "X_UP" => [[0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]],
            _ => IDENTITY,
        };
        let scale = [[unit, 0.0, 0.0, 0.0], [0.0, unit, 0.0, 0.0], [0.0, 0.0, unit, 0.0], [0.0, 0.0, 0.0, 1.0]];
        let outer = mul(&turn, &scale);

        let mut named: HashMap<&str, roxmltree::Node<'_, '_>> = HashMap::new();
        for n in root.descendants().filter(|n| n.has_tag_name("node")) {
            if let Some(id) = n.attribute("id") {
                named.insert(id, n);
            }
            for t in n.children().filter(|c| TRANSFORMS.iter().any(|name| c.has_tag_name(*name))) {
                blank.push(t.range());
            }
        }
        let scenes: Vec<roxmltree::Node<'_, '_>> =
            root.descendants().filter(|n| n.has_tag_name("visual_scene")).collect();
        let wanted = child(root, "scene")
            .and_then(|s| child(s, "instance_visual_scene"))
            .and_then(|i| i.attribute("url"))
            .map(|u| u.trim_start_matches('#'));
        let scene = scenes.iter().find(|s| wanted.is_some() && s.attribute("id") == wanted).or(scenes.first());
        let mut instances = Vec::new();
        if let Some(scene) = scene {
            for n in scene.children().filter(|c| c.has_tag_name("node")) {
                visit(n, &outer, &named, 0, &mut instances);
            }
        }

        let mut geometry_only = bytes.to_vec();
        for r in blank {
            for b in &mut geometry_only[r] {
                if *b != b'\n' {
                    *b = b' ';
                }
            }
        }
        Ok(Placed { geometry_only, instances, outer })
    }

    fn child<'a, 'i>(n: roxmltree::Node<'a, 'i>, name: &str) -> Option<roxmltree::Node<'a, 'i>> {
        n.children().find(|c| c.has_tag_name(name))
    }

    fn visit(
        node: roxmltree::Node<'_, '_>,
        parent: &M4,
        named: &HashMap<&str, roxmltree::Node<'_, '_>>,
        depth: usize,
        out: &mut Vec<(String, M4)>,
    ) {
        if depth > 64 {
            return;
        }
        let mut world = *parent;
        for t in node.children().filter(|c| c.is_element()) {
            let v: Vec<f64> = t.text().unwrap_or("").split_whitespace().filter_map(|x| x.parse().ok()).collect();
            let local = match (t.tag_name().name(), v.as_slice()) {
                ("matrix", m) if m.len() == 16 => [0, 1, 2, 3].map(|i| [0, 1, 2, 3].map(|j| m[4 * i + j])),
                ("translate", &[x, y, z]) => [[1.0, 0.0, 0.0, x], [0.0, 1.0, 0.0, y], [0.0, 0.0, 1.0, z], IDENTITY[3]],
                ("scale", &[x, y, z]) => [[x, 0.0, 0.0, 0.0], [0.0, y, 0.0, 0.0], [0.0, 0.0, z, 0.0], IDENTITY[3]],
                ("rotate", &[x, y, z, degrees]) => rotation([x, y, z], degrees.to_radians()),
                _ => continue,
            };
            world = mul(&world, &local);
        }
        for c in node.children().filter(|c| c.is_element()) {
            match c.tag_name().name() {
                "instance_geometry" => {
                    if let Some(url) = c.attribute("url") {
                        out.push((url.trim_start_matches('#').to_string(), world));
                    }
                }
                "node" => visit(c, &world, named, depth + 1, out),
                "instance_node" => {
                    if let Some(target) = c.attribute("url").and_then(|u| named.get(u.trim_start_matches('#'))) {
                        visit(*target, &world, named, depth + 1, out);
                    }
                }
                _ => {}
            }
        }
    }

    fn rotation(axis: [f64; 3], angle: f64) -> M4 {
        let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        if n <= 0.0 || n.is_nan() {
            return IDENTITY;
        }
        let [x, y, z] = axis.map(|a| a / n);
        let (s, c) = angle.sin_cos();
        let k = 1.0 - c;
        [
            [c + x * x * k, x * y * k - z * s, x * z * k + y * s, 0.0],
            [y * x * k + z * s, c + y * y * k, y * z * k - x * s, 0.0],
            [z * x * k - y * s, z * y * k + x * s, c + z * z * k, 0.0],
            IDENTITY[3],
        ]
    }

    fn mul(a: &M4, b: &M4) -> M4 {
        [0, 1, 2, 3].map(|i| [0, 1, 2, 3].map(|j| (0..4).map(|k| a[i][k] * b[k][j]).sum()))
    }

    pub fn apply(m: &M4, p: [f32; 3]) -> [f32; 3] {
        let p = p.map(f64::from);
        [0, 1, 2].map(|i| (m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3]) as f32)
    }

    /// The matrix that turns normals as `m` turns surfaces: the cofactors
    /// of its 3x3 part, signed so that a mirror keeps normals outward.
    pub fn normal_matrix(m: &M4) -> [[f64; 3]; 3] {
        let a = |i: usize, j: usize| m[i % 3][j % 3];
        let cof =
            [0, 1, 2].map(|i| [0, 1, 2].map(|j| a(i + 1, j + 1) * a(i + 2, j + 2) - a(i + 1, j + 2) * a(i + 2, j + 1)));
        let det: f64 = (0..3).map(|j| m[0][j] * cof[0][j]).sum();
        let sign = if det < 0.0 { -1.0 } else { 1.0 };
        cof.map(|row| row.map(|x| x * sign))
    }

    pub fn turn(n: &[[f64; 3]; 3], v: [f32; 3]) -> [f32; 3] {
        let v = v.map(f64::from);
        [0, 1, 2].map(|i| (n[i][0] * v[0] + n[i][1] * v[1] + n[i][2] * v[2]) as f32)
    }
}

#[cfg(not(feature = "meshes"))]
fn read_corners(_bytes: &[u8], _path: &Path, _format: Format) -> Result<Corners, String> {
    Err("this build reads no mesh files (multibody-view's `meshes` feature is off)".into())
}

type Key = [u32; 3];

fn key(p: [f32; 3]) -> Key {
    // +0 and -0 are one position.
    p.map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

/// Welds the corners into shared vertices, with a normal per vertex.
fn build(corners: &Corners) -> MeshData {
    // Faces with a finite, non-zero area.
    let faces: Vec<usize> = (0..corners.positions.len() / 3)
        .filter(|&f| {
            let p = &corners.positions[3 * f..3 * f + 3];
            p.iter().flatten().all(|x| x.is_finite()) && norm(face_normal(p)) > 0.0
        })
        .collect();
    let mut out = MeshData::default();
    if faces.is_empty() {
        return out;
    }

    // Positions welded: each corner's position number.
    let mut position_of: HashMap<Key, u32> = HashMap::new();
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut corner_position = Vec::with_capacity(faces.len() * 3);
    for &f in &faces {
        for p in &corners.positions[3 * f..3 * f + 3] {
            let next = positions.len() as u32;
            let i = *position_of.entry(key(*p)).or_insert(next);
            if i == next {
                positions.push(*p);
            }
            corner_position.push(i);
        }
    }

    // Faces at each position (compressed rows), for the smooth normals.
    let face_normals: Vec<[f64; 3]> =
        faces.iter().map(|&f| face_normal(&corners.positions[3 * f..3 * f + 3])).collect();
    let mut start = vec![0u32; positions.len() + 1];
    for &p in &corner_position {
        start[p as usize + 1] += 1;
    }
    for i in 0..positions.len() {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut faces_at = vec![0u32; corner_position.len()];
    for (c, &p) in corner_position.iter().enumerate() {
        faces_at[fill[p as usize] as usize] = (c / 3) as u32;
        fill[p as usize] += 1;
    }
    let cos_crease = CREASE_DEGREES.to_radians().cos();

    // Vertices: a position with a normal, shared where both agree.
    let mut vertex_of: HashMap<(u32, Key), u32> = HashMap::new();
    for (c, &p) in corner_position.iter().enumerate() {
        let (k, corner) = (c / 3, 3 * faces[c / 3] + c % 3);
        let given = corners.normals.as_ref().map(|n| n[corner]).filter(|n| {
            let n = n.map(f64::from);
            n.iter().all(|x| x.is_finite()) && norm(n) > 1e-12
        });
        let n = match given {
            Some(n) => unit(n.map(f64::from)),
            None => {
                let own = unit(face_normals[k]);
                let mut sum = [0.0; 3];
                for &g in &faces_at[start[p as usize] as usize..start[p as usize + 1] as usize] {
                    let other = face_normals[g as usize];
                    if dot(own, unit(other)) >= cos_crease {
                        sum = [0, 1, 2].map(|i| sum[i] + other[i]);
                    }
                }
                unit(sum)
            }
        };
        let n = n.map(|x| x as f32);
        let next = (out.positions.len() / 3) as u32;
        let v = *vertex_of.entry((p, key(n))).or_insert(next);
        if v == next {
            out.positions.extend_from_slice(&positions[p as usize]);
            out.normals.extend_from_slice(&n);
        }
        out.indices.push(v);
    }

    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in &positions {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    out.min = lo;
    out.max = hi;
    out
}

/// Twice the area times the unit normal of a triangle (right-handed).
fn face_normal(p: &[[f32; 3]]) -> [f64; 3] {
    let [a, b, c] = [p[0], p[1], p[2]].map(|v| v.map(f64::from));
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    if n > 0.0 && n.is_finite() {
        a.map(|x| x / n)
    } else {
        [0.0, 0.0, 1.0]
    }
}
