//! URDF robots: read with the place of everything (so that an error says
//! file:line:col), checked as a tree, and written as a Dyad model file of
//! the library's URDF parts, whose component names are the URDF's link and
//! joint names. `multibody import` writes that file; `multibody run
//! robot.urdf` reads the same text directly.
//!
//! Conventions: a joint's `<origin>` places its frame in the parent link's
//! (`xyz`, then the fixed-axis roll, pitch, yaw: `R = Rz(yaw) Ry(pitch)
//! Rx(roll)`), which our `URDFRevolute`/`URDFPrismatic` take as a rotation by
//! `angle` about `n`; an `<inertial>`'s inertia is rotated into the link
//! frame. URDF is z-up: the World's gravity points along -z.

use std::cell::Cell;
use std::collections::{HashMap, HashSet};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// How many components a model may have: the lowering refuses more.
pub use crate::lowering::lower::MAX_COMPONENTS;

/// A place in the URDF file (1-based).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pos {
    pub line: u32,
    pub col: u32,
}

/// What is wrong with a URDF file, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfError {
    pub at: Pos,
    pub message: String,
    pub help: Option<String>,
}

impl UrdfError {
    fn new(at: Pos, message: impl Into<String>) -> Self {
        UrdfError { at, message: message.into(), help: None }
    }

    fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// `file:line:col: error: message` and the help, as the command prints it.
    pub fn render(&self, file: &str) -> String {
        let mut s = format!("{file}:{}:{}: error: {}", self.at.line, self.at.col, self.message);
        if let Some(h) = &self.help {
            let _ = write!(s, "\n  help: {h}");
        }
        s
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Origin {
    pub xyz: [f64; 3],
    pub rpy: [f64; 3],
}

impl Default for Origin {
    fn default() -> Self {
        Origin { xyz: [0.0; 3], rpy: [0.0; 3] }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Inertial {
    pub origin: Origin,
    pub mass: f64,
    /// ixx, ixy, ixz, iyy, iyz, izz, in the inertial frame.
    pub inertia: [f64; 6],
    pub at: Pos,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    Box {
        size: [f64; 3],
    },
    Cylinder {
        radius: f64,
        length: f64,
    },
    Sphere {
        radius: f64,
    },
    /// `filename` as written (`package://...`, `file://...` or a path);
    /// `path` where [`resolve_meshes`] found it.
    Mesh {
        filename: String,
        scale: [f64; 3],
        path: Option<std::path::PathBuf>,
        at: Pos,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Visual {
    pub origin: Origin,
    pub geometry: Geometry,
    /// RGBA, from the visual's `<material>` or the robot's material it names.
    pub color: Option<[f64; 4]>,
    /// The name of the robot's material, when the visual names one.
    pub material: Option<String>,
    pub at: Pos,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    pub name: String,
    pub inertial: Option<Inertial>,
    pub visuals: Vec<Visual>,
    pub at: Pos,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    Revolute,
    Continuous,
    Prismatic,
    Fixed,
    /// Six degrees of freedom between two links.
    Floating,
    /// Motion in the plane whose normal is the axis.
    Planar,
}

impl JointKind {
    /// A joint of one coordinate (which mimics and dampers act on).
    pub fn has_one_coordinate(self) -> bool {
        matches!(self, JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Mimic {
    pub joint: String,
    pub multiplier: f64,
    pub offset: f64,
    pub at: Pos,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
    /// Positions among the robot's links.
    pub parent: usize,
    pub child: usize,
    pub origin: Origin,
    /// The unit axis, in the joint frame.
    pub axis: [f64; 3],
    pub limits: Option<(f64, f64)>,
    pub damping: f64,
    pub friction: f64,
    pub mimic: Option<Mimic>,
    pub at: Pos,
}

/// An element the import does not map, once per tag, with its first place.
#[derive(Clone, Debug, PartialEq)]
pub struct Skipped {
    pub tag: String,
    pub at: Pos,
    pub count: usize,
}

/// Data the import takes as it is, but doubts: said with its place.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfWarning {
    pub at: Pos,
    pub message: String,
    pub help: Option<String>,
}

impl UrdfWarning {
    /// `file:line:col: warning: message` and the help, as the command prints it.
    pub fn render(&self, file: &str) -> String {
        let mut s = format!("{file}:{}:{}: warning: {}", self.at.line, self.at.col, self.message);
        if let Some(h) = &self.help {
            let _ = write!(s, "\n  help: {h}");
        }
        s
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    pub name: String,
    /// The place of `<robot>`.
    pub at: Pos,
    pub links: Vec<Link>,
    /// In the file's order.
    pub joints: Vec<Joint>,
    /// The link no joint moves.
    pub root: usize,
    pub skipped: Vec<Skipped>,
    pub warnings: Vec<UrdfWarning>,
}

/// Lines and columns of places in a text. roxmltree's `text_pos_at`
/// counts from the start of the text at each call, which made reading a
/// robot of n links take n² steps; this finds the line by bisection and
/// counts the column on from the place asked for before when it can.
struct Places<'t> {
    text: &'t str,
    /// The byte where each line starts.
    lines: Vec<usize>,
    /// The last place asked for: its byte and its column (1-based).
    last: Cell<(usize, u32)>,
}

impl<'t> Places<'t> {
    fn new(text: &'t str) -> Self {
        let mut lines = vec![0];
        lines.extend(text.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(k, _)| k + 1));
        Places { text, lines, last: Cell::new((0, 1)) }
    }

    /// As roxmltree counts: lines from 1, columns in characters from 1.
    fn at(&self, byte: usize) -> Pos {
        let byte = byte.min(self.text.len());
        let line = self.lines.partition_point(|&start| start <= byte) - 1;
        let start = self.lines[line];
        let (last, last_col) = self.last.get();
        let (from, col) = if last >= start && last <= byte { (last, last_col) } else { (start, 1) };
        let col = col + self.text[from..byte].chars().count() as u32;
        self.last.set((byte, col));
        Pos { line: line as u32 + 1, col }
    }
}

/// Reads and checks a URDF file.
pub fn parse(text: &str) -> Result<Robot, UrdfError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let p = e.pos();
        UrdfError::new(Pos { line: p.row, col: p.col }, format!("this is not well-formed XML: {e}"))
    })?;
    let places = Places::new(text);
    let pos = |n: roxmltree::Node| places.at(n.range().start);
    let root = doc.root_element();
    if root.tag_name().name() != "robot" {
        return Err(UrdfError::new(
            pos(root),
            format!("the root element is `<{}>`, not `<robot>`", root.tag_name().name()),
        )
        .help("a URDF file describes one `<robot name=\"...\">`"));
    }
    // Too many parts for one model is said before any is read.
    let count = |tag: &str| root.children().filter(|n| n.is_element() && n.tag_name().name() == tag).count();
    let (link_count, joint_count) = (count("link"), count("joint"));
    if 1 + link_count + joint_count > MAX_COMPONENTS {
        return Err(too_many_components(pos(root), link_count, joint_count, 1 + link_count + joint_count));
    }
    let mut skipped: Vec<Skipped> = Vec::new();
    let mut skipped_at: HashMap<String, usize> = HashMap::new();
    let mut skip = |tag: &str, at: Pos| match skipped_at.get(tag) {
        Some(&k) => skipped[k].count += 1,
        None => {
            skipped_at.insert(tag.to_string(), skipped.len());
            skipped.push(Skipped { tag: tag.to_string(), at, count: 1 });
        }
    };
    let mut links: Vec<Link> = Vec::new();
    let mut link_index: HashMap<String, usize> = HashMap::new();
    let mut raw_joints = Vec::new();
    // The robot's named materials, which visuals may name (the first of a
    // name counts).
    let mut materials: HashMap<String, [f64; 4]> = HashMap::new();
    for node in root.children().filter(|n| n.is_element()) {
        match node.tag_name().name() {
            "link" => {
                let link = read_link(node, &pos, &mut skip)?;
                if let Some(&other) = link_index.get(&link.name) {
                    return Err(UrdfError::new(link.at, format!("a second link named `{}`", link.name))
                        .help(format!("the first is at line {}", links[other].at.line)));
                }
                link_index.insert(link.name.clone(), links.len());
                links.push(link);
            }
            "joint" => raw_joints.push(node),
            "material" => {
                if let (Some(name), Some(color)) = read_material(node, &pos)? {
                    materials.entry(name).or_insert(color);
                }
            }
            other => skip(other, pos(node)),
        }
    }
    if links.is_empty() {
        return Err(UrdfError::new(pos(root), "the robot has no `<link>`"));
    }
    let warnings = links.iter().filter_map(impossible_inertia).collect();
    for visual in links.iter_mut().flat_map(|l| l.visuals.iter_mut()).filter(|v| v.color.is_none()) {
        visual.color = visual.material.as_ref().and_then(|m| materials.get(m)).copied();
    }
    let mut joints: Vec<Joint> = Vec::new();
    let mut joint_index: HashMap<String, usize> = HashMap::new();
    // The joint that moves each link.
    let mut parent_joint: Vec<Option<usize>> = vec![None; links.len()];
    for node in raw_joints {
        let joint = read_joint(node, &links, &link_index, &pos, &mut skip)?;
        if let Some(&other) = joint_index.get(&joint.name) {
            return Err(UrdfError::new(joint.at, format!("a second joint named `{}`", joint.name))
                .help(format!("the first is at line {}", joints[other].at.line)));
        }
        if let Some(other) = parent_joint[joint.child].map(|k| &joints[k]) {
            return Err(UrdfError::new(
                joint.at,
                format!(
                    "the link `{}` has two parents: joint `{}` (line {}) and joint `{}`",
                    links[joint.child].name, other.name, other.at.line, joint.name
                ),
            )
            .help("each link is the child of at most one joint; a closed chain cannot be written in URDF"));
        }
        joint_index.insert(joint.name.clone(), joints.len());
        parent_joint[joint.child] = Some(joints.len());
        joints.push(joint);
    }
    // A fixed joint does not move: a mimic on it (Talos's grippers have
    // some) changes nothing.
    for j in joints.iter_mut().filter(|j| j.kind == JointKind::Fixed) {
        if let Some(m) = j.mimic.take() {
            skip("mimic", m.at);
        }
    }
    check_mimics(&joints, &joint_index)?;
    // The root: the one link no joint moves; a loop leaves none.
    let roots: Vec<usize> = (0..links.len()).filter(|&l| parent_joint[l].is_none()).collect();
    let root_link = match roots.as_slice() {
        [one] => *one,
        [] => {
            return Err(loop_error(&links, &joints, &parent_joint));
        }
        many => {
            let names: Vec<String> = many.iter().map(|&l| format!("`{}`", links[l].name)).collect();
            return Err(UrdfError::new(
                links[many[1]].at,
                format!(
                    "the robot is in {} pieces: the links {} are each moved by no joint",
                    many.len(),
                    names.join(", ")
                ),
            )
            .help("join them with joints (a `fixed` joint for a rigid attachment)"));
        }
    };
    // Every link reached from the root (a loop elsewhere leaves some out).
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
    for j in &joints {
        children[j.parent].push(j.child);
    }
    let mut reached = vec![false; links.len()];
    let mut stack = vec![root_link];
    while let Some(l) = stack.pop() {
        if std::mem::replace(&mut reached[l], true) {
            continue;
        }
        stack.extend(children[l].iter().rev());
    }
    if reached.iter().any(|r| !r) {
        return Err(loop_error(&links, &joints, &parent_joint));
    }
    Ok(Robot {
        name: root.attribute("name").unwrap_or("robot").to_string(),
        at: pos(root),
        links,
        joints,
        root: root_link,
        skipped,
        warnings,
    })
}

/// A link's inertia that no rigid body can have: taken as it is (real
/// robots' data has some), with a warning at its `<inertial>`.
fn impossible_inertia(link: &Link) -> Option<UrdfWarning> {
    let inertial = link.inertial.as_ref()?;
    let [xx, xy, xz, yy, yz, zz] = inertial.inertia;
    let doubt = multibody::components::ImpossibleInertia::of([xx, yy, zz, xy, xz, yz])?;
    Some(UrdfWarning {
        at: inertial.at,
        message: format!(
            "no rigid mass distribution has the inertia of the link `{}`: {}",
            link.name,
            doubt.describe()
        ),
        help: Some(
            "a rigid body's largest principal moment is at most the sum of the other two; the robot is imported \
             with the inertia as given, but check ixx ... izz"
                .into(),
        ),
    })
}

/// A robot whose model would have more components than a model may have.
fn too_many_components(at: Pos, links: usize, joints: usize, components: usize) -> UrdfError {
    UrdfError::new(
        at,
        format!(
            "the robot has {links} links and {joints} joints: its model would have {components} components, and a \
             model has at most {MAX_COMPONENTS}"
        ),
    )
    .help(
        "the world, each link, each joint, each shape and each damper is a component: split the robot into URDF \
         files of fewer links (or leave its meshes out with --no-meshes, if the shapes are what is too many)",
    )
}

/// How many components [`to_dyad`] makes of the robot: the world, a
/// component per link, per joint, per visual drawn, per placed planar or
/// floating joint and per damper.
pub fn component_count(robot: &Robot, options: &ImportOptions) -> usize {
    let visuals = robot
        .links
        .iter()
        .flat_map(|l| &l.visuals)
        .filter(|v| !matches!(v.geometry, Geometry::Mesh { path: None, .. }))
        .count();
    let placed = robot.joints.iter().filter(|j| matches!(j.kind, JointKind::Planar | JointKind::Floating)).count();
    let dampers =
        robot.joints.iter().filter(|j| options.damping && j.damping > 0.0 && j.kind.has_one_coordinate()).count();
    1 + robot.links.len() + robot.joints.len() + visuals + placed + dampers
}

/// The robot's model is not larger than a model may be: said at
/// `<robot>`, before the model is written.
pub fn check_size(robot: &Robot, options: &ImportOptions) -> Result<(), UrdfError> {
    let n = component_count(robot, options);
    if n > MAX_COMPONENTS {
        return Err(too_many_components(robot.at, robot.links.len(), robot.joints.len(), n));
    }
    Ok(())
}

/// Each mimic names a joint that exists and moves, the follower moves too,
/// and no chain of mimics comes back to where it started.
fn check_mimics(joints: &[Joint], index: &HashMap<String, usize>) -> Result<(), UrdfError> {
    let leader = |j: &Joint| j.mimic.as_ref().and_then(|m| index.get(&m.joint).copied());
    // The joints on a circle of mimics: each joint has one leader at most,
    // so a walk from each joint not yet seen finds them in one pass.
    let mut on_circle = vec![false; joints.len()];
    let mut state = vec![0u8; joints.len()]; // 0 not seen, 1 on this walk, 2 done
    let mut walk = Vec::new();
    for start in 0..joints.len() {
        let mut at = Some(start);
        while let Some(k) = at.filter(|&k| state[k] == 0) {
            state[k] = 1;
            walk.push(k);
            at = leader(&joints[k]);
        }
        if let Some(k) = at.filter(|&k| state[k] == 1) {
            let from = walk.iter().position(|&w| w == k).unwrap_or(0);
            for &w in &walk[from..] {
                on_circle[w] = true;
            }
        }
        for w in walk.drain(..) {
            state[w] = 2;
        }
    }
    for (k, j) in joints.iter().enumerate() {
        let Some(m) = &j.mimic else { continue };
        let Some(l) = leader(j) else {
            return Err(UrdfError::new(
                m.at,
                format!("`{}` mimics the joint `{}`, which does not exist", j.name, m.joint),
            ));
        };
        if !(j.kind.has_one_coordinate() && joints[l].kind.has_one_coordinate()) {
            return Err(UrdfError::new(
                m.at,
                format!("`{}` ({:?}) mimics `{}` ({:?})", j.name, j.kind, m.joint, joints[l].kind).to_lowercase(),
            )
            .help("a mimic couples two joints of one coordinate each: revolute, continuous or prismatic"));
        }
        if !(m.multiplier.is_finite() && m.offset.is_finite()) {
            return Err(UrdfError::new(
                m.at,
                format!("the mimic of `{}` has a multiplier or offset that is not a finite number", j.name),
            ));
        }
        if on_circle[k] {
            let mut chain = vec![j.name.as_str()];
            let mut at = l;
            while at != k {
                chain.push(joints[at].name.as_str());
                at = leader(&joints[at]).unwrap_or(k);
            }
            chain.push(j.name.as_str());
            return Err(UrdfError::new(
                m.at,
                format!("the mimic joints {} follow each other in a circle", chain.join(" -> ")),
            )
            .help("one joint of the chain must move on its own"));
        }
    }
    Ok(())
}

/// The joints of a loop, for the message: from a link not reached, up its
/// parents until one repeats.
fn loop_error(links: &[Link], joints: &[Joint], parent_joint: &[Option<usize>]) -> UrdfError {
    let mut seen = Vec::new();
    let mut seen_before = vec![false; joints.len()];
    let mut link = (0..links.len()).find(|&l| parent_joint[l].is_some()).unwrap_or(0);
    while let Some(j) = parent_joint[link] {
        if std::mem::replace(&mut seen_before[j], true) {
            let start = seen.iter().position(|&s| s == j).unwrap_or(0);
            let cycle: Vec<String> = seen[start..].iter().map(|&k: &usize| format!("`{}`", joints[k].name)).collect();
            return UrdfError::new(joints[j].at, format!("the joints {} form a loop", cycle.join(" → ")))
                .help("URDF describes trees: remove one joint of the loop and close it in a model file with a joint of the library");
        }
        seen.push(j);
        link = joints[j].parent;
    }
    UrdfError::new(links[0].at, "the links do not form a tree")
}

type PosOf<'a> = dyn Fn(roxmltree::Node) -> Pos + 'a;

fn read_link(node: roxmltree::Node, pos: &PosOf, skip: &mut dyn FnMut(&str, Pos)) -> Result<Link, UrdfError> {
    let name = required(node, "name", pos)?.to_string();
    let mut link = Link { name, inertial: None, visuals: Vec::new(), at: pos(node) };
    for child in node.children().filter(|n| n.is_element()) {
        match child.tag_name().name() {
            "inertial" => link.inertial = Some(read_inertial(child, pos)?),
            "visual" => {
                if let Some(v) = read_visual(child, pos, skip)? {
                    link.visuals.push(v);
                }
            }
            "collision" => skip("collision", pos(child)),
            other => skip(other, pos(child)),
        }
    }
    Ok(link)
}

fn read_inertial(node: roxmltree::Node, pos: &PosOf) -> Result<Inertial, UrdfError> {
    let origin = read_origin(node, pos)?;
    let mass_node = element(node, "mass")
        .ok_or_else(|| UrdfError::new(pos(node), "`<inertial>` without `<mass value=\"...\"/>`"))?;
    let mass = number(mass_node, "value", pos)?;
    if mass < 0.0 {
        return Err(
            UrdfError::new(pos(mass_node), format!("a negative mass ({mass} kg)")).help("masses are 0 or positive")
        );
    }
    let i =
        element(node, "inertia").ok_or_else(|| UrdfError::new(pos(node), "`<inertial>` without `<inertia .../>`"))?;
    let mut inertia = [0.0; 6];
    for (k, key) in ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"].iter().enumerate() {
        inertia[k] = number(i, key, pos)?;
    }
    let at = pos(i);
    let [xx, xy, xz, yy, yz, zz] = inertia;
    // Positive semi-definite, and the triangle inequalities of a real body.
    let principal_minors =
        [xx, xx * yy - xy * xy, xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz)];
    // Rounding in the file (-5e-20 for a zero) is not a negative inertia.
    let size = (xx.abs() + yy.abs() + zz.abs()).max(1e-9);
    let tol = [1e-9 * size, 1e-9 * size * size, 1e-9 * size * size * size];
    if principal_minors.iter().zip(tol).any(|(&m, t)| m < -t) || [xx, yy, zz].iter().any(|&d| d < -1e-9 * size) {
        return Err(UrdfError::new(
            at,
            format!("the inertia (ixx {xx}, ixy {xy}, ixz {xz}, iyy {yy}, iyz {yz}, izz {zz}) is not positive semi-definite"),
        )
        .help("no rigid body has this inertia: check the signs of the products of inertia"));
    }
    Ok(Inertial { origin, mass, inertia, at: pos(node) })
}

fn read_visual(
    node: roxmltree::Node,
    pos: &PosOf,
    skip: &mut dyn FnMut(&str, Pos),
) -> Result<Option<Visual>, UrdfError> {
    let origin = read_origin(node, pos)?;
    let Some(geometry) = element(node, "geometry") else {
        return Err(UrdfError::new(pos(node), "`<visual>` without `<geometry>`"));
    };
    let Some(shape) = geometry.children().find(|n| n.is_element()) else {
        return Err(UrdfError::new(pos(geometry), "`<geometry>` without a shape (box, cylinder, sphere or mesh)"));
    };
    let geometry = match shape.tag_name().name() {
        "box" => Geometry::Box { size: vector(shape, "size", pos)?.ok_or_else(|| missing(shape, "size", pos))? },
        "cylinder" => {
            Geometry::Cylinder { radius: number(shape, "radius", pos)?, length: number(shape, "length", pos)? }
        }
        "sphere" => Geometry::Sphere { radius: number(shape, "radius", pos)? },
        "mesh" => Geometry::Mesh {
            filename: required(shape, "filename", pos)?.to_string(),
            scale: vector(shape, "scale", pos)?.unwrap_or([1.0; 3]),
            path: None,
            at: pos(shape),
        },
        other => {
            skip(other, pos(shape));
            return Ok(None);
        }
    };
    let (material, color) = match element(node, "material") {
        Some(m) => read_material(m, pos)?,
        None => (None, None),
    };
    Ok(Some(Visual { origin, geometry, color, material, at: pos(node) }))
}

fn read_joint(
    node: roxmltree::Node,
    links: &[Link],
    link_index: &HashMap<String, usize>,
    pos: &PosOf,
    skip: &mut dyn FnMut(&str, Pos),
) -> Result<Joint, UrdfError> {
    let name = required(node, "name", pos)?.to_string();
    let kind = match required(node, "type", pos)? {
        "revolute" => JointKind::Revolute,
        "continuous" => JointKind::Continuous,
        "prismatic" => JointKind::Prismatic,
        "fixed" => JointKind::Fixed,
        "floating" => JointKind::Floating,
        "planar" => JointKind::Planar,
        other => {
            return Err(UrdfError::new(pos(node), format!("the joint `{name}` has the type `{other}`"))
                .help("URDF's joint types are revolute, continuous, prismatic, fixed, floating and planar"))
        }
    };
    let link_of = |tag: &str| -> Result<usize, UrdfError> {
        let e = element(node, tag)
            .ok_or_else(|| UrdfError::new(pos(node), format!("the joint `{name}` has no `<{tag} link=\"...\"/>`")))?;
        let wanted = required(e, "link", pos)?;
        link_index.get(wanted).copied().ok_or_else(|| {
            let hint = crate::diagnostics::did_you_mean(wanted, links.iter().map(|l| l.name.as_str()));
            let mut err = UrdfError::new(
                pos(e),
                format!("the joint `{name}` names the {tag} link `{wanted}`, which does not exist"),
            );
            if let Some(h) = hint {
                err = err.help(h);
            }
            err
        })
    };
    let (parent, child) = (link_of("parent")?, link_of("child")?);
    if parent == child {
        return Err(UrdfError::new(
            pos(node),
            format!("the joint `{name}` joins the link `{}` to itself", links[parent].name),
        ));
    }
    let origin = read_origin(node, pos)?;
    let mut axis = [1.0, 0.0, 0.0];
    if let Some(a) = element(node, "axis") {
        axis = vector(a, "xyz", pos)?.unwrap_or(axis);
        let norm = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm <= 1e-12 && (kind.has_one_coordinate() || kind == JointKind::Planar) {
            return Err(UrdfError::new(pos(a), format!("the axis of `{name}` is zero")));
        }
        if norm > 1e-12 {
            axis = axis.map(|x| x / norm);
        }
    }
    let mut joint = Joint {
        name,
        kind,
        parent,
        child,
        origin,
        axis,
        limits: None,
        damping: 0.0,
        friction: 0.0,
        mimic: None,
        at: pos(node),
    };
    for e in node.children().filter(|n| n.is_element()) {
        match e.tag_name().name() {
            "origin" | "axis" | "parent" | "child" => {}
            "limit" => {
                skip("limit", pos(e));
                let lower = optional_number(e, "lower", pos)?.unwrap_or(0.0);
                let upper = optional_number(e, "upper", pos)?.unwrap_or(0.0);
                joint.limits = Some((lower, upper));
            }
            "dynamics" => {
                joint.damping = optional_number(e, "damping", pos)?.unwrap_or(0.0);
                joint.friction = optional_number(e, "friction", pos)?.unwrap_or(0.0);
                if joint.damping < 0.0 {
                    return Err(UrdfError::new(
                        pos(e),
                        format!("a negative damping ({}) on `{}`", joint.damping, joint.name),
                    ));
                }
                if joint.friction != 0.0 {
                    skip("dynamics friction", pos(e));
                }
                if joint.damping != 0.0 && joint.kind == JointKind::Fixed {
                    skip("dynamics damping of a fixed joint", pos(e));
                } else if joint.damping != 0.0 && !joint.kind.has_one_coordinate() {
                    skip("dynamics damping", pos(e));
                }
            }
            "mimic" => {
                joint.mimic = Some(Mimic {
                    joint: required(e, "joint", pos)?.to_string(),
                    multiplier: optional_number(e, "multiplier", pos)?.unwrap_or(1.0),
                    offset: optional_number(e, "offset", pos)?.unwrap_or(0.0),
                    at: pos(e),
                })
            }
            other => skip(other, pos(e)),
        }
    }
    Ok(joint)
}

fn element<'a, 'i>(node: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    node.children().find(|n| n.is_element() && n.tag_name().name() == tag)
}

fn required<'a>(node: roxmltree::Node<'a, '_>, key: &str, pos: &PosOf) -> Result<&'a str, UrdfError> {
    node.attribute(key).ok_or_else(|| missing(node, key, pos))
}

fn missing(node: roxmltree::Node, key: &str, pos: &PosOf) -> UrdfError {
    UrdfError::new(pos(node), format!("`<{}>` needs the attribute `{key}`", node.tag_name().name()))
}

fn parse_number(text: &str, node: roxmltree::Node, key: &str, pos: &PosOf) -> Result<f64, UrdfError> {
    let x: f64 = text.trim().parse().map_err(|_| {
        UrdfError::new(pos(node), format!("`{key}=\"{text}\"` of `<{}>` is not a number", node.tag_name().name()))
    })?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(UrdfError::new(pos(node), format!("`{key}=\"{text}\"` of `<{}>` is not finite", node.tag_name().name())))
    }
}

fn number(node: roxmltree::Node, key: &str, pos: &PosOf) -> Result<f64, UrdfError> {
    parse_number(required(node, key, pos)?, node, key, pos)
}

fn optional_number(node: roxmltree::Node, key: &str, pos: &PosOf) -> Result<Option<f64>, UrdfError> {
    node.attribute(key).map(|t| parse_number(t, node, key, pos)).transpose()
}

fn vector(node: roxmltree::Node, key: &str, pos: &PosOf) -> Result<Option<[f64; 3]>, UrdfError> {
    numbers(node, key, pos, "three")
}

/// `N` numbers separated by spaces (`words` says how many, for the message).
fn numbers<const N: usize>(
    node: roxmltree::Node,
    key: &str,
    pos: &PosOf,
    words: &str,
) -> Result<Option<[f64; N]>, UrdfError> {
    let Some(text) = node.attribute(key) else { return Ok(None) };
    let tag = node.tag_name().name();
    if text.contains(',') {
        let spaced = text.split(|c: char| c == ',' || c.is_whitespace()).filter(|p| !p.is_empty()).collect::<Vec<_>>();
        return Err(UrdfError::new(
            pos(node),
            format!(
                "`{key}=\"{text}\"` of `<{tag}>` separates its numbers with commas; URDF separates them with \
                 spaces: `{key}=\"{}\"`",
                spaced.join(" ")
            ),
        ));
    }
    let parts: Vec<&str> = text.split_whitespace().collect();
    if parts.len() != N {
        return Err(UrdfError::new(pos(node), format!("`{key}=\"{text}\"` of `<{tag}>` needs {words} numbers")));
    }
    let mut v = [0.0; N];
    for (k, p) in parts.iter().enumerate() {
        // The whole attribute in the message, not only the piece.
        v[k] = parse_number(p, node, key, pos).map_err(|_| {
            UrdfError::new(pos(node), format!("`{key}=\"{text}\"` of `<{tag}>`: `{p}` is not a finite number"))
        })?;
    }
    Ok(Some(v))
}

/// A `<material>`'s name and its `<color rgba>`, if it has one.
fn read_material(node: roxmltree::Node, pos: &PosOf) -> Result<(Option<String>, Option<[f64; 4]>), UrdfError> {
    let color = match element(node, "color") {
        Some(c) => numbers(c, "rgba", pos, "four")?,
        None => None,
    };
    Ok((node.attribute("name").map(str::to_string), color))
}

fn read_origin(node: roxmltree::Node, pos: &PosOf) -> Result<Origin, UrdfError> {
    let Some(o) = element(node, "origin") else { return Ok(Origin::default()) };
    Ok(Origin { xyz: vector(o, "xyz", pos)?.unwrap_or([0.0; 3]), rpy: vector(o, "rpy", pos)?.unwrap_or([0.0; 3]) })
}

/// Where mesh files are looked for: the URDF file's folder, and folders
/// that hold ROS packages (`--package-dir`, `ROS_PACKAGE_PATH`).
#[derive(Clone, Debug, Default)]
pub struct MeshSearch {
    pub urdf_folder: PathBuf,
    pub package_dirs: Vec<PathBuf>,
}

/// A mesh that was not found: its place, its name as written, and the
/// places looked at.
#[derive(Clone, Debug)]
pub struct MissingMesh {
    pub at: Pos,
    pub filename: String,
    pub looked: Vec<PathBuf>,
    /// Why the name is not looked for at all (it leaves its package).
    pub refused: Option<&'static str>,
    /// What the path found names when it is not a regular file (a FIFO, a
    /// folder, a device): it was found, but is no mesh to read.
    pub not_a_file: Option<multibody::files::Kind>,
}

impl MissingMesh {
    /// `file:line:col: {severity}: the mesh ... is not found (looked for ...)`.
    pub fn render(&self, file: &str, severity: &str) -> String {
        if let Some(why) = self.refused {
            let (line, col, name) = (self.at.line, self.at.col, &self.filename);
            return format!("{file}:{line}:{col}: {severity}: the mesh `{name}` is not read: {why}");
        }
        if let (Some(kind), Some(path)) = (self.not_a_file, self.looked.first()) {
            let (line, col, name) = (self.at.line, self.at.col, &self.filename);
            return format!(
                "{file}:{line}:{col}: {severity}: the mesh `{name}` is not read: {} is {}, not a regular file; \
                 give the path of a mesh file",
                path.display(),
                kind.describe()
            );
        }
        let mut looked: Vec<String> = self.looked.iter().take(3).map(|p| p.display().to_string()).collect();
        if self.looked.len() > 3 {
            looked.push(format!("{} more places", self.looked.len() - 3));
        }
        format!(
            "{file}:{}:{}: {severity}: the mesh `{}` is not found (looked for {})",
            self.at.line,
            self.at.col,
            self.filename,
            if looked.is_empty() { "nothing".into() } else { looked.join(", ") }
        )
    }
}

/// The folder of the ROS package `name`, seen from `search`: a package
/// folder given (or one inside it), or a folder above the URDF file named
/// `name` or whose `package.xml` names it.
fn package_folder(name: &str, search: &MeshSearch, looked: &mut Vec<PathBuf>) -> Option<PathBuf> {
    let names_package = |dir: &Path| {
        dir.file_name().is_some_and(|f| f == name)
            || std::fs::read_to_string(dir.join("package.xml")).is_ok_and(|x| {
                roxmltree::Document::parse(&x).is_ok_and(|d| {
                    d.root_element().children().any(|n| n.has_tag_name("name") && n.text().map(str::trim) == Some(name))
                })
            })
    };
    for dir in &search.package_dirs {
        if names_package(dir) {
            return Some(dir.clone());
        }
        looked.push(dir.join(name));
        if dir.join(name).is_dir() {
            return Some(dir.join(name));
        }
    }
    let start = std::fs::canonicalize(&search.urdf_folder).unwrap_or_else(|_| search.urdf_folder.clone());
    for dir in start.ancestors() {
        if names_package(dir) {
            return Some(dir.to_path_buf());
        }
        looked.push(dir.join(name));
        if dir.join(name).is_dir() {
            return Some(dir.join(name));
        }
    }
    None
}

/// Finds every mesh file of the robot (`path` of each mesh); the ones not
/// found are returned, and keep no path.
pub fn resolve_meshes(robot: &mut Robot, search: &MeshSearch) -> Vec<MissingMesh> {
    let mut missing = Vec::new();
    for visual in robot.links.iter_mut().flat_map(|l| l.visuals.iter_mut()) {
        let Geometry::Mesh { filename, path, at, .. } = &mut visual.geometry else { continue };
        let mut looked = Vec::new();
        let candidate = if let Some(rest) = filename.strip_prefix("package://") {
            let (package, inside) = rest.split_once('/').unwrap_or((rest, ""));
            // `package://../../etc/passwd` would climb out of any package.
            let leaves = |p: &str| p.split(['/', '\\']).any(|part| part == "..") || Path::new(p).is_absolute();
            if package.is_empty() || package == "." || leaves(package) || leaves(inside) {
                let why = "a `package://NAME/...` path names a file inside the package NAME, and `..` or an \
                           absolute path would leave it; write the package's name and the path inside it";
                missing.push(MissingMesh {
                    at: *at,
                    filename: filename.clone(),
                    looked,
                    refused: Some(why),
                    not_a_file: None,
                });
                continue;
            }
            package_folder(package, search, &mut looked).map(|dir| dir.join(inside))
        } else if let Some(absolute) = filename.strip_prefix("file://") {
            Some(PathBuf::from(absolute))
        } else {
            Some(search.urdf_folder.join(&*filename))
        };
        match candidate {
            Some(file) if file.is_file() => *path = Some(file),
            Some(file) => {
                // A FIFO or a folder there is found, but no mesh: said so, not "not found".
                let not_a_file = std::fs::metadata(&file).ok().and_then(|m| multibody::files::Kind::of(&m));
                looked.clear();
                looked.push(file);
                missing.push(MissingMesh { at: *at, filename: filename.clone(), looked, refused: None, not_a_file });
            }
            None => missing.push(MissingMesh {
                at: *at,
                filename: filename.clone(),
                looked,
                refused: None,
                not_a_file: None,
            }),
        }
    }
    missing
}

/// `path` relative to the folder `from` (both made absolute), for a model
/// file that names its meshes from where it is.
pub fn relative_path(path: &Path, from: &Path) -> PathBuf {
    let absolute = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| std::path::absolute(p).unwrap_or(p.into()));
    let (path, from) = (absolute(path), absolute(from));
    let common = path.components().zip(from.components()).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return path;
    }
    let mut out = PathBuf::new();
    for _ in from.components().skip(common) {
        out.push("..");
    }
    out.extend(path.components().skip(common));
    out
}

