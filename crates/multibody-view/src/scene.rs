//! Sampling a solution into what the page draws: the poses of the frames
//! the shapes are placed by, at the animation's frame times, and the shapes
//! themselves with their placements resolved to indices into those poses.

use crate::mesh::{self, MeshData};
use crate::ViewError;
use multibody::components::shapes::{Placement, Shape, ShapeKind};
use multibody::math::rotation::axis_rotation;
use multibody::math::{Mat3, Transform, Vec3};
use multibody::Solution;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Floats per pose: position (3) and the frame-to-world rotation as a unit
/// quaternion `[w, x, y, z]` (4).
pub const POSE_FLOATS: usize = 7;

/// The most pose data a page embeds (bytes before base64); longer or larger
/// runs get fewer frames per second.
const MAX_POSE_BYTES: usize = 24 << 20;

/// The most triangles of mesh files (ShapefileVisualizer) a page embeds,
/// each file counted once however many shapes draw it: about 40 MB of page,
/// and still a few frames per second in a software renderer. A file that
/// would pass it is left out, with a message.
pub const MAX_MESH_TRIANGLES: usize = 1_000_000;

/// Everything the page needs to draw the motion.
#[derive(Debug)]
pub struct Scene {
    /// Animation frame times.
    pub times: Vec<f64>,
    /// Frame-major: frame `k`, pose `j` at `(k * pose_count + j) * 7`.
    pub poses: Vec<f32>,
    pub pose_names: Vec<String>,
    /// Frame-major world vectors (force arrows): 3 floats each.
    pub vectors: Vec<f32>,
    pub vector_names: Vec<String>,
    pub shapes: Vec<SceneShape>,
    /// Bounds of every drawn shape over the whole motion.
    pub bbox: ([f64; 3], [f64; 3]),
    /// Shapes left out, with the reason.
    pub skipped: Vec<String>,
    /// The mesh files the shapes draw, each once: the path as resolved, and
    /// the mesh.
    pub meshes: Vec<(String, MeshData)>,
}

/// A mesh shape's file (an index into `Scene::meshes`) and where it goes in
/// its frame: `transform * (scale * p)`.
#[derive(Debug)]
pub struct SceneMesh {
    pub index: usize,
    pub transform: [[f64; 4]; 4],
    pub scale: f64,
}

#[derive(Debug)]
pub struct SceneShape {
    pub component: String,
    pub kind: &'static str,
    pub windings: f64,
    pub color: [f64; 4],
    pub specular: f64,
    pub width: f64,
    pub height: f64,
    pub placement: ScenePlacement,
    pub mesh: Option<SceneMesh>,
}

#[derive(Debug)]
pub enum ScenePlacement {
    Frame { pose: usize, origin: [f64; 3], length: [f64; 3], width_dir: [f64; 3] },
    Between { from: usize, to: usize },
    Vector { pose: usize, vector: usize, scale: f64 },
}

fn kind_name(kind: &ShapeKind) -> (&'static str, f64) {
    match kind {
        ShapeKind::Sphere => ("sphere", 0.0),
        ShapeKind::Cylinder => ("cylinder", 0.0),
        ShapeKind::Box => ("box", 0.0),
        ShapeKind::Cone => ("cone", 0.0),
        ShapeKind::Helix { windings } => ("helix", *windings),
        ShapeKind::Line => ("line", 0.0),
        ShapeKind::Arrow => ("arrow", 0.0),
        ShapeKind::Mesh { .. } => ("mesh", 0.0),
    }
}

