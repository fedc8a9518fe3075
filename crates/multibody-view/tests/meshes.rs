//! The mesh files ShapefileVisualizer draws, read from small files written
//! for these tests (in `tests/meshes/`, or made here): triangle counts,
//! bounds, units and normals against the geometry the files were written
//! with.

mod common;

use common::models;
use multibody_view::mesh::{load, parse, Format, MeshData};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/meshes").join(name)
}

fn assert_bounds(mesh: &MeshData, min: [f32; 3], max: [f32; 3], tolerance: f32) {
    for i in 0..3 {
        assert!(
            (mesh.min[i] - min[i]).abs() <= tolerance && (mesh.max[i] - max[i]).abs() <= tolerance,
            "bounds {:?} .. {:?}, expected {min:?} .. {max:?}",
            mesh.min,
            mesh.max
        );
    }
}

/// Every normal is a unit vector, and the normals of each triangle's
/// corners point to the side its right-handed winding says (all test
/// meshes are wound outwards), or to the side the file says.
fn assert_normals_outward(mesh: &MeshData) {
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    let p = |v: u32| [0, 1, 2].map(|i| mesh.positions[3 * v as usize + i]);
    let n = |v: u32| [0, 1, 2].map(|i| mesh.normals[3 * v as usize + i]);
    for t in mesh.indices.chunks(3) {
        let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let face = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
        for &k in t {
            let nk = n(k);
            let length = (nk[0] * nk[0] + nk[1] * nk[1] + nk[2] * nk[2]).sqrt();
            assert!((length - 1.0).abs() < 1e-5, "normal {nk:?} is not a unit vector");
            let along = nk[0] * face[0] + nk[1] * face[1] + nk[2] * face[2];
            assert!(along > 0.0, "normal {nk:?} points against its face {face:?}");
        }
    }
}

/// A binary STL of the cube [-1, 1]^3 (12 triangles wound outwards), with
/// zero facet normals as some exporters write them.
fn binary_cube_stl() -> Vec<u8> {
    let bytes = models::box_stl(1.0, 1.0, 1.0);
    assert_eq!(bytes.len(), 84 + 12 * 50);
    bytes
}

#[test]
fn ascii_stl_tetrahedron() {
    let mesh = load(&data("tetra.stl")).unwrap();
    assert_eq!(mesh.triangles(), 4);
    assert_bounds(&mesh, [0.0; 3], [1.0; 3], 0.0);
    // The file's facet normals: flat faces, three corners each.
    assert_eq!(mesh.vertices(), 12);
    assert_normals_outward(&mesh);
}

#[test]
fn binary_stl_cube_gets_flat_normals() {
    let mesh = parse(&binary_cube_stl(), Path::new("cube.stl"), Format::Stl).unwrap();
    assert_eq!(mesh.triangles(), 12);
    assert_bounds(&mesh, [-1.0; 3], [1.0; 3], 0.0);
    // The file's zero normals are replaced by computed ones; the cube's
    // edges (90 degrees) stay sharp: four vertices on each of six faces.
    assert_eq!(mesh.vertices(), 24);
    assert_normals_outward(&mesh);
    for v in 0..mesh.vertices() {
        let n = &mesh.normals[3 * v..3 * v + 3];
        assert_eq!(n.iter().filter(|x| x.abs() == 1.0).count(), 1, "not an axis: {n:?}");
    }
}

#[test]
fn obj_cube_of_quads_without_normals_or_materials() {
    let mesh = load(&data("cube.obj")).unwrap();
    assert_eq!(mesh.triangles(), 12, "six quads are twelve triangles");
    assert_bounds(&mesh, [-1.0, -1.0, 0.0], [1.0, 1.0, 2.0], 0.0);
    assert_eq!(mesh.vertices(), 24);
    assert_normals_outward(&mesh);
}

#[test]
fn collada_units_and_node_transforms() {
    let mesh = load(&data("wedge_mm.dae")).unwrap();
    assert_eq!(mesh.triangles(), 4);
    // Legs 0.1, 0.2, 0.3 m; moved 1 m along the inner node's x, then a
    // quarter turn about z: x -> y, y -> -x.
    assert_bounds(&mesh, [-0.2, 1.0, 0.0], [0.0, 1.1, 0.3], 1e-5);
    assert_normals_outward(&mesh);
}

#[test]
fn collada_y_up_is_turned_to_z_up() {
    let text = std::fs::read_to_string(data("wedge_mm.dae")).unwrap();
    let y_up = text.replace("<up_axis>Z_UP</up_axis>", "<up_axis>Y_UP</up_axis>");
    let mesh = parse(y_up.as_bytes(), Path::new("wedge_y_up.dae"), Format::Collada).unwrap();
    // The Z_UP bounds turned by (x, y, z) -> (x, -z, y).
    assert_bounds(&mesh, [-0.2, -0.3, 1.0], [0.0, 0.0, 1.1], 1e-5);
    assert_normals_outward(&mesh);
}

#[test]
fn smooth_surfaces_share_normals_and_edges_stay_sharp() {
    // A shallow roof of two triangles (5 degrees apart) shares its ridge
    // normals; a second copy folded at 90 degrees does not.
    let stl = |angle: f32| {
        let (z, y) = angle.to_radians().sin_cos();
        let y = -y;
        format!(
            "solid roof\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n\
             facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 {y} {z}\nvertex 1 0 0\nendloop\nendfacet\nendsolid roof\n"
        )
    };
    let shallow = parse(stl(5.0).as_bytes(), Path::new("roof.stl"), Format::Stl).unwrap();
    assert_eq!((shallow.triangles(), shallow.vertices()), (2, 4), "the shared edge is smooth");
    let folded = parse(stl(90.0).as_bytes(), Path::new("fold.stl"), Format::Stl).unwrap();
    assert_eq!((folded.triangles(), folded.vertices()), (2, 6), "the fold stays sharp");
    assert_normals_outward(&shallow);
    assert_normals_outward(&folded);
}

#[test]
fn unreadable_files_say_why() {
    let missing = load(Path::new("/no/such/folder/part.stl")).unwrap_err();
    assert_eq!(missing, "no such file");
    let unknown = load(&data("tetra.stl").with_extension("ply")).unwrap_err();
    assert!(unknown.contains(".stl, .obj or .dae"), "{unknown}");
    let broken = parse(b"<COLLADA><library_geometries>", Path::new("broken.dae"), Format::Collada).unwrap_err();
    assert!(broken.starts_with("cannot parse it"), "{broken}");
    let truncated = parse(&binary_cube_stl()[..300], Path::new("short.stl"), Format::Stl);
    assert!(truncated.is_err() || truncated.unwrap().triangles() < 12);
}