/// How a robot is imported.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    /// The root link moves freely (a floating base) instead of being fixed
    /// to the world.
    pub floating: bool,
    /// Joint damping (`<dynamics damping>`) as a damper on the joint's axis;
    /// without it, the dynamics Pinocchio computes (it leaves damping out).
    pub damping: bool,
    /// Mimic joints as couplings of their axes; without it, each moves on
    /// its own (as in Pinocchio's dynamics unless asked otherwise).
    pub mimic: bool,
    /// The folder the model file will be in: mesh files are named from
    /// there (absolute paths without it).
    pub mesh_base: Option<PathBuf>,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions { floating: false, damping: true, mimic: true, mesh_base: None }
    }
}

/// A unit vector perpendicular to `axis`: the plane's x of a planar joint
/// (x itself for the axis z, as Pinocchio's planar joint has it).
fn in_plane(axis: [f64; 3]) -> [f64; 3] {
    let k = (0..3).min_by(|&a, &b| axis[a].abs().total_cmp(&axis[b].abs())).unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let d = axis[k];
    let v = [e[0] - d * axis[0], e[1] - d * axis[1], e[2] - d * axis[2]];
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.map(|x| x / norm)
}

/// A Dyad string literal.
fn quoted(text: &str) -> String {
    format!("\"{}\"", text.replace('\\', "\\\\").replace('"', "\\\""))
}