/// The columns of a frame's pose: a 3-D frame's `r_0[1..3]` and
/// `R[1,1]..R[3,3]`, or a planar frame's `x`, `y` and `phi` (in the plane
/// `plane`, turned about its normal).
enum FrameColumns<'a> {
    Spatial([&'a [f64]; 12]),
    Planar { columns: [&'a [f64]; 3], plane: Transform },
}

fn frame_columns<'a>(solution: &'a Solution, frame: &str, plane: Transform) -> Option<FrameColumns<'a>> {
    if let (Some(x), Some(y), Some(phi)) = (
        solution.get(&format!("{frame}.x")),
        solution.get(&format!("{frame}.y")),
        solution.get(&format!("{frame}.phi")),
    ) {
        return Some(FrameColumns::Planar { columns: [x, y, phi], plane });
    }
    let mut names = Vec::with_capacity(12);
    for i in 1..=3 {
        names.push(format!("{frame}.r_0[{i}]"));
    }
    for i in 1..=3 {
        for j in 1..=3 {
            names.push(format!("{frame}.R[{i},{j}]"));
        }
    }
    let mut cols: Vec<&[f64]> = Vec::with_capacity(12);
    for n in &names {
        cols.push(solution.get(n)?);
    }
    cols.try_into().ok().map(FrameColumns::Spatial)
}

/// Where each animation frame falls between two solution samples.
#[derive(Clone, Copy, Debug)]
struct Blend {
    k0: usize,
    k1: usize,
    w: f64,
}

fn blend(times: &[f64], t: f64) -> Blend {
    let k = times.partition_point(|&s| s < t);
    if k == 0 {
        return Blend { k0: 0, k1: 0, w: 0.0 };
    }
    if k >= times.len() {
        let last = times.len() - 1;
        return Blend { k0: last, k1: last, w: 0.0 };
    }
    let (t0, t1) = (times[k - 1], times[k]);
    let w = if t1 > t0 { ((t - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
    Blend { k0: k - 1, k1: k, w }
}

/// The unit quaternion `[w, x, y, z]` of the rotation matrix `m` (row-major,
/// `v_world = m v_frame`).
pub fn quaternion(m: &[f64; 9]) -> [f64; 4] {
    let (m00, m01, m02, m10, m11, m12, m20, m21, m22) = (m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8]);
    let trace = m00 + m11 + m22;
    let q = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s]
    } else if m00 > m11 && m00 > m22 {
        let s = (1.0 + m00 - m11 - m22).sqrt() * 2.0;
        [(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s]
    } else if m11 > m22 {
        let s = (1.0 + m11 - m00 - m22).sqrt() * 2.0;
        [(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s]
    } else {
        let s = (1.0 + m22 - m00 - m11).sqrt() * 2.0;
        [(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s]
    };
    normalize4(q)
}

fn normalize4(q: [f64; 4]) -> [f64; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    if n > 0.0 && n.is_finite() {
        [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
    } else {
        [1.0, 0.0, 0.0, 0.0]
    }
}

/// The rotation matrix (row-major, frame to world) of a unit quaternion.
pub fn rotation(q: &[f64; 4]) -> [f64; 9] {
    let [w, x, y, z] = *q;
    [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    ]
}

fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

/// A frame's position and frame-to-world quaternion at sample `k`. The
/// solution's `R` maps world to frame (`v_frame = R v_world`), so the
/// frame-to-world matrix is its transpose.
fn pose_at(cols: &FrameColumns, k: usize) -> ([f64; 3], [f64; 4]) {
    let (p, r) = match cols {
        FrameColumns::Spatial(cols) => {
            (Vec3::new(cols[0][k], cols[1][k], cols[2][k]), Mat3::from_fn(|i, j| cols[3 + 3 * i + j][k]))
        }
        // In the plane, then the plane into the world.
        FrameColumns::Planar { columns: [x, y, phi], plane } => {
            (plane.inv_apply_point(&Vec3::new(x[k], y[k], 0.0)), axis_rotation(2, phi[k]) * plane.rot)
        }
    };
    let m = [r[(0, 0)], r[(1, 0)], r[(2, 0)], r[(0, 1)], r[(1, 1)], r[(2, 1)], r[(0, 2)], r[(1, 2)], r[(2, 2)]];
    ([p.x, p.y, p.z], quaternion(&m))
}

/// The frame times: the solution's own samples when there are no more than
/// the animation needs, else a uniform grid.
fn frame_times(times: &[f64], fps: f64, max_frames: usize) -> Vec<f64> {
    let (t0, t1) = (times[0], times[times.len() - 1]);
    let duration = t1 - t0;
    if duration <= 0.0 || !duration.is_finite() {
        return vec![t0];
    }
    let fps = if fps > 0.0 && fps.is_finite() { fps } else { 30.0 };
    let wanted = ((duration * fps).ceil() as usize + 1).clamp(2, max_frames.max(2));
    if times.len() <= wanted {
        return times.to_vec();
    }
    (0..wanted).map(|k| t0 + duration * k as f64 / (wanted - 1) as f64).collect()
}

/// The file a mesh shape names: an absolute path as it is, a relative one
/// from `folder` (the current directory when there is none); `~` is a
/// name like any other.
pub fn mesh_path(path: &str, folder: Option<&Path>) -> PathBuf {
    let p = Path::new(path);
    match folder {
        Some(folder) if p.is_relative() => folder.join(p),
        _ => p.to_path_buf(),
    }
}

/// The mesh files of a scene, each read once, within the triangle budget.
#[derive(Default)]
struct MeshFiles {
    loaded: Vec<(String, MeshData)>,
    by_path: HashMap<PathBuf, Result<usize, String>>,
    triangles: usize,
}

impl MeshFiles {
    fn get(&mut self, path: &Path) -> Result<usize, String> {
        if let Some(known) = self.by_path.get(path) {
            return known.clone();
        }
        let left = MAX_MESH_TRIANGLES - self.triangles;
        // Too large files are refused before they are read, with the budget's message.
        let loaded = mesh::load_within(path, left).map_err(|e| match e {
            mesh::LoadError::Triangles(n) => over_budget(&format!("it has {n} triangles"), left),
            mesh::LoadError::Bytes(size) => over_budget(
                &format!(
                    "it is {size} bytes long, more than {left} triangles take in any mesh format read ({} bytes \
                     each)",
                    mesh::MAX_BYTES_PER_TRIANGLE
                ),
                left,
            ),
            mesh::LoadError::Unreadable(why) => why,
        });
        let result = loaded.and_then(|m| {
            if m.triangles() == 0 {
                return Err("it has no triangles".to_string());
            }
            if m.triangles() > left {
                return Err(over_budget(&format!("it has {} triangles", m.triangles()), left));
            }
            self.triangles += m.triangles();
            self.loaded.push((path.display().to_string(), m));
            Ok(self.loaded.len() - 1)
        });
        self.by_path.insert(path.to_path_buf(), result.clone());
        result
    }
}

/// "{what}, and the page's budget of ... triangles of meshes has {left}
/// left; simplify (decimate) the mesh".
fn over_budget(what: &str, left: usize) -> String {
    format!(
        "{what}, and the page's budget of {MAX_MESH_TRIANGLES} triangles of meshes has {left} left; simplify \
         (decimate) the mesh"
    )
}

/// Samples the motion of `shapes` in `solution` at about `fps` frames per
/// simulated second, with at most `max_frames` frames. Mesh files are read
/// from `mesh_folder` when their path is relative.
pub fn sample(
    shapes: &[Shape],
    solution: &Solution,
    fps: f64,
    max_frames: usize,
    mesh_folder: Option<&Path>,
) -> Result<Scene, ViewError> {
    let times = solution.time();
    if times.is_empty() {
        return Err(ViewError::EmptySolution);
    }

    // Resolve every shape's frames and vectors to tracks.
    let mut frame_index: HashMap<String, usize> = HashMap::new();
    let mut frames: Vec<(String, FrameColumns)> = Vec::new();
    let mut vector_index: HashMap<String, usize> = HashMap::new();
    let mut vectors: Vec<(String, [&[f64]; 3])> = Vec::new();
    let mut skipped = Vec::new();
    let mut placed: Vec<(&Shape, ScenePlacementDraft, Option<usize>)> = Vec::new();
    let mut mesh_files = MeshFiles::default();

    let mut frame = |name: &str, skipped: &mut Vec<String>, shape: &Shape| -> Option<usize> {
        if let Some(&i) = frame_index.get(name) {
            return Some(i);
        }
        let component = &shape.component;
        match frame_columns(solution, name, shape.plane) {
            Some(cols) => {
                frames.push((name.to_string(), cols));
                frame_index.insert(name.to_string(), frames.len() - 1);
                Some(frames.len() - 1)
            }
            None => {
                skipped.push(format!("{component}: the solution has no pose of {name} ({name}.r_0 and {name}.R, or {name}.x, .y and .phi)"));
                None
            }
        }
    };
    for shape in shapes {
        let mesh = match &shape.kind {
            ShapeKind::Mesh { path, .. } => {
                let file = mesh_path(path, mesh_folder);
                match mesh_files.get(&file) {
                    Ok(index) => Some(index),
                    Err(why) => {
                        skipped.push(format!("{}: the mesh {} is not drawn: {why}", shape.component, file.display()));
                        continue;
                    }
                }
            }
            _ => None,
        };
        let draft = match &shape.placement {
            Placement::InFrame { frame: f, origin, length, width_dir } => {
                let Some(pose) = frame(f, &mut skipped, shape) else { continue };
                ScenePlacementDraft::Frame {
                    pose,
                    origin: [origin.x, origin.y, origin.z],
                    length: [length.x, length.y, length.z],
                    width_dir: [width_dir.x, width_dir.y, width_dir.z],
                }
            }
            Placement::Between { from, to } => {
                let Some(a) = frame(from, &mut skipped, shape) else { continue };
                let Some(b) = frame(to, &mut skipped, shape) else { continue };
                ScenePlacementDraft::Between { from: a, to: b }
            }
            Placement::Vector { frame: f, vector, scale } => {
                let Some(pose) = frame(f, &mut skipped, shape) else { continue };
                let v = match vector_index.get(vector) {
                    Some(&v) => v,
                    None => {
                        let cols: Option<Vec<&[f64]>> =
                            (1..=3).map(|i| solution.get(&format!("{vector}[{i}]"))).collect();
                        let Some(cols) = cols else {
                            skipped.push(format!("{}: the solution has no vector {vector}[1..3]", shape.component));
                            continue;
                        };
                        vectors.push((vector.clone(), [cols[0], cols[1], cols[2]]));
                        vector_index.insert(vector.clone(), vectors.len() - 1);
                        vectors.len() - 1
                    }
                };
                ScenePlacementDraft::Vector { pose, vector: v, scale: *scale }
            }
        };
        placed.push((shape, draft, mesh));
    }

    // Frame times, within the size budget.
    let per_frame = (frames.len() * POSE_FLOATS + vectors.len() * 3).max(1) * 4;
    let max_frames = max_frames.min(MAX_POSE_BYTES / per_frame).max(2);
    let frame_t = frame_times(times, fps, max_frames);
    let blends: Vec<Blend> = frame_t.iter().map(|&t| blend(times, t)).collect();

    // Sample each frame's track: positions interpolated linearly,
    // rotations by normalized quaternion interpolation, signs kept
    // continuous so that the page can interpolate between frames too.
    let nf = frame_t.len();
    let mut tracks: Vec<Vec<f32>> = Vec::with_capacity(frames.len());
    for (_, cols) in &frames {
        let mut track = Vec::with_capacity(nf * POSE_FLOATS);
        let mut previous = [1.0, 0.0, 0.0, 0.0];
        for b in &blends {
            let (p0, q0) = pose_at(cols, b.k0);
            let (p, mut q) = if b.k1 == b.k0 || b.w == 0.0 {
                (p0, q0)
            } else {
                let (p1, mut q1) = pose_at(cols, b.k1);
                if dot4(&q0, &q1) < 0.0 {
                    q1 = q1.map(|x| -x);
                }
                let w = b.w;
                let p = [0, 1, 2].map(|i| p0[i] * (1.0 - w) + p1[i] * w);
                let q = normalize4([0, 1, 2, 3].map(|i| q0[i] * (1.0 - w) + q1[i] * w));
                (p, q)
            };
            if dot4(&q, &previous) < 0.0 {
                q = q.map(|x| -x);
            }
            previous = q;
            track.extend(p.iter().chain(q.iter()).map(|&x| x as f32));
        }
        tracks.push(track);
    }

    // Frames that move together (connected connectors) share one track.
    let mut unique: Vec<usize> = Vec::new();
    let mut remap = vec![0usize; tracks.len()];
    let mut seen: HashMap<Vec<u32>, usize> = HashMap::new();
    for (i, track) in tracks.iter().enumerate() {
        let key: Vec<u32> = track.iter().map(|x| x.to_bits()).collect();
        let next = unique.len();
        let u = *seen.entry(key).or_insert(next);
        if u == next {
            unique.push(i);
        }
        remap[i] = u;
    }
    let pose_count = unique.len();
    let mut poses = Vec::with_capacity(nf * pose_count * POSE_FLOATS);
    for k in 0..nf {
        for &i in &unique {
            poses.extend_from_slice(&tracks[i][k * POSE_FLOATS..(k + 1) * POSE_FLOATS]);
        }
    }
    let pose_names: Vec<String> = unique.iter().map(|&i| frames[i].0.clone()).collect();

    let mut vector_data = Vec::with_capacity(nf * vectors.len() * 3);
    for b in &blends {
        for (_, cols) in &vectors {
            for c in cols {
                vector_data.push((c[b.k0] * (1.0 - b.w) + c[b.k1] * b.w) as f32);
            }
        }
    }

    let scene_shapes: Vec<SceneShape> = placed
        .iter()
        .map(|(shape, draft, mesh)| {
            let (kind, windings) = kind_name(&shape.kind);
            let mesh = match (&shape.kind, mesh) {
                (ShapeKind::Mesh { transform, scale, .. }, Some(index)) => {
                    Some(SceneMesh { index: *index, transform: *transform, scale: *scale })
                }
                _ => None,
            };
            let placement = match *draft {
                ScenePlacementDraft::Frame { pose, origin, length, width_dir } => {
                    ScenePlacement::Frame { pose: remap[pose], origin, length, width_dir }
                }
                ScenePlacementDraft::Between { from, to } => {
                    ScenePlacement::Between { from: remap[from], to: remap[to] }
                }
                ScenePlacementDraft::Vector { pose, vector, scale } => {
                    ScenePlacement::Vector { pose: remap[pose], vector, scale }
                }
            };
            SceneShape {
                component: shape.component.clone(),
                kind,
                windings,
                color: shape.color,
                specular: shape.specular,
                width: shape.width,
                height: shape.height,
                placement,
                mesh,
            }
        })
        .collect();

    let mut scene = Scene {
        times: frame_t,
        poses,
        pose_names,
        vectors: vector_data,
        vector_names: vectors.iter().map(|(n, _)| n.clone()).collect(),
        shapes: scene_shapes,
        bbox: ([0.0; 3], [0.0; 3]),
        skipped,
        meshes: mesh_files.loaded,
    };
    scene.bbox = bounds(&scene);
    Ok(scene)
}

#[derive(Clone, Copy)]
enum ScenePlacementDraft {
    Frame { pose: usize, origin: [f64; 3], length: [f64; 3], width_dir: [f64; 3] },
    Between { from: usize, to: usize },
    Vector { pose: usize, vector: usize, scale: f64 },
}

/// The bounding box of the shapes' key points (origins and ends) over all
/// frames, grown by half the widest shape; the world origin when nothing is
/// drawn.
fn bounds(scene: &Scene) -> ([f64; 3], [f64; 3]) {
    let pose_count = scene.pose_names.len();
    let vector_count = scene.vector_names.len();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut add = |p: [f64; 3]| {
        if p.iter().all(|x| x.is_finite()) {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
    };
    let pose = |k: usize, j: usize| -> ([f64; 3], [f64; 9]) {
        let o = (k * pose_count + j) * POSE_FLOATS;
        let d = &scene.poses[o..o + POSE_FLOATS];
        let q = [d[3], d[4], d[5], d[6]].map(f64::from);
        ([d[0], d[1], d[2]].map(f64::from), rotation(&q))
    };
    let apply = |p: &[f64; 3], m: &[f64; 9], v: &[f64; 3]| -> [f64; 3] {
        [0, 1, 2].map(|i| p[i] + m[3 * i] * v[0] + m[3 * i + 1] * v[1] + m[3 * i + 2] * v[2])
    };
    let mut widest: f64 = 0.0;
    for s in &scene.shapes {
        if s.width.is_finite() {
            widest = widest.max(s.width);
        }
    }
    for k in 0..scene.times.len() {
        for s in &scene.shapes {
            match s.placement {
                ScenePlacement::Frame { pose: j, .. } if s.mesh.is_some() => {
                    let (p, m) = pose(k, j);
                    for corner in mesh_corners(scene, s) {
                        add(apply(&p, &m, &corner));
                    }
                }
                ScenePlacement::Frame { pose: j, origin, length, .. } => {
                    let (p, m) = pose(k, j);
                    let start = apply(&p, &m, &origin);
                    add(start);
                    if s.kind != "sphere" {
                        add(apply(&p, &m, &[0, 1, 2].map(|i| origin[i] + length[i])));
                    }
                }
                ScenePlacement::Between { from, to } => {
                    add(pose(k, from).0);
                    add(pose(k, to).0);
                }
                ScenePlacement::Vector { pose: j, vector, scale } => {
                    let p = pose(k, j).0;
                    let o = (k * vector_count + vector) * 3;
                    let v = &scene.vectors[o..o + 3];
                    add(p);
                    add([0, 1, 2].map(|i| p[i] + scale * f64::from(v[i])));
                }
            }
        }
    }
    if !lo[0].is_finite() {
        return ([-0.5; 3], [0.5; 3]);
    }
    let pad = widest / 2.0;
    (lo.map(|x| x - pad), hi.map(|x| x + pad))
}

/// The corners of a mesh shape's box in its frame: the file's bounds
/// through `transform * scale`.
fn mesh_corners(scene: &Scene, s: &SceneShape) -> Vec<[f64; 3]> {
    let Some(mesh) = &s.mesh else { return Vec::new() };
    let data = &scene.meshes[mesh.index].1;
    let t = &mesh.transform;
    (0..8)
        .map(|c| {
            let corner = [0, 1, 2].map(|i| f64::from(if c & (1 << i) != 0 { data.max[i] } else { data.min[i] }));
            let q = corner.map(|x| x * mesh.scale);
            [0, 1, 2].map(|i| t[i][0] * q[0] + t[i][1] * q[1] + t[i][2] * q[2] + t[i][3])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternion_round_trip() {
        // A rotation of 120 degrees about (1,1,1): x -> y -> z -> x.
        let m = [0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let q = quaternion(&m);
        let back = rotation(&q);
        for i in 0..9 {
            assert!((back[i] - m[i]).abs() < 1e-12, "{back:?}");
        }
        // Half-turns take the other branches.
        for m in [
            [1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0],
            [-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0],
            [-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0],
        ] {
            let back = rotation(&quaternion(&m));
            assert!(back.iter().zip(&m).all(|(a, b)| (a - b).abs() < 1e-12), "{back:?}");
        }
    }

    #[test]
    fn frame_times_follow_fps_and_cap() {
        let times: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
        let f = frame_times(&times, 30.0, 10_000);
        assert_eq!(f.len(), 301);
        assert!((f[300] - 10.0).abs() < 1e-12);
        assert_eq!(frame_times(&times, 30.0, 50).len(), 50);
        // A coarse solution is used as it is.
        let coarse: Vec<f64> = (0..=10).map(|k| k as f64).collect();
        assert_eq!(frame_times(&coarse, 30.0, 10_000), coarse);
        assert_eq!(frame_times(&[0.0], 30.0, 100), [0.0]);
    }
}