type Mat = [[f64; 3]; 3];

/// `R = Rz(yaw) Ry(pitch) Rx(roll)`: the child frame's axes in the parent's.
pub fn rpy_matrix([r, p, y]: [f64; 3]) -> Mat {
    let (sr, cr, sp, cp, sy, cy) = (r.sin(), r.cos(), p.sin(), p.cos(), y.sin(), y.cos());
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// The axis and angle of a rotation matrix (`angle` in [0, pi]).
pub fn axis_angle(m: &Mat) -> ([f64; 3], f64) {
    let trace = m[0][0] + m[1][1] + m[2][2];
    let cos = ((trace - 1.0) / 2.0).clamp(-1.0, 1.0);
    let skew = [m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]];
    let sin2 = (skew[0] * skew[0] + skew[1] * skew[1] + skew[2] * skew[2]).sqrt();
    let angle = sin2.atan2(trace - 1.0);
    if angle < 1e-12 {
        return ([1.0, 0.0, 0.0], 0.0);
    }
    if cos > -0.99 {
        return (skew.map(|x| x / sin2), angle);
    }
    // Near a half turn: the axis from the symmetric part, its sign from the
    // skew part.
    let k = (0..3).max_by(|&a, &b| m[a][a].total_cmp(&m[b][b])).unwrap_or(0);
    let mut n = [0.0; 3];
    n[k] = ((m[k][k] - cos) / (1.0 - cos)).max(0.0).sqrt();
    for i in (0..3).filter(|&i| i != k) {
        n[i] = (m[i][k] + m[k][i]) / (2.0 * (1.0 - cos) * n[k]);
    }
    let dot = n[0] * skew[0] + n[1] * skew[1] + n[2] * skew[2];
    if dot < 0.0 {
        n = n.map(|x| -x);
    }
    let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    (n.map(|x| x / norm), angle)
}

fn mat_vec(m: &Mat, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// `R I R'`: an inertia given in a rotated frame, in the link frame.
fn rotate_inertia(m: &Mat, [xx, xy, xz, yy, yz, zz]: [f64; 6]) -> Mat {
    let i = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
    let mut out = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            out[a][b] =
                (0..3).flat_map(|c| (0..3).map(move |d| (c, d))).map(|(c, d)| m[a][c] * i[c][d] * m[b][d]).sum();
        }
    }
    out
}

/// Words a component may not be named.
const RESERVED: &[&str] = &[
    "analysis",
    "and",
    "component",
    "connect",
    "connector",
    "constant",
    "der",
    "each",
    "else",
    "elseif",
    "end",
    "enum",
    "example",
    "extends",
    "false",
    "final",
    "for",
    "function",
    "if",
    "in",
    "initial",
    "input",
    "model",
    "not",
    "or",
    "output",
    "parameter",
    "partial",
    "potential",
    "flow",
    "relations",
    "struct",
    "then",
    "time",
    "true",
    "type",
    "variable",
    "when",
    "world",
    "pi",
];

/// A Dyad identifier for each name, unique, as close to it as can be.
fn identifiers<'a>(names: impl Iterator<Item = (&'a str, &'static str)>) -> Vec<String> {
    let mut ids: Vec<String> = Vec::new();
    let mut used: HashSet<String> = HashSet::new();
    for (name, kind) in names {
        let mut id: String =
            name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
        if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
            id.insert(0, '_');
        }
        if RESERVED.contains(&id.as_str()) {
            id.push('_');
        }
        let base = id.clone();
        if used.contains(&id) {
            id = format!("{base}_{kind}");
        }
        let mut k = 2;
        while used.contains(&id) {
            id = format!("{base}_{kind}{k}");
            k += 1;
        }
        used.insert(id.clone());
        ids.push(id);
    }
    ids
}

fn num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:?}")
    }
}

fn vec3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

/// A Dyad type name from the robot's name.
fn type_name(name: &str) -> String {
    let mut out = String::new();
    let mut upper = true;
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(if upper { c.to_ascii_uppercase() } else { c });
            upper = false;
        } else {
            upper = true;
        }
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert(0, 'R');
    }
    out
}

/// The component names of the links and of the joints: the URDF's names
/// made Dyad identifiers (`left elbow` is `left_elbow`), unique (a joint
/// named as a link gets `_joint`).
pub fn dyad_names(robot: &Robot) -> (Vec<String>, Vec<String>) {
    let all = identifiers(
        robot
            .links
            .iter()
            .map(|l| (l.name.as_str(), "link"))
            .chain(robot.joints.iter().map(|j| (j.name.as_str(), "joint"))),
    );
    let joints = all[robot.links.len()..].to_vec();
    let mut links = all;
    links.truncate(robot.links.len());
    (links, joints)
}

/// The robot as a Dyad model file: a component named after the robot, of
/// the World (gravity along -z), a `Body` per link with mass, a joint
/// component per joint (named as in the URDF), the visuals as shapes, a
/// damper per damped joint, and an analysis that simulates it.
pub fn to_dyad(robot: &Robot, file: &str, options: &ImportOptions) -> String {
    let (link_ids, joint_ids) = dyad_names(robot);
    let ty = type_name(&robot.name);
    let mut declarations: Vec<String> = Vec::new();
    let mut relations: Vec<String> = Vec::new();
    // The connectors at each link's frame.
    let mut at_link: Vec<Vec<String>> = vec![Vec::new(); robot.links.len()];
    let mut used = link_ids.iter().chain(&joint_ids).cloned().collect::<HashSet<_>>();
    let mut fresh = |base: String| {
        let mut id = base.clone();
        let mut k = 2;
        while used.contains(&id) {
            id = format!("{base}{k}");
            k += 1;
        }
        used.insert(id.clone());
        id
    };
    let joint_index: HashMap<&str, usize> =
        robot.joints.iter().enumerate().rev().map(|(k, j)| (j.name.as_str(), k)).collect();
    declarations.push("  world = MultibodyComponents.World(n = [0, 0, -1])".into());
    for (l, link) in robot.links.iter().enumerate() {
        let id = &link_ids[l];
        let massive = link.inertial.as_ref().is_some_and(|i| i.mass > 0.0 || i.inertia.iter().any(|&x| x != 0.0));
        if let Some(inertial) = link.inertial.as_ref().filter(|_| massive) {
            let r = rpy_matrix(inertial.origin.rpy);
            // Rounding in the file (-5e-20 for a zero) is not an inertia.
            let i = rotate_inertia(&r, inertial.inertia).map(|row| row.map(|x| if x.abs() < 1e-15 { 0.0 } else { x }));
            let floating = options.floating && l == robot.root;
            let state = if floating { "orientation_state = OrientationState.Quaternion(), " } else { "" };
            let render = if link.visuals.is_empty() { "" } else { "render = false, " };
            declarations.push(format!(
                "  \"Link `{}` (line {})\"\n  {id} = MultibodyComponents.Body({state}{render}m = {}, r_cm = {}, I_11 = {}, I_22 = {}, \
                 I_33 = {}, I_21 = {}, I_31 = {}, I_32 = {})",
                link.name,
                link.at.line,
                num(inertial.mass),
                vec3(inertial.origin.xyz),
                num(i[0][0]),
                num(i[1][1]),
                num(i[2][2]),
                num(i[1][0]),
                num(i[2][0]),
                num(i[2][1])
            ));
            at_link[l].push(format!("{id}.frame_a"));
        } else if options.floating && l == robot.root {
            // The floating base's free motion belongs to a Body: a massless
            // root gets one without mass (the links fixed to it carry it).
            declarations.push(format!(
                "  \"Link `{}` (line {}): no mass, the floating base\"\n  {id} = MultibodyComponents.Body(orientation_state = \
                 OrientationState.Quaternion(), m = 0, r_cm = [0, 0, 0], I_11 = 0, I_22 = 0, I_33 = 0)",
                link.name, link.at.line
            ));
            at_link[l].push(format!("{id}.frame_a"));
        } else {
            // A link without mass is a frame: named, so that its pose and
            // signals can be asked for by the link's name.
            declarations.push(format!(
                "  \"Link `{}` (line {}): no mass, a frame\"\n  {id} = MultibodyComponents.FixedTranslation(r = [0, 0, 0])",
                link.name, link.at.line
            ));
            at_link[l].push(format!("{id}.frame_a"));
        }
        for (k, visual) in link.visuals.iter().enumerate() {
            let r = rpy_matrix(visual.origin.rpy);
            let (ex, ey, ez) =
                (mat_vec(&r, [1.0, 0.0, 0.0]), mat_vec(&r, [0.0, 1.0, 0.0]), mat_vec(&r, [0.0, 0.0, 1.0]));
            let c = visual.origin.xyz;
            let shift = |dir: [f64; 3], by: f64| [c[0] - by * dir[0], c[1] - by * dir[1], c[2] - by * dir[2]];
            let shape = match &visual.geometry {
                Geometry::Box { size } => format!(
                    "BoxShape(r_shape = {}, length_direction = {}, width_direction = {}, length = {}, width = {}, height = {})",
                    vec3(shift(ex, size[0] / 2.0)),
                    vec3(ex),
                    vec3(ey),
                    num(size[0]),
                    num(size[1]),
                    num(size[2])
                ),
                Geometry::Cylinder { radius, length } => format!(
                    "CylinderShape(r_shape = {}, length_direction = {}, width_direction = {}, length = {}, width = {}, height = {})",
                    vec3(shift(ez, length / 2.0)),
                    vec3(ez),
                    vec3(ex),
                    num(*length),
                    num(2.0 * radius),
                    num(2.0 * radius)
                ),
                Geometry::Sphere { radius } => format!(
                    "SphereShape(r_shape = {}, length = {}, width = {}, height = {})",
                    vec3(c),
                    num(2.0 * radius),
                    num(2.0 * radius),
                    num(2.0 * radius)
                ),
                Geometry::Mesh { path: None, .. } => continue,
                Geometry::Mesh { path: Some(path), scale, .. } => {
                    let file = match &options.mesh_base {
                        Some(base) => relative_path(path, base),
                        None => path.clone(),
                    };
                    // The mesh's scale (per axis) goes into the transform.
                    let row = |i: usize| {
                        format!(
                            "[{}, {}, {}, {}]",
                            num(r[i][0] * scale[0]),
                            num(r[i][1] * scale[1]),
                            num(r[i][2] * scale[2]),
                            num(c[i])
                        )
                    };
                    format!(
                        "ShapefileVisualizer(shapefile = {}, shape_transform = [{}, {}, {}, [0, 0, 0, 1]])",
                        quoted(&file.to_string_lossy()),
                        row(0),
                        row(1),
                        row(2)
                    )
                }
            };
            let shape = match visual.color {
                Some([r, g, b, a]) => {
                    format!("{}, color = [{}, {}, {}, {}])", &shape[..shape.len() - 1], num(r), num(g), num(b), num(a))
                }
                None => shape,
            };
            let name = fresh(format!(
                "{id}_visual{}",
                if link.visuals.len() > 1 { (k + 1).to_string() } else { String::new() }
            ));
            declarations.push(format!("  {name} = MultibodyComponents.{shape}"));
            at_link[l].push(format!("{name}.frame_a"));
        }
    }
    for (j, joint) in robot.joints.iter().enumerate() {
        let id = &joint_ids[j];
        let (n, angle) = axis_angle(&rpy_matrix(joint.origin.rpy));
        let r = vec3(joint.origin.xyz);
        let origin =
            if angle == 0.0 { format!("r = {r}") } else { format!("r = {r}, n = {}, angle = {}", vec3(n), num(angle)) };
        let note = format!("  \"Joint `{}` ({:?}, line {})\"\n", joint.name, joint.kind, joint.at.line)
            .replace("Continuous", "continuous");
        // A mimic's follower starts where its leader puts it.
        let mimic = joint.mimic.as_ref().filter(|_| options.mimic);
        let start = if mimic.is_some() { "guess" } else { "initial" };
        let component = match joint.kind {
            JointKind::Revolute | JointKind::Continuous => {
                format!("URDFRevolute({origin}, joint_n = {}, phi({start} = 0), w({start} = 0))", vec3(joint.axis))
            }
            JointKind::Prismatic => {
                format!("URDFPrismatic({origin}, joint_n = {}, s({start} = 0), v({start} = 0))", vec3(joint.axis))
            }
            JointKind::Fixed => {
                if angle == 0.0 {
                    format!("FixedTranslation(r = {r})")
                } else {
                    format!("FixedRotation({origin})")
                }
            }
            JointKind::Planar => {
                format!("Planar(n = {}, n_x = {})", vec3(joint.axis), vec3(in_plane(joint.axis)))
            }
            JointKind::Floating => "FreeMotion(orientation_state = OrientationState.Quaternion())".into(),
        };
        declarations.push(format!("{note}  {id} = MultibodyComponents.{component}"));
        if matches!(joint.kind, JointKind::Planar | JointKind::Floating) {
            // These library joints have no origin of their own: a fixed
            // part before them carries it.
            let placed = fresh(format!("{id}_origin"));
            let part =
                if angle == 0.0 { format!("FixedTranslation(r = {r})") } else { format!("FixedRotation({origin})") };
            declarations.push(format!("  {placed} = MultibodyComponents.{part}"));
            at_link[joint.parent].push(format!("{placed}.frame_a"));
            relations.push(format!("  connect({placed}.frame_b, {id}.frame_a)"));
        } else {
            at_link[joint.parent].push(format!("{id}.frame_a"));
        }
        at_link[joint.child].push(format!("{id}.frame_b"));
        if let Some(m) = mimic {
            let leader = joint_index[m.joint.as_str()];
            let coordinate = |kind: JointKind| if kind == JointKind::Prismatic { "s" } else { "phi" };
            relations.push(format!(
                "  \"Mimic (line {}): `{}` = {} * `{}` + {}\"\n  {id}.axis.{} = {} * {}.axis.{} + {}",
                m.at.line,
                joint.name,
                num(m.multiplier),
                m.joint,
                num(m.offset),
                coordinate(joint.kind),
                num(m.multiplier),
                joint_ids[leader],
                coordinate(robot.joints[leader].kind),
                num(m.offset)
            ));
        }
        if joint.damping > 0.0 && options.damping {
            let damper = fresh(format!("{id}_damping"));
            let (lib, a, b) = match joint.kind {
                JointKind::Prismatic => ("TranslationalComponents", "flange_a", "flange_b"),
                _ => ("RotationalComponents", "spline_a", "spline_b"),
            };
            if joint.kind.has_one_coordinate() {
                declarations.push(format!("  {damper} = {lib}.Damper(d = {})", num(joint.damping)));
                relations.push(format!("  connect({damper}.{a}, {id}.support)"));
                relations.push(format!("  connect({damper}.{b}, {id}.axis)"));
            }
        }
    }
    if !options.floating {
        at_link[robot.root].insert(0, "world.frame_b".into());
    }
    debug_assert_eq!(declarations.len(), component_count(robot, options), "one declaration per component");
    let mut connects: Vec<String> = Vec::new();
    // A link with one connector (a floating root alone) needs no connect.
    for connectors in at_link.iter().filter(|c| c.len() >= 2) {
        connects.push(format!("  connect({})", connectors.join(", ")));
    }
    connects.extend(relations);
    let mut out = String::new();
    let moving = robot.joints.iter().filter(|j| !matches!(j.kind, JointKind::Fixed)).count();
    let _ = writeln!(
        out,
        "\"\"\"\n# {}\n\nImported from `{file}` by `multibody import`: {} links, {} joints ({moving} that move), \
         {} base. URDF is z-up: the World's gravity points along -z.\n\"\"\"",
        robot.name,
        robot.links.len(),
        robot.joints.len(),
        if options.floating { "a floating" } else { "a fixed" }
    );
    let _ = writeln!(out, "component {ty}");
    for d in &declarations {
        let _ = writeln!(out, "{d}");
    }
    let _ = writeln!(out, "relations");
    for c in &connects {
        let _ = writeln!(out, "{c}");
    }
    let _ = writeln!(out, "end\n");
    let _ = writeln!(out, "\"Five seconds, saved every 10 ms.\"\nanalysis {ty}Simulation\n  extends TransientAnalysis(stop = 5, saveat = 0.01)\n  model = {ty}()\nend");
    out
}

/// What leaving out an element of this tag does, for the note.
pub fn skipped_effect(tag: &str) -> &'static str {
    match tag {
        "collision" => "collision geometry is not used (no contacts)",
        "transmission" | "gazebo" => "simulator and controller settings are not used",
        "safety_controller" | "calibration" => "controller settings are not used",
        "dynamics friction" => "joint friction is not applied (damping is)",
        "dynamics damping" => "the damping of planar and floating joints is not applied",
        "dynamics damping of a fixed joint" => "a fixed joint does not move, so its damping has no effect",
        "mimic" => "a mimic on a fixed joint has no effect",
        "limit" => "limits are not enforced (nor are they in Pinocchio's dynamics)",
        _ => "not part of the model",
    }
}
